"""make lab-twin's commands on standard input: each becomes one call on the twin, a wrong one one line saying what to type."""

from __future__ import annotations

from typing import List, Tuple

from hri_teleop.apps.lab_twin import handle
from hri_teleop.hardware.sim.rosserial_board import BoardStandInError, Piston
from hri_teleop.ros.lab_twin.report import TwinReport


class StubTwin:
    """Records what the commands ask of the twin; a press is checked as the board checks it."""

    def __init__(self) -> None:
        self.calls: List[Tuple[str, object]] = []

    def press(self, count: int, hold_s: float) -> None:
        Piston().press(count, hold_s, 0.0)
        self.calls.append(("press", (count, hold_s)))

    def set_activated(self, activated: bool) -> None:
        self.calls.append(("activated", activated))

    def report(self) -> TwinReport:
        return TwinReport(twists=5, nonzero_twists=3, activated=False, gripper_goals={"move": 2},
                          pub_force_published=40, pub_force_publishers=["/serial_node"], replaced=["/franka_control"])


def run(*lines: str) -> Tuple[StubTwin, List[str]]:
    twin, said = StubTwin(), []
    for line in lines:
        handle(twin, line, said.append)  # type: ignore[arg-type]
    return twin, said


def test_press_activate_and_deactivate_reach_the_twin() -> None:
    twin, said = run("press 700 2", "press", "deactivate", "activate", "")
    assert twin.calls == [("press", (700, 2.0)), ("press", (700, 2.0)), ("activated", False), ("activated", True)]
    assert said[0] == "twin: piston pressed to 700 for 2 s"


def test_report_says_what_reached_the_twin() -> None:
    _twin, said = run("report")
    text = "\n".join(said)
    assert "5 twists received, 3 non-zero (user stop engaged: the arm stays)" in text
    assert "goals: move 2" in text and "40 counts on /pub_force by /serial_node" in text
    assert "replaced: /franka_control" in text


def test_a_wrong_command_is_one_line_saying_what_to_type() -> None:
    twin, said = run("presss 700", "press seven", "press 2000 1")
    assert twin.calls == []
    assert said[0] == "twin: unknown command 'presss'; type help"
    assert said[1] == "twin: 'press seven': give numbers, e.g. press 700 2"
    assert said[2].startswith("twin: a press count must be a whole count in 0..1023") and len(said) == 3
    assert issubclass(BoardStandInError, ValueError)  # so the toolkit's error is caught before "give numbers"
