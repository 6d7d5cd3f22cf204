"""The simulated study of Ex. 14: counterbalanced, reproducible, analysed as recorded trials are."""

from __future__ import annotations

import pytest

from hri_teleop.core.experiment.metrics import TrialMeta
from hri_teleop.sim.study import StudyError, participant_codes, simulate_study, simulate_trial
from hri_teleop.sim.virtual_pad import parse_script


@pytest.mark.parametrize("bad", [1, 0, -3, True, 2.0, "4"])
def test_a_study_needs_at_least_two_participants_as_a_whole_number(bad):
    with pytest.raises(StudyError, match="at least 2"):
        participant_codes(bad)


def test_two_participants_are_enough_and_codes_are_zero_padded():
    assert participant_codes(2) == ["P01", "P02"]
    assert participant_codes(12)[-1] == "P12"


def test_the_condition_switches_the_rumble_and_nothing_else():
    on = simulate_trial(TrialMeta("P01", "egg", "feedback", 1), 7)
    off = simulate_trial(TrialMeta("P01", "egg", "no_feedback", 1), 7)
    assert max(v for _, v in on.rumble) > 0.9
    assert max((v for _, v in off.rumble), default=0.0) == 0.0


def test_an_unknown_object_is_named_with_the_choices():
    with pytest.raises(StudyError, match="not in the simulation's set"):
        simulate_trial(TrialMeta("P01", "brick", "feedback", 1), 0)


def test_the_same_seed_gives_the_same_study_and_feedback_protects_the_egg():
    first = simulate_study(4, seed=3)
    again = simulate_study(4, seed=3)
    assert [m.peak_force_n for m in first.metrics] == [m.peak_force_n for m in again.metrics]
    assert [(m.meta.participant, m.meta.condition) for m in first.metrics][:4] == [
        ("P01", "feedback"), ("P01", "no_feedback"), ("P02", "no_feedback"), ("P02", "feedback")]
    rates = first.rates()
    assert rates["feedback"]["crush_rate"] == 0.0 and rates["feedback"]["success_rate"] == 1.0
    assert rates["no_feedback"]["crush_rate"] > 0.0
    assert set(first.comparisons) >= {"peak_force_n", "crush_rate"}


def test_a_callers_operator_runs_in_both_conditions():
    steps = parse_script([{"t": 0.5, "tap": "west", "hold": 0.1}])  # quits at once: nothing grasped
    study = simulate_study(2, operator=steps)
    assert {m.meta.condition for m in study.metrics} == {"feedback", "no_feedback"}
    assert not any(m.lifted or m.crushed for m in study.metrics)
    assert all(t.record.duration_s() < 2.0 for t in study.trials)
