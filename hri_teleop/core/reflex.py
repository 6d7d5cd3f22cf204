"""A Franka reflex in plain words: which limit, where, and what the operator does next.

The robot names a reflex by libfranka's error flags; a student at home or in the lab needs the
cause and the next step. The simulated arm, the teleoperation node's log and the notebooks all
say it with these sentences.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Sequence

from hri_teleop.core.joints import (
    JOINT_ACCELERATION_DISCONTINUITY,
    JOINT_POSITION_LIMITS_VIOLATION,
    JOINT_VELOCITY_DISCONTINUITY,
    JOINT_VELOCITY_LIMITS_VIOLATION,
)
from hri_teleop.core.robot_file import lab_robot_file

__all__ = ["ERROR_RECOVERY_ACTION", "ReflexCause", "CARTESIAN_VELOCITY_LIMITS_VIOLATION", "CARTESIAN_VELOCITY_DISCONTINUITY",
           "CARTESIAN_ACCELERATION_DISCONTINUITY", "NON_FINITE_COMMAND", "RECOVERY_HINT", "explain_cause",
           "explain_reflex"]

# The names come from the robot profile (core/robots/franka_panda.yaml).
_ERRORS = lab_robot_file()["errors"]
#: franka_control's error recovery action (franka_msgs/ErrorRecoveryAction); lab_sim serves it at home.
ERROR_RECOVERY_ACTION: str = lab_robot_file()["topics"]["error_recovery"]
#: ``|v|`` above the Cartesian velocity limit (franka::Errors field).
CARTESIAN_VELOCITY_LIMITS_VIOLATION: str = _ERRORS["cartesian"]["velocity"]
#: ``|dv/dt|`` above the acceleration limit: "commanded velocity ... is discontinuous".
CARTESIAN_VELOCITY_DISCONTINUITY: str = _ERRORS["cartesian"]["acceleration"]
#: ``|da/dt|`` above the jerk limit: "commanded acceleration ... is discontinuous".
CARTESIAN_ACCELERATION_DISCONTINUITY: str = _ERRORS["cartesian"]["jerk"]
#: Not a franka::Errors flag: libfranka's std::invalid_argument "Commanding value is infinite or NaN.".
NON_FINITE_COMMAND: str = _ERRORS["non_finite"]

#: The last sentence of every explanation: how the lab gets the robot moving again.
RECOVERY_HINT = ("Then recover: press options (start) on the pad, or the notebook's recover button "
                 "(franka_control's error_recovery action); the robot accepts commands again from rest.")


@dataclass(frozen=True)
class ReflexCause:
    """One broken limit: libfranka's name, where (``"translation"``, ``"rotation"`` or ``"joint 4"``),
    the value the robot saw and its limit, in SI units of that quantity."""

    error: str
    where: str
    value: float
    limit: float


def _unit(where: str) -> str:
    return "m/s" if where == "translation" else "rad/s"


def explain_cause(cause: ReflexCause) -> str:
    """One or two sentences for one broken limit (without the numbers when the robot gave none: NaN)."""
    e, where, value, limit = cause.error, cause.where, cause.value, cause.limit
    unit = _unit(where)
    known = not (math.isnan(value) and math.isnan(limit))

    def numbers(text: str) -> str:
        return f" ({text})" if known else ""

    if e == CARTESIAN_VELOCITY_LIMITS_VIOLATION:
        return (f"The hand was commanded faster than the robot allows{numbers(f'{where} {value:.3g} {unit}, limit {limit:g} {unit}')}. "
                "Lower the gains k_trans/k_rot or the velocity limit of the twist limiter.")
    if e == CARTESIAN_VELOCITY_DISCONTINUITY:
        return (f"The commanded {where} velocity jumped: its change within one millisecond is too large an "
                f"acceleration{numbers(f'{value:.3g} {unit}/s, limit {limit:g}')}. Ramp the velocity with the twist "
                "limiter, never step it, not even to zero.")
    if e == CARTESIAN_ACCELERATION_DISCONTINUITY:
        return (f"The commanded {where} acceleration jumped: too large a jerk{numbers(f'{value:.3g} {unit}/s^2, limit {limit:g}')}. "
                "Ramp the velocity smoothly; a step, however small, is a jump of the acceleration.")
    if e == NON_FINITE_COMMAND:
        return "A command held NaN or infinity, which the robot refuses. Check the numbers your node computes."
    if e == JOINT_POSITION_LIMITS_VIOLATION:
        side = ("upper " if value >= limit else "lower ") if known else ""
        return (f"The hand cannot go further this way: {where} reached its {side}limit"
                f"{numbers(f'{value:+.4f} rad, limit {limit:+.4f} rad')}. After recovering, move back the way you came "
                "(in rotation mode, turn the other way) or drive to the start pose first.")
    if e == JOINT_VELOCITY_LIMITS_VIOLATION:
        speed = "an infinite speed" if math.isinf(value) else f"{abs(value):.3g} rad/s"
        return (f"{where.capitalize()} would have had to turn too fast{numbers(f'{speed}, limit {limit:g} rad/s')}: the "
                "arm is near a singular pose (stretched out, or two wrist axes in line), where a small hand motion "
                "needs a large joint motion. Move the hand back towards the middle of the workspace, slowly.")
    if e == JOINT_VELOCITY_DISCONTINUITY:
        return (f"{where.capitalize()}'s velocity jumped{numbers(f'{abs(value):.3g} rad/s^2, limit {limit:g}')}: for this "
                "arm pose the twist changed too abruptly. Ramp more gently, or move away from a stretched-out pose.")
    if e == JOINT_ACCELERATION_DISCONTINUITY:
        return (f"{where.capitalize()}'s acceleration jumped{numbers(f'{abs(value):.3g} rad/s^3, limit {limit:g}')}: a "
                "step in the commanded twist reaches the joints as a jerk. Ramp the velocity, never step it.")
    return f"{e}{numbers(f'{where}: {value:.3g}, limit {limit:g}')}."


def explain_reflex(causes: Sequence[ReflexCause]) -> List[str]:
    """The reflex as lines for a person: what stopped the robot (each error once), then how to recover."""
    if not causes:
        return ["No reflex: the robot accepts commands."]
    lines = ["The robot stopped itself (a reflex) because a command would have broken one of its limits:"]
    seen = set()
    for cause in causes:  # each error once, at the first place it broke (a singular pose breaks them all)
        if cause.error in seen:
            continue
        seen.add(cause.error)
        lines.append(f"- {explain_cause(cause)} [libfranka: {cause.error}]")
    lines.append(RECOVERY_HINT)
    return lines
