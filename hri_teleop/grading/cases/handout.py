"""Handout Table 1: the robot parameters Ex. 3 sets by hand, Ex. 4 writes in robot_params.yaml and Ex. 7 loads.

Three exercises judge against it, so it lives here, below them all.
"""

from __future__ import annotations

from typing import Any, Dict

__all__ = ["TABLE_1"]

#: Table 1 of the handout: name -> value (with the Python type YAML gives it).
TABLE_1: Dict[str, Any] = {
    "robot_name": "FER",
    "robot_number": 1,
    "robot_mass": 18.0,
    "load_gripper": True,
    "mixed_list": ["text", 1.0, 1],
    "gains": {"p": 10.0, "i": 1.0, "d": 5.0},
}
