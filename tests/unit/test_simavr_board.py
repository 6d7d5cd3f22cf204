"""The simulated board's Python side (hri_teleop.hardware.sim.simavr_board): force profiles -> A0 voltages."""

from __future__ import annotations

from pathlib import Path

import pytest

from hri_teleop.core.fsr import count_to_force, force_to_count
from hri_teleop.hardware.sim.simavr_board import (
    ProfilePoint,
    SimavrBoardError,
    SimulatedUno,
    force_profile,
    press_forces,
    staircase_forces,
    write_profile,
)


def test_the_profile_voltage_reads_as_the_count_the_fsr_model_predicts_for_the_force():
    forces = [0.0, 0.2, 1.0, 10.0, 100.0]
    points = force_profile([0.0, 0.1, 0.2, 0.3, 0.4], forces)
    assert [p.t_us for p in points] == [0, 100000, 200000, 300000, 400000]
    assert points[0] == ProfilePoint(t_us=0, microvolts=0)
    assert [p.count for p in points] == [int(force_to_count(f)) for f in forces]


@pytest.mark.parametrize("count", [1, 300, 700, 1000])
def test_a_force_on_the_lower_edge_of_a_step_keeps_its_count(count):
    (point,) = force_profile([0.0], [float(count_to_force(count))])
    assert point.count == count


def test_a_press_rises_smoothly_holds_at_max_count_and_releases():
    times, forces = press_forces(700, 2.0, hold_s=0.2)
    counts = [p.count for p in force_profile(times, forces)]
    assert counts[0] == 0 and counts[-1] == 0
    assert max(counts) == 700
    assert sum(1 for c in counts if c == 700) >= 200          # held for 0.2 s at 1 ms steps
    steps = [abs(b - a) for a, b in zip(forces, forces[1:])]
    assert max(steps) < 0.02 * max(forces)                    # no jumps


def test_a_staircase_holds_each_force_for_its_step():
    times, forces = staircase_forces([0, 1, 5], 0.3)
    assert times == pytest.approx([0.0, 0.3, 0.6]) and forces == [0.0, 1.0, 5.0]


def test_bad_profiles_are_refused_in_one_line():
    with pytest.raises(SimavrBoardError, match="as many times as forces"):
        force_profile([0.0, 1.0], [1.0])
    with pytest.raises(SimavrBoardError, match="ascending"):
        force_profile([1.0, 0.5], [1.0, 2.0])
    with pytest.raises(SimavrBoardError, match="1..1023"):
        press_forces(0, 2.0)


def test_the_profile_file_is_what_the_harness_reads(tmp_path):
    path = write_profile([ProfilePoint(0, 0), ProfilePoint(1500, 2500000)], tmp_path / "p.txt")
    lines = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    assert lines == ["0 0", "1500 2500000"]


def test_the_harness_command_line(tmp_path):
    board = SimulatedUno(tmp_path / "tty", Path("p.txt"), repeat_us=2000000, speed=2.0,
                         firmware=Path("fw.elf"), harness=Path("uno_sim"))
    assert board.argv() == ["uno_sim", "--firmware", "fw.elf", "--link", str(tmp_path / "tty"), "--quiet",
                            "--profile", "p.txt", "--repeat-us", "2000000", "--speed", "2.0"]


def test_starting_without_a_build_names_the_fix(tmp_path):
    board = SimulatedUno(tmp_path / "tty", harness=tmp_path / "nothing")
    with pytest.raises(SimavrBoardError, match="make firmware"):
        board.start()
