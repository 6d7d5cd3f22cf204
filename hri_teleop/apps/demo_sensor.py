"""``make demo-sensor``: sensor.launch (handout Ex. 6) with the simulated press profile, recorded and checked.

    python -m hri_teleop.apps.demo_sensor [--duration 5] [--max-sensor-force 700] [--rate 50]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

from hri_teleop.core.config import lab_max_sensor_force
from hri_teleop.ros.master import run_reporting
from hri_teleop.ros.sensor_demo import run


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=5.0, help="recording time, s")
    parser.add_argument("--max-sensor-force", type=int, default=lab_max_sensor_force(),
                        help="/max_sensor_force, ADC counts (default: hri_lab/config/calibration.yaml)")
    parser.add_argument("--rate", type=float, default=50.0, help="FSR_sensor.py publish rate, Hz")
    parser.add_argument("--press-max", type=int, default=800,
                        help="top count of a simulated press; above --max-sensor-force shows the clipping")
    parser.add_argument("--out", type=Path, default=Path("out"), help="folder for the bag and the plot")
    args = parser.parse_args(argv)
    return run_reporting(lambda: run(args.duration, args.max_sensor_force, args.rate, args.out, args.press_max), "demo")


if __name__ == "__main__":
    sys.exit(main())
