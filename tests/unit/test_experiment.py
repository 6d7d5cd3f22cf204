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
