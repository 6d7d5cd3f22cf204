"""The teleoperation node under grading runs on the grader's clock (/use_sim_time, /clock one tick at a
time): as fast as the node computes, and with the same messages however busy the machine is."""

from __future__ import annotations

import pytest
from grading_helpers import answer_text, write_package

from hri_teleop.grading.exercises.teleoperation import check as teleop_check
from hri_teleop.grading.exercises.teleoperation.judge_node import compare_teleop_node

pytestmark = pytest.mark.ros

SEED = 407054861


@pytest.fixture
def clocks(monkeypatch):
    """The clock each node run was observed on ("grader" or "real time"), as the judge saw it."""


    seen = []
    original = compare_teleop_node

    def spy(observation, *args, **kwargs):
        seen.append(observation.clock)
        return original(observation, *args, **kwargs)

    monkeypatch.setattr(teleop_check, "compare_teleop_node", spy)
    return seen


def _package(tmp_path, text):
    return write_package(tmp_path / "hri_lab", {"package.xml": answer_text("package.xml"),
                                                "scripts/teleoperation.py": text})


def test_the_answer_key_runs_on_the_grader_clock_and_gets_full_marks(tmp_path, clocks):
    """On the grader's clock a run takes what the node computes, not the pad script's length; how much
    faster that is than real time is make bench's ("hri-grade submission, real time", same run)."""
    from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation

    result = grade_teleoperation(_package(tmp_path, answer_text("scripts/teleoperation.py")), seed=SEED)
    assert result.score == result.max_score, result.failed_parts
    assert not any("real time" in n for n in result.notes)
    assert clocks == ["grader"]


def test_a_loop_paced_by_time_sleep_is_judged_all_the_same(tmp_path, clocks):
    """Such a loop ignores /clock; under grading time.sleep in the student's files follows the
    grader's clock (grading/run/clock_sleep.py), so the loop passes once per tick, busy or not."""
    from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation

    text = answer_text("scripts/teleoperation.py")
    assert "            rate.sleep()" in text
    text = text.replace("            rate.sleep()", "            time.sleep(1.0 / self.rate)")
    result = grade_teleoperation(_package(tmp_path, text), seed=SEED)
    assert result.score == result.max_score, result.failed_parts
    assert clocks == ["grader"]  # stepped tick by tick, not paced on the wall clock


def test_the_grader_clock_gives_the_same_messages_run_after_run(tmp_path):

    from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation

    seen = []
    original = compare_teleop_node

    def spy(observation, *args, **kwargs):
        seen.append({t: [(ts, v) for ts, _k, v in msgs] for t, msgs in observation.messages.items()})
        return original(observation, *args, **kwargs)

    package = _package(tmp_path, answer_text("scripts/teleoperation.py"))
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(teleop_check, "compare_teleop_node", spy)
        for _ in range(2):
            grade_teleoperation(package, seed=SEED)
    twist = "/cartesian_velocity_controller/cmd_vel"
    assert seen[0][twist] and seen[0][twist] == seen[1][twist]
    assert seen[0]["/gripper_width"] == seen[1]["/gripper_width"]


def test_hri_grade_clock_real_runs_the_node_on_the_wall_clock_through_the_same_checks(tmp_path, monkeypatch, clocks):
    """HRI_GRADE_CLOCK=real: grading as it was before the grader owned the clock (make bench's
    "before" row): the pad script and the node on the wall clock, the same parts judged, no note
    about the clock. Its points are not asserted: on the wall clock a busy machine costs a loop
    ticks, which is why the grader owns the clock (test_a_loop_paced_by_time_sleep...)."""
    from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation
    from hri_teleop.grading.judge.harness import CLOCK_ENV

    package = _package(tmp_path, answer_text("scripts/teleoperation.py"))
    on_clock = grade_teleoperation(package, seed=SEED)
    monkeypatch.setenv(CLOCK_ENV, "real")
    real = grade_teleoperation(package, seed=SEED)
    assert clocks == ["grader", "real time"]  # the pad script ran on the wall clock
    assert [p.name for p in real.parts] == [p.name for p in on_clock.parts]
    assert real.max_score == on_clock.max_score
    assert not real.notes
