"""``python -m hri_teleop.ros.lab_twin``: ``make lab-twin`` (hri_teleop.ros.lab_twin.cli)."""

from __future__ import annotations

import sys

from hri_teleop.ros.lab_twin.cli import main

sys.exit(main())
