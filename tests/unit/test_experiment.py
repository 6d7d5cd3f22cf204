"""Ex. 14's experiment core: the trial plan, the per-trial metrics, a simulated study end to end."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from hri_teleop.core.attachment import Attachment
from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.experiment.metrics import (
    MetricsError,
    TrialMeta,
    calibrated_force_n,
    per_participant,
    trial_metrics,
)
from hri_teleop.core.experiment.plan import counterbalanced_plan, read_plan, trial_seed, write_plan
from hri_teleop.core.experiment.stats import paired_comparison
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.operators import study_operator
from hri_teleop.sim.world import WorldConfig

REPO = Path(__file__).resolve().parents[2]
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
EGG = WorldConfig(object=OBJECTS["egg"])
MAX = Attachment().full_travel_count  # the calibration a student would measure in this world


def _trial(condition: str, seed: int, participant: str = "P01", trial: int = 1):
    from dataclasses import replace

    params = replace(CONFIG.params, feedback=(condition == "feedback"))
    record = run_lab(study_operator(condition, seed), EGG, params, CONFIG.limits, max_sensor_force=MAX)
    return record, trial_metrics(record, TrialMeta(participant, "egg", condition, trial), MAX)


def test_the_plan_gives_everyone_every_object_in_both_conditions_and_balances_the_order():
    plan = counterbalanced_plan(["P01", "P02", "P03", "P04"], ["egg", "sponge", "block"], repetitions=2)
    assert len(plan) == 4 * 3 * 2 * 2
    cells = Counter((m.participant, m.object_name, m.condition) for m in plan)
    assert set(cells.values()) == {2} and len(cells) == 4 * 3 * 2
    first = {m.participant: m.condition for m in plan if m.trial == 1}
    assert Counter(first.values()) == Counter({"feedback": 2, "no_feedback": 2})
    firsts = [next(m.object_name for m in plan if m.participant == p) for p in ("P01", "P02", "P03")]
    assert sorted(firsts) == ["block", "egg", "sponge"]  # Latin square: each object leads once
    assert [m.trial for m in plan if m.participant == "P03"] == list(range(1, 13))


def test_a_plan_round_trips_through_its_csv(tmp_path):
    plan = counterbalanced_plan(["A", "B"], ["egg"])
    assert read_plan(write_plan(plan, tmp_path / "plan.csv")) == plan


def test_the_calibration_makes_the_measured_maximum_read_the_full_travel_force():
    force = calibrated_force_n([0, MAX, 650], 690.0)
    assert force[0] == 0.0 and force[2] < force[1]
    assert calibrated_force_n([690], 690.0)[0] == pytest.approx(Attachment().full_travel_force_n)


def test_metrics_agree_with_what_the_simulation_knows_for_a_careful_grasp():
    record, m = _trial("feedback", seed=1)
    assert m.success and m.lifted and not m.crushed
    # the FSR's calibrated force matches the simulated spring within the ADC's resolution
    spring_peak = max(v for _, v in record.grip_force)  # below full travel, grip = spring (series)
    assert m.peak_force_n == pytest.approx(spring_peak, rel=0.05)
    assert 0 < m.time_to_grasp_s < m.time_to_lift_s < m.duration_s
    assert m.rumble_s > 1.0 and m.saturated_s == 0.0


def test_metrics_see_a_crush_and_the_piston_bottomed_out_without_feedback():
    for seed in range(40):
        record, m = _trial("no_feedback", seed)
        if record.crushed:
            break
    assert m.crushed and not m.success and m.rumble_s == 0.0
    # the shell gives way within milliseconds of full travel: the FSR's last word is its maximum
    assert m.peak_force_n == pytest.approx(Attachment().full_travel_force_n, rel=0.02)


def test_a_block_squeezed_past_full_travel_keeps_the_piston_bottomed_out():
    record = run_lab(REPO / "hri_lab" / "scenarios" / "squeeze.yaml", WorldConfig(object=OBJECTS["block"]),
                     CONFIG.params, CONFIG.limits, max_sensor_force=MAX)
    m = trial_metrics(record, TrialMeta("P01", "block", "feedback", 1), MAX)
    assert m.saturated_s > 2.0 and not m.crushed and m.lifted
    assert max(v for _, v in record.grip_force) > 10 * m.peak_force_n  # the housing, not the FSR, took it


@pytest.mark.parametrize("board_rate_hz", [3.333, 2.0])
def test_the_careful_participant_feels_each_tap_before_the_next_even_when_the_board_is_slow(board_rate_hz):
    """A tap's rumble comes 0.24-0.28 s later through the lab's nodes; the board's period (the handout
    firmware's 300 ms, or 500 ms) delays it as much as a stalled node on a busy PC does. At the old tap
    every 0.5 s, 2 of these 8 cracked the egg at 3.333 Hz and 4 at 2 Hz: one tap too many."""
    from dataclasses import replace

    from hri_teleop.sim.config import world_config_from_dict
    from hri_teleop.sim.operators import study_scenario
    from hri_teleop.sim.virtual_pad import parse_script

    params = replace(CONFIG.params, feedback=True)
    outcomes = []
    for seed in range(4):
        for quick in (True, False):
            data = study_scenario("feedback", seed, "egg", quick=quick)
            world = world_config_from_dict({**data["world"], "board": {"rate_hz": board_rate_hz}})
            record = run_lab(parse_script(data["steps"]), world, params, CONFIG.limits, max_sensor_force=MAX)
            outcomes.append((seed, quick, record.lifted, record.crushed))
    assert [o for o in outcomes if o[2:] != (True, False)] == []


def test_a_simulated_study_shows_feedback_lowers_the_squeeze():
    participants = ["P01", "P02", "P03", "P04", "P05", "P06"]
    metrics = []
    for i, p in enumerate(participants):
        for condition in ("feedback", "no_feedback"):
            metrics.append(_trial(condition, seed=100 + i, participant=p)[1])
    with_fb = per_participant(metrics, "peak_force_n", "feedback")
    without = per_participant(metrics, "peak_force_n", "no_feedback")
    result = paired_comparison([v for _, v in without], [v for _, v in with_fb])
    # Four of the six squeeze 7 taps in both conditions: the same compression, peaks apart by the
    # ADC's noise near 1.3 N (0.02 N, as in the study's end-to-end test); the median is one of those.
    assert result.n_pairs == 6 and result.median_difference >= -0.02
    assert sum(m.success for m in metrics if m.meta.condition == "feedback") == 6
    assert sum(m.success for m in metrics if m.meta.condition == "no_feedback") < 6


def test_the_study_figure_is_drawn_from_trials(tmp_path):
    from hri_teleop.plots.study import study_figure

    trials = []
    for i, p in enumerate(["P01", "P02", "P03"]):
        for condition in ("feedback", "no_feedback"):
            record, m = _trial(condition, seed=200 + i, participant=p)
            trials.append((m, record))
    png = study_figure(trials, MAX, tmp_path / "study.png")
    assert png.stat().st_size > 30_000


def test_a_trial_without_sensor_samples_is_named_in_the_error():
    from hri_teleop.core.run_record import LabRecord

    with pytest.raises(MetricsError, match="P07 trial 3"):
        trial_metrics(LabRecord(), TrialMeta("P07", "egg", "feedback", 3), 700)


@pytest.mark.parametrize("obj", ["egg", "sponge", "block"])
def test_a_quick_study_trial_grasps_as_the_full_one_in_half_the_time(obj):
    from hri_teleop.sim.config import world_config_from_dict
    from hri_teleop.sim.operators import study_scenario
    from hri_teleop.sim.virtual_pad import parse_script

    for condition, seed in (("feedback", 3), ("no_feedback", 0), ("no_feedback", 8), ("no_feedback", 1)):
        params = replace_params(feedback=(condition == "feedback"))
        runs = []
        for quick in (False, True):
            data = study_scenario(condition, seed, obj, quick=quick)
            assert data["world"]["object"] == obj
            runs.append(run_lab(parse_script(data["steps"]), world_config_from_dict(data["world"]), params,
                                CONFIG.limits, max_sensor_force=MAX))
        full, quick = runs
        assert (quick.lifted, quick.crushed) == (full.lifted, full.crushed), (condition, seed)
        assert max(v for _, v in quick.count) == pytest.approx(max(v for _, v in full.count), abs=3)
        assert quick.duration_s() < 0.5 * full.duration_s() and quick.violations == 0


def test_study_scenarios_refuse_an_object_outside_the_simulations_set():
    from hri_teleop.sim.operators import study_operator, study_scenario

    with pytest.raises(ValueError, match="not in the simulation's set; use one of block, egg"):
        study_scenario("feedback", 1, "cup")
    with pytest.raises(ValueError, match="skip_taps"):
        study_operator("no_feedback", 1, skip_taps=6)


def replace_params(**changes):
    from dataclasses import replace

    return replace(CONFIG.params, **changes)


def test_a_trial_seed_is_the_base_plus_1000_per_participant_plus_the_trial_number():
    assert trial_seed(0, 0, 1) == 1
    assert trial_seed(7, 2, 3) == 2010
    assert trial_seed(7, 0, 999) == 1006 and trial_seed(7, 1, 0) == 1007
    seed = trial_seed(7.0, 2.0, 3.0)  # a number read from a file is still a whole seed
    assert seed == 2010 and type(seed) is int
    assert trial_seed("7", "2", "3") == 2010


def test_the_plan_of_two_participants_is_crossed_over_and_rotated_trial_by_trial():
    plan = counterbalanced_plan(["P01", "P02"], ["egg", "sponge"], repetitions=2)
    assert [(m.participant, m.trial, m.condition, m.object_name) for m in plan] == [
        ("P01", 1, "feedback", "egg"), ("P01", 2, "feedback", "sponge"),
        ("P01", 3, "feedback", "egg"), ("P01", 4, "feedback", "sponge"),
        ("P01", 5, "no_feedback", "egg"), ("P01", 6, "no_feedback", "sponge"),
        ("P01", 7, "no_feedback", "egg"), ("P01", 8, "no_feedback", "sponge"),
        ("P02", 1, "no_feedback", "sponge"), ("P02", 2, "no_feedback", "egg"),
        ("P02", 3, "no_feedback", "sponge"), ("P02", 4, "no_feedback", "egg"),
        ("P02", 5, "feedback", "sponge"), ("P02", 6, "feedback", "egg"),
        ("P02", 7, "feedback", "sponge"), ("P02", 8, "feedback", "egg"),
    ]
    three = counterbalanced_plan(["A", "B", "C"], ["egg", "sponge", "block"])
    assert [(m.participant, m.condition, m.object_name) for m in three if m.trial <= 3] == [
        ("A", "feedback", "egg"), ("A", "feedback", "sponge"), ("A", "feedback", "block"),
        ("B", "no_feedback", "sponge"), ("B", "no_feedback", "block"), ("B", "no_feedback", "egg"),
        ("C", "feedback", "block"), ("C", "feedback", "egg"), ("C", "feedback", "sponge"),
    ]
    assert len(counterbalanced_plan(["A"], ["egg"], repetitions=1)) == 2
    assert [(m.trial, m.condition) for m in counterbalanced_plan(["A"], ["egg"])] == [(1, "feedback"),
                                                                                     (2, "no_feedback")]


@pytest.mark.parametrize("participants, objects, repetitions, message", [
    ([], ["egg"], 1, "participants must be distinct codes, got []; e.g. P01 P02 P03 P04"),
    (["P01", "P01"], ["egg"], 1, "participants must be distinct codes, got ['P01', 'P01']; e.g. P01 P02 P03 P04"),
    (["P01"], [], 1, "objects must be distinct names, got []; e.g. egg sponge"),
    (["P01"], ["egg", "egg"], 1, "objects must be distinct names, got ['egg', 'egg']; e.g. egg sponge"),
    (["P01"], ["egg"], 0, "repetitions must be at least 1, got 0"),
    (["P01"], ["egg"], -1, "repetitions must be at least 1, got -1"),
])
def test_a_plan_needs_distinct_participants_and_objects_and_one_repetition_or_more(participants, objects,
                                                                                   repetitions, message):
    with pytest.raises(MetricsError) as info:
        counterbalanced_plan(participants, objects, repetitions)
    assert str(info.value) == message


def test_the_plan_csv_lists_participant_trial_condition_object_in_a_new_folder(tmp_path):
    path = write_plan(counterbalanced_plan(["A", "B"], ["egg"]), tmp_path / "new" / "deeper" / "plan.csv")
    assert path == tmp_path / "new" / "deeper" / "plan.csv"
    assert path.read_bytes() == (b"participant,trial,condition,object\r\nA,1,feedback,egg\r\nA,2,no_feedback,egg\r\n"
                                 b"B,1,no_feedback,egg\r\nB,2,feedback,egg\r\n")


@pytest.mark.parametrize("text, cause", [
    ("participant,trial,condition\nA,1,feedback\n", "'object'"),
    ("participant,trial,condition,object\nA,one,feedback,egg\n", "invalid literal for int() with base 10: 'one'"),
    ("participant,trial,condition,object\nA,1,fb,egg\n", "condition must be one of feedback, no_feedback, got 'fb'"),
])
def test_a_file_that_is_not_a_plan_is_named_with_the_columns_it_needs(tmp_path, text, cause):
    path = tmp_path / "plan.csv"
    path.write_text(text)
    with pytest.raises(MetricsError) as info:
        read_plan(path)
    assert str(info.value) == f"{path}: not a trial plan ({cause}); columns are participant, trial, condition, object"


def test_a_plan_with_a_quoted_line_break_in_a_name_reads_back_whole(tmp_path):
    path = tmp_path / "plan.csv"
    path.write_bytes(b'participant,trial,condition,object\r\nA,1,feedback,"raw\r\negg"\r\n')
    assert read_plan(path) == [TrialMeta("A", "raw\r\negg", "feedback", 1)]


# -- the metrics on hand-made records (no simulation) ----------------------------------------------------

def _hand_record(counts, heights=(), rumble=(), lifted=True, crushed=False, **series):
    from hri_teleop.core.run_record import LabRecord

    return LabRecord(count=list(counts), object_height=list(heights), rumble=list(rumble), lifted=lifted,
                     crushed=crushed, **series)


HAND = TrialMeta("P07", "egg", "no_feedback", 3)


def test_contact_starts_above_1_percent_of_the_calibration_and_saturation_at_it():
    # calibrated at 700: contact above 7 counts, full travel at 700
    record = _hand_record([(2.0, 0.0), (3.0, 7.0), (4.0, 8.0), (5.0, 350.0), (6.0, 699.0), (7.0, 700.0),
                           (8.0, 701.0), (9.0, 0.0)])
    m = trial_metrics(record, HAND, 700)
    assert m.time_to_grasp_s == 2.0  # 8 counts at 4 s, 2 s after the first sample
    assert m.saturated_s == 2.0  # 700 and 701 held one second each; 699 is not full travel
    assert m.peak_force_n == pytest.approx(1.7805, abs=1e-4)  # 701 counts, above the calibration's 1.77 N
    # the mean over 8, 350, 699, 700 and 701 counts (0.0012, 0.2748, 1.7596, 1.77, 1.7805 N)
    assert m.mean_force_n == pytest.approx(1.1172, abs=1e-4)
    assert trial_metrics(_hand_record([(0.0, 7.0), (1.0, 7.0)]), HAND, 700).time_to_grasp_s is None
    assert trial_metrics(_hand_record([(0.0, 7.0), (1.0, 7.0)]), HAND, 700).mean_force_n == 0.0
    assert trial_metrics(_hand_record([(0.0, 7.0), (1.0, 8.0)]), HAND, 700).mean_force_n == pytest.approx(0.0012,
                                                                                                         abs=1e-4)


def test_a_contact_fraction_of_10_percent_starts_contact_above_70_counts_of_700():
    record = _hand_record([(0.0, 0.0), (1.0, 70.0), (2.0, 71.0), (3.0, 0.0)])
    assert trial_metrics(record, HAND, 700, contact_fraction=0.1).time_to_grasp_s == 2.0
    assert trial_metrics(record, HAND, 700).time_to_grasp_s == 1.0


def test_the_object_counts_as_lifted_above_5_mm_and_times_count_from_the_first_sample_of_any_series():
    record = _hand_record([(1.0, 0.0), (2.0, 350.0), (6.0, 0.0)],
                          heights=[(0.5, 0.0), (3.0, 0.005), (4.0, 0.0051), (7.0, 0.02)],
                          rumble=[(0.5, 0.0), (2.0, 0.3), (2.5, 0.0), (3.0, 0.2), (3.25, 0.0), (6.0, 0.0)])
    m = trial_metrics(record, HAND, 700)
    assert (m.time_to_grasp_s, m.time_to_lift_s, m.duration_s) == (1.5, 3.5, 6.5)
    assert m.rumble_s == 0.75  # 0.5 s at 0.3 and 0.25 s at 0.2; nothing at 0
    assert m.peak_force_n == pytest.approx(0.2748, abs=1e-4)
    assert trial_metrics(_hand_record([(0.0, 0.0), (1.0, 350.0)], heights=[(0.0, 0.0), (1.0, 0.005)]),
                         HAND, 700).time_to_lift_s is None
    assert trial_metrics(_hand_record([(0.0, 0.0), (1.0, 350.0)]), HAND, 700).time_to_lift_s is None


@pytest.mark.parametrize("lifted, crushed, outcome, expected", [
    (True, False, {}, (True, True, False)),
    (True, True, {}, (False, True, True)),
    (False, False, {}, (False, False, False)),
    (True, False, {"outcome_crushed": True}, (False, True, True)),
    (False, True, {"outcome_lifted": True, "outcome_crushed": False}, (True, True, False)),
    (True, False, {"outcome_lifted": False}, (False, False, False)),
    (True, True, {"outcome_lifted": 1, "outcome_crushed": 0}, (True, True, False)),
])
def test_success_is_lifted_and_not_crushed_by_the_experimenters_word_else_the_recordings(lifted, crushed, outcome,
                                                                                         expected):
    m = trial_metrics(_hand_record([(0.0, 0.0), (1.0, 350.0)], lifted=lifted, crushed=crushed), HAND, 700,
                      **outcome)
    assert (m.success, m.lifted, m.crushed) == expected
    assert type(m.lifted) is bool and type(m.crushed) is bool


def test_the_full_travel_force_given_replaces_the_attachments_and_the_score_is_kept_as_a_float():
    record = _hand_record([(0.0, 0.0), (1.0, 700.0), (2.0, 0.0)])
    assert trial_metrics(record, HAND, 700).peak_force_n == pytest.approx(1.77)
    m = trial_metrics(record, HAND, 700, full_travel_force_n=2, raw_tlx=45)
    assert m.peak_force_n == pytest.approx(2.0) and m.raw_tlx == 45.0 and type(m.raw_tlx) is float
    assert trial_metrics(record, HAND, 700).raw_tlx is None
    assert calibrated_force_n([700, 350], 700, 2)[0] == pytest.approx(2.0)
    assert calibrated_force_n([350], 700, 2)[0] == pytest.approx(0.3105, abs=1e-4)
    assert calibrated_force_n([350], 690)[0] == pytest.approx(0.2914, abs=1e-4)


def test_a_calibration_of_half_a_count_or_one_count_is_positive_and_reads_full_travel_there():
    assert calibrated_force_n([1], 1)[0] == pytest.approx(1.77)
    assert calibrated_force_n([0.5, 0], 0.5)[0] == pytest.approx(1.77)
    assert calibrated_force_n([0.001], 0.001)[0] == pytest.approx(1.77)


@pytest.mark.parametrize("value", [0, -1, 0.0, float("nan")])
def test_a_calibration_that_is_not_a_positive_count_is_refused(value):
    with pytest.raises(MetricsError) as info:
        calibrated_force_n([100], value)
    assert str(info.value) == f"max_sensor_force must be a positive count, got {value!r}; use the Ex. 11 value"


def test_a_trial_without_samples_says_which_and_what_to_check():
    with pytest.raises(MetricsError) as info:
        trial_metrics(_hand_record([]), HAND, 700)
    assert str(info.value) == ("P07 trial 3 (egg, no_feedback): no /pub_force samples recorded; "
                               "was the sensor board running?")
    assert info.value._render_traceback_() == ["MetricsError: P07 trial 3 (egg, no_feedback): no /pub_force samples "
                                               "recorded; was the sensor board running?"]


@pytest.mark.parametrize("participant, condition, message", [
    ("P01", "fb", "condition must be one of feedback, no_feedback, got 'fb'"),
    ("", "feedback", "participant code is empty; use a pseudonym such as P01"),
    ("  ", "feedback", "participant code is empty; use a pseudonym such as P01"),
])
def test_a_trial_needs_a_participant_code_and_one_of_the_two_conditions(participant, condition, message):
    with pytest.raises(MetricsError) as info:
        TrialMeta(participant, "egg", condition, 1)
    assert str(info.value) == message
    assert TrialMeta("0", "egg", "no_feedback", 1).label == "0 trial 1 (egg, no_feedback)"


def _m(participant, condition, peak, tlx=None):
    from hri_teleop.core.experiment.metrics import TrialMetrics

    return TrialMetrics(TrialMeta(participant, "egg", condition, 1), True, True, False, peak, 0.0, 0.0, None, None,
                        0.0, 1.0, tlx)


def test_each_participants_value_is_their_mean_in_the_condition_sorted_by_code_missing_values_skipped():
    metrics = [_m("P02", "feedback", 1.0, 30), _m("P01", "feedback", 2.0), _m("P02", "feedback", 2.0, 40),
               _m("P01", "no_feedback", 5.0, 50), _m("P03", "no_feedback", 1, 20)]
    assert per_participant(metrics, "peak_force_n", "feedback") == [("P01", 2.0), ("P02", 1.5)]
    assert per_participant(metrics, "peak_force_n", "no_feedback") == [("P01", 5.0), ("P03", 1.0)]
    assert per_participant(metrics, "raw_tlx", "feedback") == [("P02", 35.0)]
    assert all(type(v) is float for _, v in per_participant(metrics, "peak_force_n", "no_feedback"))


def test_pairs_are_the_participants_with_a_value_in_both_conditions_the_others_left_out():
    from hri_teleop.core.experiment.metrics import paired_by_participant

    metrics = [_m("P03", "feedback", 1.0, 30), _m("P03", "no_feedback", 4.0), _m("P01", "no_feedback", 5.0, 50),
               _m("P01", "feedback", 2.0, 20), _m("P02", "feedback", 3.0, 10)]
    assert paired_by_participant(metrics, "peak_force_n") == (["P01", "P03"], [5.0, 4.0], [2.0, 1.0], ["P02"])
    assert paired_by_participant(metrics, "raw_tlx") == (["P01"], [50.0], [20.0], ["P02", "P03"])
