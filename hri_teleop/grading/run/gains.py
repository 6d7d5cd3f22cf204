"""The gains a teleoperation case gives the student's Teleoperation class: plain data, no rule.

Here, not beside the cases (:mod:`hri_teleop.grading.cases.inputs`), because the probe that imports a student's
teleoperation.py reads them: that process must hold nothing of the reference rules a student's code could reach
(:mod:`hri_teleop.grading.run.student_guard`). The reference controller's parameters for them:
:func:`hri_teleop.grading.cases.inputs.reference_params`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict

__all__ = ["TeleopGains"]


@dataclass(frozen=True)
class TeleopGains:
    """The parameters of the student's Teleoperation class (its constructor's arguments)."""

    rate: float = 50.0
    k_trans: float = 0.1
    k_rot: float = 0.3
    k_gripper: float = 0.04
    deadzone: float = 0.1

    def as_dict(self) -> Dict[str, float]:
        return {"rate": self.rate, "k_trans": self.k_trans, "k_rot": self.k_rot,
                "k_gripper": self.k_gripper, "deadzone": self.deadzone}
