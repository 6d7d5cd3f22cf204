"""The simulated lab in lock step, for the notebooks of Ex. 11 and 14: no ROS, faster than real time.

``run_lab(pad script, world)`` runs the teleoperation node's rules, the Franka, the hand with
the FSR attachment and the board on one clock and returns the record that ``summarize`` and
``timeline`` read; ``simulate_study`` runs a whole counterbalanced study.
"""

from __future__ import annotations

from typing import Sequence, Tuple

from hri_teleop.core.paths import SCENARIOS
from hri_teleop.core.run_record import format_summary, summarize
from hri_teleop.core.teleop import TeleopParams
from hri_teleop.plots.common import lab_timeline as timeline
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.study import simulate_study
from hri_teleop.sim.virtual_pad import parse_script
from hri_teleop.sim.world import WorldConfig

__all__ = ["run_lab", "parse_script", "WorldConfig", "OBJECTS", "SCENARIOS", "TeleopParams",
           "summarize", "format_summary", "timeline", "simulate_study", "describe_samples"]


def describe_samples(series: Sequence[Tuple[float, float]], what: str = "count", unit: str = "", last: int = 5) -> str:
    """A record's series in one line, rounded, with units: '351 samples (time_s, count); the last 5:
    t = 3.42 s: 701, ...' (a whole number as one, anything else to 3 significant digits)."""
    def value(v: float) -> str:
        text = f"{v:.0f}" if float(v).is_integer() else f"{v:.3g}"
        return f"{text} {unit}" if unit else text

    tail = ", ".join(f"t = {t:.2f} s: {value(v)}" for t, v in series[-last:])
    return f"{len(series)} samples (time_s, {what}); the last {min(last, len(series))}: {tail}"
