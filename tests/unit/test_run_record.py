"""hri_teleop.core.run_record: what a run did, as `make demo`, the offline runner and the tests print it."""

from __future__ import annotations

import pytest

from hri_teleop.core.run_record import LabRecord, LabSummary, format_summary, summarize, time_above

SERIES = ("count", "mapped", "rumble", "width_target", "width", "speed", "grip_force", "object_height")


@pytest.mark.parametrize("name", SERIES)
def test_a_run_starts_at_its_earliest_sample_and_lasts_to_its_latest_in_any_series(name):
    record = LabRecord(count=[(2.0, 0.0), (3.0, 1.0)], speed=[(2.5, 0.0), (4.0, 0.1)])
    setattr(record, name, [(1.0, 0.0), (5.0, 0.0)])
    assert record.start_s() == 1.0
    assert record.duration_s() == 4.0


def test_a_run_without_samples_starts_at_0_and_lasts_0_s():
    assert LabRecord().start_s() == 0.0 and LabRecord().duration_s() == 0.0
    assert LabRecord(width=[(7.0, 0.08)]).duration_s() == 0.0


def test_the_outcome_is_the_worst_thing_that_happened_crushed_then_lifted_then_grasped_else_missed():
    def outcome(**flags):
        return summarize(LabRecord(**flags)).outcome

    assert outcome(crushed=True, lifted=True, grasped=True) == "crushed"
    assert outcome(lifted=True, grasped=True) == "lifted"
    assert outcome(grasped=True) == "grasped"
    assert outcome() == "missed"


def test_the_pad_rumbled_for_the_time_its_samples_held_a_level_above_0():
    rumble = [(0.0, 0.0), (1.0, 0.5), (1.5, 0.0), (3.0, 0.2), (3.25, 0.2), (4.0, 0.0)]
    assert time_above(rumble) == pytest.approx(0.5 + 0.25 + 0.75)
    assert time_above(rumble, 0.2) == pytest.approx(0.5)  # a level exactly at the threshold is not above it
    assert time_above(rumble, 0.19) == pytest.approx(1.5)
    assert time_above([(0.0, 1.0)]) == 0.0  # the last sample holds for no time


def test_the_summary_takes_the_worlds_peak_grip_force_when_it_kept_one_else_the_series_peak():
    forces = [(0.0, 3.0), (1.0, 12.5), (2.0, 4.0)]
    assert summarize(LabRecord(grip_force=forces)).peak_force_n == 12.5
    assert summarize(LabRecord(grip_force=forces, peak_grip_force_n=14.0)).peak_force_n == 14.0
    assert summarize(LabRecord(grip_force=forces, peak_grip_force_n=0.0)).peak_force_n == 0.0
    assert summarize(LabRecord()).peak_force_n == 0.0 and summarize(LabRecord()).peak_force_mapped == 0.0


def test_the_summary_holds_the_runs_answers():
    record = LabRecord(mapped=[(0.0, 0.1), (1.0, 0.75), (2.0, 0.2)], rumble=[(0.0, 0.3), (0.5, 0.0)],
                       object_name="sponge", grasped=True, violations=3,
                       violation_counts={"joint 4 velocity": 2, "cartesian jerk": 1},
                       reflex_explanation=["a", "b"], ended_by="quit")
    summary = summarize(record)
    assert summary == LabSummary(object_name="sponge", grasped=True, lifted=False, crushed=False, peak_force_n=0.0,
                                 peak_force_mapped=0.75, rumble_s=0.5, violations=3,
                                 violation_counts={"joint 4 velocity": 2, "cartesian jerk": 1}, duration_s=2.0,
                                 ended_by="quit", reflex_explanation=("a", "b"))
    record.violation_counts["joint 4 velocity"] = 9  # the summary keeps its own copy
    assert summary.violation_counts["joint 4 velocity"] == 2
    assert summarize(LabRecord()).object_name == "none"


def test_the_printout_has_one_line_per_answer_and_the_reflex_explanation_indented():
    summary = LabSummary(object_name="sponge", grasped=True, lifted=True, crushed=False, peak_force_n=12.345,
                         peak_force_mapped=0.75, rumble_s=1.256, violations=3,
                         violation_counts={"joint 4 velocity": 2, "cartesian jerk": 1}, duration_s=20.04,
                         ended_by="quit", reflex_explanation=("reflex: joint 4 velocity", "fix: ramp"))
    assert format_summary(summary) == [
        "object            sponge: lifted",
        "grasped           yes",
        "lifted            yes",
        "crushed           no",
        "peak grip force   12.35 N",
        "peak /force_mapped 0.750",
        "pad rumbled       1.26 s",
        "Franka limit violations 3 (cartesian jerk: 1, joint 4 velocity: 2)",
        "run               20.0 s, ended by quit",
        "  reflex: joint 4 velocity",
        "  fix: ramp",
    ]


def test_a_clean_run_prints_no_violation_names_and_an_unknown_end_as_a_question_mark():
    lines = format_summary(summarize(LabRecord()))
    assert lines[0] == "object            none: missed"
    assert lines[7] == "Franka limit violations 0"
    assert lines[8] == "run               0.0 s, ended by ?"
    assert len(lines) == 9
    crushed = format_summary(summarize(LabRecord(object_name="egg", grasped=True, crushed=True)))
    assert crushed[:4] == ["object            egg: crushed", "grasped           yes", "lifted            no",
                           "crushed           yes"]
