"""The kernel's master as the rules see it: this kernel's own, or the lab's -- asked of the master.

Every start from a notebook goes through :func:`start_refusal` (``course.nodes``), so the rule of
:mod:`hri_teleop.core.modes` is applied in one place: on a master this kernel did not start, or
next to real hardware, nothing simulated or scripted starts, whatever ``HRI_MODE`` says.
A refused start is a :class:`NotStarted`: it says why, and later cells keep working.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import List, Optional, Sequence

from hri_teleop.core.modes import HARDWARE_NODES, Start, decide_mode, mode_from_env
from hri_teleop.core.modes import start_refusal as rule_refusal
from hri_teleop.ros.master import started_here
from hri_teleop.ros.master_api import MasterApiError, master_reachable, master_uri, running_nodes

__all__ = ["MasterMode", "master_mode", "start_refusal", "NotStarted"]


@dataclass(frozen=True)
class MasterMode:
    """The mode on the kernel's master, whether this process started it, and its hardware nodes."""

    mode: str
    own: bool
    hardware: List[str] = field(default_factory=list)


def master_mode(uri: Optional[str] = None) -> MasterMode:
    """Decide from the master at ``uri`` (default ``$ROS_MASTER_URI``) what may start on it.

    No master answering: nothing can be harmed there, the environment's wish stands (the
    kernel starts its own master before it starts anything).
    """
    where = uri or master_uri()
    if started_here(where):
        own = True
    elif master_reachable(where):
        own = False
    else:
        return MasterMode(mode_from_env(os.environ), own=True)
    try:
        hardware = running_nodes(among=list(HARDWARE_NODES), uri=where)
    except MasterApiError:
        hardware = []
    return MasterMode(decide_mode(os.environ, own), own, hardware)


def start_refusal(starts: Sequence[Start], uri: Optional[str] = None) -> Optional[str]:
    """The first refusal among ``starts`` on the kernel's master, or None when all may start."""
    if not starts:
        return None
    state = master_mode(uri)
    for start in starts:
        refusal = rule_refusal(state.mode, start, state.hardware, state.own)
        if refusal:
            return refusal
    return None


class NotStarted:
    """What a refused start returns: false, not running, its ``output()`` the refusal.

    Later cells that print ``node.output()`` or call ``node.stop()`` keep working.
    """

    def __init__(self, reason: str) -> None:
        self.reason = reason

    def __bool__(self) -> bool:
        return False

    def __repr__(self) -> str:
        return f"NotStarted({self.reason!r})"

    @property
    def running(self) -> bool:
        return False

    def output(self) -> str:
        return self.reason + "\n"

    def stop(self) -> None:
        """Nothing runs: nothing to stop."""

    def wait(self, timeout_s: float = 0.0) -> Optional[int]:
        """Nothing ran: no exit status."""
        return None
