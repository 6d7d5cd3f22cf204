"""``make doctor``'s gamepad: found or not, which layout, its buttons seen once each, its rumble felt or refused.

The walk-through asks for each button and stick the lab uses, reads it through the layout the
teleoperation node would use, and names a control that arrives under another name: the usual
cause of a pad that "does the wrong thing". Each step can be skipped (``skip`` says so).
"""

from __future__ import annotations

import time
from typing import Any, Callable, List, Optional, Tuple

from hri_teleop.core.doctor import FAIL, Finding, pad_finding, rumble_finding, walk_finding
from hri_teleop.core.gamepad.identify import identify_layout
from hri_teleop.core.gamepad.state import BUTTON_LABELS, GamepadError
from hri_teleop.hardware.real.pygame_pad import PygamePad, import_pygame

__all__ = ["WALK_BUTTONS", "WALK_STICKS", "WAIT_S", "RUMBLE", "pad_findings", "PadInfo", "find_pad"]

#: What the lab's node reads, in the order the walk-through asks for it.
WALK_BUTTONS = ("south", "east", "north", "west")
WALK_STICKS = (("left_y", 1.0, "left stick up"), ("left_x", 1.0, "left stick right"),
               ("right_y", 1.0, "right stick up"))
#: How long the walk-through waits for each press (s) before it counts the step as not tried.
WAIT_S = 8.0
#: The rumble probe: low- and high-frequency motor strengths (0..1) and its length (ms).
RUMBLE = (0.7, 0.7, 600)


class PadInfo:
    """The first pad SDL sees: its SDL joystick (initialised), name, GUID and counts of axes and buttons."""

    def __init__(self, joystick: Any) -> None:
        self.joystick = joystick
        self.name = str(joystick.get_name())
        self.guid = str(joystick.get_guid()) if hasattr(joystick, "get_guid") else ""
        self.num_axes = int(joystick.get_numaxes())
        self.num_buttons = int(joystick.get_numbuttons())

    def describe(self) -> str:
        return f"{self.name} (GUID {self.guid or '?'}, {self.num_axes} axes, {self.num_buttons} buttons)"


def find_pad() -> Tuple[Optional[PadInfo], str]:
    """The first pad, or None and why none (pygame missing, no pad plugged in)."""
    try:
        pygame = import_pygame()
    except GamepadError as exc:
        return None, str(exc)
    if pygame.joystick.get_count() == 0:
        return None, "no gamepad"
    joystick = pygame.joystick.Joystick(0)
    joystick.init()
    return PadInfo(joystick), ""


def _layout(info: PadInfo) -> Tuple[Optional[str], str]:
    """The layout identified from the pad's GUID and name (the node's ``layout: auto``)."""
    guess = identify_layout(info.guid, info.name, info.num_axes, info.num_buttons)
    return guess.layout, guess.reason


def _wait_for(pad: PygamePad, wanted: Callable[[Any], bool], seconds: float,
              skip: Callable[[], bool]) -> Optional[Any]:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and not skip():
        state = pad.poll()
        if wanted(state):
            return state
        time.sleep(0.01)
    return None


def walk(pad: PygamePad, say: Callable[[str], None], skip: Callable[[], bool], wait_s: float = WAIT_S) -> Finding:
    """Each button and stick once: seen under its own name, or named as what arrived instead."""
    wrong: List[str] = []
    unseen: List[str] = []
    for button in WALK_BUTTONS:
        label = BUTTON_LABELS.get(button, button)
        say(f"      press {label} (Enter or Skip: skip; {wait_s:.0f} s)")
        state = _wait_for(pad, lambda s: any(s.pressed(b) for b in WALK_BUTTONS), wait_s, skip)
        if state is None:
            unseen.append(label)
            continue
        if not state.pressed(button):
            arrived = next(b for b in WALK_BUTTONS if state.pressed(b))
            wrong.append(f"{label} reads as {BUTTON_LABELS.get(arrived, arrived)}")
        _wait_for(pad, lambda s: not any(s.pressed(b) for b in WALK_BUTTONS), wait_s, lambda: False)
    for axis, sign, words in WALK_STICKS:
        say(f"      push the {words}, all the way (Enter or Skip: skip; {wait_s:.0f} s)")
        state = _wait_for(pad, lambda s, a=axis: abs(s.axis(a)) > 0.8, wait_s, skip)  # type: ignore[misc]
        if state is None:
            unseen.append(words)
        elif state.axis(axis) * sign < 0:
            wrong.append(f"{words} reads reversed")
    return walk_finding(wrong, unseen)


def _rumble(joystick: Any) -> bool:
    try:
        return bool(joystick.rumble(*RUMBLE))
    except (AttributeError, RuntimeError):  # pygame < 2.0.2, or SDL without haptics
        return False


def pad_findings(mode: str, walk_through: bool, ask: Callable[[str], str], say: Callable[[str], None],
                 skip: Callable[[], bool] = lambda: False) -> List[Finding]:
    """The gamepad's lines: found and its layout, its buttons (with ``walk_through``), its rumble."""
    info, why = find_pad()
    if info is None:
        return [pad_finding(mode, None, None, why)]
    layout, reason = _layout(info)
    findings = [pad_finding(mode, info.describe(), layout, reason)]
    if walk_through:
        try:
            pad = PygamePad(layout, 0)
        except GamepadError as exc:
            findings.append(Finding("pad buttons", FAIL, str(exc), "pick this pad's layout (layout:=...)"))
        else:
            findings.append(walk(pad, say, skip))
            pad.close()
    accepted = _rumble(info.joystick)
    felt: Optional[bool] = None
    if accepted and walk_through:
        answer = ask("      did the pad rumble just now? [y/n, Enter: skip] ").strip().lower()
        felt = None if not answer else answer.startswith("y")
    findings.append(rumble_finding(accepted, felt))
    return findings
