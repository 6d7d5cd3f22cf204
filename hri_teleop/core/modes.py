"""Where a notebook runs -- home, lab or grading -- and what it may start there.

The same notebooks run at home, on the lab PC next to the real Panda and Arduino, and under
nbgrader. The mode is decided from the master, not from a setting: a master this process did
not start itself may carry the real robot, so it is the lab's, and there nothing simulated or
scripted starts (a fake press on the real ``/pub_force``, a script at the real arm's pad).
A missing setting can only make a notebook more careful. docs/lab-day.md, "Modes".
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

from hri_teleop.core.errors import HriTeleopError

HOME = "home"
LAB = "lab"
GRADING = "grading"
MODES = (HOME, LAB, GRADING)

#: Nodes that only the real lab runs: a master that has one of them has real hardware.
HARDWARE_NODES = ("/serial_node", "/franka_control", "/franka_gripper")

#: The gamepads a node can read: a real one through pygame, the scripted virtual pad, or the gamepad of
#: the notebook's browser page (widgets.BrowserPad publishes it to the node; at home and in the container).
PADS = ("virtual", "pygame", "browser")
#: The pad a teleoperation node reads when no ``~pad`` parameter is given (the lab's gamepad).
NODE_DEFAULT_PAD = "pygame"

#: The lab's node scripts that stand in for hardware: never next to the real one.
SIMULATED_SCRIPTS = ("FSR_sensor.py", "lab_sim.py")


class ModeError(HriTeleopError, ValueError):
    """A mode or a pad choice that cannot be used; the message names the fix."""

    def _render_traceback_(self) -> List[str]:  # IPython shows this one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


def mode_from_env(env: Mapping[str, str]) -> str:
    """The mode the environment asks for: ``HRI_MODE``, ``grading`` under nbgrader, else ``home``.

    Only a wish: :func:`decide_mode` makes any master this process did not start the lab.
    """
    value = env.get("HRI_MODE", "").strip().lower()
    if value in MODES:
        return value
    if value:
        raise ModeError(f"HRI_MODE={env['HRI_MODE']!r} is not a mode: set it to home, lab or grading "
                        "(or leave it unset: the master decides)")
    if env.get("NBGRADER_EXECUTION"):
        return GRADING
    return HOME


def decide_mode(env: Mapping[str, str], own_master: bool) -> str:
    """The mode on a master: ``lab`` on any master this process did not start, whatever is set.

    On its own private master a process is at home (``grading`` under nbgrader), unless
    ``HRI_MODE=lab`` asks for the lab's care there too.
    """
    wish = mode_from_env(env)
    if not own_master:
        return LAB
    return wish


def ignored_setting(env: Mapping[str, str], own_master: bool) -> Optional[str]:
    """One line when ``HRI_MODE`` asks for less care than the master allows, else None."""
    wish = env.get("HRI_MODE", "").strip().lower()
    if own_master or wish not in (HOME, GRADING):
        return None
    return (f"HRI_MODE={wish} is ignored: this master was not started by this process, so it is treated as the "
            "lab's (it may carry the real robot)")


@dataclass(frozen=True)
class Start:
    """What a shell is about to start, as the rules see it.

    ``simulated``: it stands in for hardware (the simulated board or robot). ``pad``: for a
    teleoperation node, the pad it reads (``virtual``: a script plays it; ``browser``: the notebook's page).
    """

    what: str
    simulated: bool = False
    pad: Optional[str] = None


def master_description(own_master: bool, hardware: Sequence[str]) -> str:
    """Why a master counts as the lab's, in words for a refusal ('' on a private one without hardware)."""
    if hardware:
        return f"this master runs real hardware ({', '.join(sorted(hardware))})"
    if not own_master:
        return "this master was not started by this process: it is treated as the lab PC's, with the real robot"
    return ""


def start_refusal(mode: str, start: Start, hardware: Sequence[str], own_master: bool = True) -> Optional[str]:
    """Why ``start`` may not start on this master (one line: what, why, what to do), or None.

    In the lab, and next to real hardware whatever the mode, nothing simulated starts, and a
    teleoperation node starts only with a real pad (a virtual pad is played by a script).
    """
    lab = mode == LAB or bool(hardware)
    if not lab:
        return None
    why = master_description(own_master, hardware) or "lab mode (HRI_MODE=lab)"
    if start.simulated:
        return (f"refused to start {start.what}: it is simulated and {why}; the real hardware does its job "
                "here (at home: restart the kernel with no ROS master running, the notebook starts its own)")
    if start.pad is not None and start.pad != "pygame":
        return (f"refused to start {start.what} with the {start.pad} pad: {why}, where only a person at the real "
                f"gamepad may drive; set PAD = \"pygame\" with the lab's pad plugged in")
    return None


def simulation_refusal(mode: str, what: str, running_nodes: Iterable[str], own_master: bool = True) -> Optional[str]:
    """Why the simulated ``what`` may not start on this master, or None when it may."""
    hardware = sorted(set(running_nodes) & set(HARDWARE_NODES))
    return start_refusal(mode, Start(what, simulated=True), hardware, own_master)


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


def default_pad(mode: str) -> str:
    """The pad a notebook's node reads unless the student picks one: the real one in the lab."""
    return "pygame" if mode == LAB else "virtual"


def pad_params(pad: str, script: Union[str, Path, None] = None, mode: str = HOME) -> Dict[str, Any]:
    """A teleoperation node's pad parameters: the script only goes to the virtual pad.

    With ``pad="pygame"`` or ``pad="browser"`` a person drives (the real gamepad, or one read by the
    browser), so a script given for the virtual pad is left out. Under grading nobody is at a pad:
    the virtual pad plays the script.
    """
    if pad not in PADS:
        raise ModeError(f"pad={pad!r} is not a gamepad: use 'virtual' (the scripted pad), 'pygame' (a real one) "
                        "or 'browser' (a gamepad read by this notebook's browser page)")
    if mode == GRADING and script is not None:
        pad = "virtual"
    if pad != "virtual" or script is None:
        return {"pad": pad}
    return {"pad": pad, "pad_script": str(script)}


def describe(mode: str, own_master: bool = True) -> str:
    """One line for the notebook: what this mode starts and where."""
    if mode == LAB and not own_master:
        return ("lab mode: a master this notebook did not start (the lab PC's, with the real robot and board); "
                "nothing simulated or scripted is started, your node drives with the real pad")
    return {
        HOME: "home mode: a private master and the simulated lab",
        LAB: "lab mode: the lab's master, the real robot and board; nothing simulated is started",
        GRADING: "grading mode: a private master and the simulated lab, as nbgrader runs it",
    }[mode]
