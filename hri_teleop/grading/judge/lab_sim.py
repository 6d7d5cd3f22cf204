"""The grader's simulated lab for a student's teleoperation node (Ex. 10's drive, Ex. 12-13's launch).

The lab's own ``lab_sim`` (trusted) stands in for the arm, the hand and the board; a scripted
virtual pad drives the student's node on the grader's clock.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, Union

from hri_teleop.core.config import ConfigError, load_teleop_config
from hri_teleop.core.teleop import TeleopParams
from hri_teleop.grading.run.standins import BOARD_TOPIC
from hri_teleop.grading.run.workspace import REPO

__all__ = ["scripted_pad_launch", "lab_sim_argv", "lab_rate_hz"]

PathLike = Union[str, Path]


def scripted_pad_launch(node: str, scenario: PathLike) -> str:
    """The parameter launch file that gives the teleoperation ``node`` the grader's scripted virtual pad."""
    return ("<launch>\n  <!-- hri-grade: no gamepad here; the teleoperation node gets a scripted virtual pad -->\n"
            + "".join(f'  <param name="{node}/{k}" type="string" value="{v}"/>\n'
                      for k, v in (("pad", "virtual"), ("layout", "dualshock4"), ("pad_script", scenario)))
            + "</launch>\n")


def lab_sim_argv(scenario: PathLike) -> List[str]:
    """The grader's lab_sim (the lab's, trusted) with ``scenario``'s world, its board on the stand-in's topic."""
    return [str(REPO / "hri_lab" / "scripts" / "lab_sim.py"), "__name:=lab_sim",
            f"_config:={REPO / 'hri_lab' / 'config' / 'sim.yaml'}", f"_scenario:={scenario}",
            f"/pub_force:={BOARD_TOPIC}"]


def lab_rate_hz() -> float:
    """The teleoperation node's loop rate when the launch file sets none: the lab's teleop.yaml."""
    path = REPO / "hri_lab" / "config" / "teleop.yaml"
    try:
        return load_teleop_config(path).params.rate_hz if path.is_file() else TeleopParams().rate_hz
    except ConfigError:
        return TeleopParams().rate_hz
