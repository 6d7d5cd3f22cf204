"""Where a notebook runs -- home, lab or grading -- and what it may start there.

The same notebooks run at home (a private master, everything simulated), on the lab PC
next to the real Panda and Arduino, and under nbgrader. Simulated hardware on the lab's
master would publish fake presses on the real ``/pub_force`` or fight the real robot, so
the rules that decide what a notebook may start live here, as plain functions (no rospy):
:mod:`hri_teleop.course` asks them before it starts a process.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

from hri_teleop.core.errors import HriTeleopError

HOME = "home"
LAB = "lab"
GRADING = "grading"
MODES = (HOME, LAB, GRADING)

#: Nodes that only the real lab runs: a master that has one of them has real hardware.
HARDWARE_NODES = ("/serial_node", "/franka_control", "/franka_gripper")

#: The gamepads a node can read: a real one through pygame, or the scripted virtual pad.
PADS = ("virtual", "pygame")


class ModeError(HriTeleopError, ValueError):
    """A mode or a pad choice that cannot be used; the message names the fix."""

    def _render_traceback_(self) -> List[str]:  # IPython shows this one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


def mode_from_env(env: Mapping[str, str]) -> str:
    """``HRI_MODE`` when set; ``grading`` under nbgrader's autograde; ``home`` otherwise.

    The lab PCs set ``HRI_MODE=lab`` (README "Home, lab and grading"): the lab is never
    guessed, so a missing setting can only make a notebook more careful, never less.
    """
    value = env.get("HRI_MODE", "").strip().lower()
    if value in MODES:
        return value
    if value:
        raise ModeError(f"HRI_MODE={env['HRI_MODE']!r} is not a mode: set it to home, lab or grading")
    if env.get("NBGRADER_EXECUTION"):
        return GRADING
    return HOME


def simulation_refusal(mode: str, what: str, running_nodes: Iterable[str]) -> Optional[str]:
    """Why the simulated ``what`` may not start on this master, or None when it may.

    Never in lab mode, and never next to a node only real hardware runs, whatever the mode.
    """
    if mode == LAB:
        return (f"lab mode: no simulated {what} is started here, the lab's hardware runs on this master "
                f"(at home, set HRI_MODE=home)")
    real = sorted(set(running_nodes) & set(HARDWARE_NODES))
    if real:
        return (f"this master runs real hardware ({', '.join(real)}): no simulated {what} is started; "
                f"on the lab PC set HRI_MODE=lab")
    return None


def duplicate_refusal(wanted: Sequence[str], running: Iterable[str]) -> Optional[str]:
    """Why nodes named ``wanted`` may not start (a node of that name runs), or None.

    ROS would shut the running node down when a second one registers its name: in the lab
    that is a student's teleoperation node, stopped in mid-motion.
    """
    taken = sorted({_absolute(name) for name in wanted} & {_absolute(name) for name in running})
    if not taken:
        return None
    names = ", ".join(taken)
    return (f"{names} already running on this master: a second node of that name would stop it; "
            f"stop it first (lab.stop() for this notebook's nodes, or rosnode kill {taken[0]})")


def _absolute(name: str) -> str:
    return name if name.startswith("/") else "/" + name


def pad_params(pad: str, script: Union[str, Path, None] = None) -> Dict[str, Any]:
    """A teleoperation node's pad parameters: the script only goes to the virtual pad.

    With ``pad="pygame"`` a person drives the real gamepad, so a script given for the
    virtual pad is left out instead of failing the node's start.
    """
    if pad not in PADS:
        raise ModeError(f"pad={pad!r} is not a gamepad: use 'virtual' (the scripted pad) or 'pygame' (a real one)")
    if pad == "pygame" or script is None:
        return {"pad": pad}
    return {"pad": pad, "pad_script": str(script)}


def describe(mode: str) -> str:
    """One line for the notebook: what this mode starts and where."""
    return {
        HOME: "home mode: a private master and the simulated lab",
        LAB: "lab mode: the lab's master, the real robot and board; nothing simulated is started",
        GRADING: "grading mode: a private master and the simulated lab, as nbgrader runs it",
    }[mode]
