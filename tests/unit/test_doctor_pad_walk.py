"""make doctor's pad walk-through on a scripted pad: a control under another name fails, a skip is noted."""

from __future__ import annotations

from typing import Iterator, List

from hri_teleop.core.doctor import FAIL, NOTE, OK
from hri_teleop.core.gamepad.state import PadState
from hri_teleop.ros.doctor_pad import WALK_BUTTONS, WALK_STICKS, walk

REST = PadState()


class ScriptedPad:
    """poll() answers each walk step with the next press (then rest, so the walk moves on)."""

    def __init__(self, presses: List[PadState]) -> None:
        self._states: Iterator[PadState] = iter([s for press in presses for s in (press, REST)])

    def poll(self) -> PadState:
        return next(self._states, REST)


def _right_presses() -> List[PadState]:
    buttons = [PadState(buttons={b: True}) for b in WALK_BUTTONS]
    return buttons + [PadState(axes={axis: sign}) for axis, sign, _ in WALK_STICKS]


def test_every_control_seen_under_its_own_name_passes() -> None:
    said: List[str] = []
    finding = walk(ScriptedPad(_right_presses()), said.append, lambda: False, wait_s=1.0)  # type: ignore[arg-type]
    assert finding.status == OK
    assert len(said) == len(WALK_BUTTONS) + len(WALK_STICKS)


def test_a_button_read_as_another_fails_naming_both() -> None:
    presses = _right_presses()
    presses[0] = PadState(buttons={"east": True})  # asked for cross, the pad says circle
    finding = walk(ScriptedPad(presses), lambda _l: None, lambda: False, wait_s=1.0)  # type: ignore[arg-type]
    assert finding.status == FAIL and finding.detail == "cross / A reads as circle / B"


def test_a_reversed_stick_fails() -> None:
    presses = _right_presses()
    presses[len(WALK_BUTTONS)] = PadState(axes={"left_y": -1.0})
    finding = walk(ScriptedPad(presses), lambda _l: None, lambda: False, wait_s=1.0)  # type: ignore[arg-type]
    assert finding.status == FAIL and "left stick up reads reversed" in finding.detail


def test_skipping_every_step_notes_them_all_without_waiting() -> None:
    finding = walk(ScriptedPad([]), lambda _l: None, lambda: True, wait_s=60.0)  # type: ignore[arg-type]
    assert finding.status == NOTE
    assert finding.detail.count(",") == len(WALK_BUTTONS) + len(WALK_STICKS) - 1
