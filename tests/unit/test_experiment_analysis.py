"""Ex. 14's analysis on simulated trials whose truth is known (lock-step runs, no ROS): metrics, rates,
the paired comparison, the questionnaire, the figure, and one-line errors for bad input."""

from __future__ import annotations

import csv
from dataclasses import replace
from pathlib import Path

import pytest

from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.experiment.analysis import (
    COLUMNS,
    LoadedTrial,
    analyse_trials,
    default_trials_folder,
)
from hri_teleop.core.experiment.metrics import MetricsError, TrialMeta
from hri_teleop.core.experiment.tlx import TlxRatings
from hri_teleop.plots.study import PANEL_TITLES, save_result_figure
from hri_teleop.ros.trial import analyse_folder
from hri_teleop.sim.config import world_config_from_dict
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.operators import study_scenario
from hri_teleop.sim.virtual_pad import parse_script

REPO = Path(__file__).resolve().parents[2]
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
_RUNS = {}


def _record(condition: str, seed: int, obj: str = "egg"):
    key = (condition, seed, obj)
    if key not in _RUNS:
        data = study_scenario(condition, seed, obj, quick=True)
        params = replace(CONFIG.params, feedback=(condition == "feedback"))
        _RUNS[key] = run_lab(parse_script(data["steps"]), world_config_from_dict(data["world"]), params,
                             CONFIG.limits, max_sensor_force=700)
    return _RUNS[key]


def _trial(participant: str, number: int, condition: str, seed: int, obj: str = "egg", **extra) -> LoadedTrial:
    sidecar = {"sim": True, "max_sensor_force": 700}
    sidecar.update(extra)
    return LoadedTrial(TrialMeta(participant, obj, condition, number), _record(condition, seed, obj), sidecar,
                       Path(f"trials/{participant}_t{number:02d}.yaml"))


def _study(seeds=(0, 8, 1)):
    """Participant i does both conditions with seed seeds[i] (0: 8 taps, crush; 8: 7 taps, lift; 1: 6, slip)."""
    trials = []
    for i, seed in enumerate(seeds):
        p = f"P{i + 1:02d}"
        order = ("feedback", "no_feedback") if i % 2 == 0 else ("no_feedback", "feedback")
        trials += [_trial(p, n, c, seed) for n, c in enumerate(order, 1)]
    return trials


def test_a_study_is_measured_compared_and_drawn(tmp_path):
    result = save_result_figure(analyse_trials(_study()), tmp_path / "study.png")
    assert [(m.meta.participant, m.meta.trial) for m in result.metrics] == [
        ("P01", 1), ("P01", 2), ("P02", 1), ("P02", 2), ("P03", 1), ("P03", 2)]
    for t, m in zip(result.trials, result.metrics):  # the simulation's word, measured from the FSR counts
        assert (m.lifted, m.crushed) == (t.record.lifted, t.record.crushed)
    by = {(m.meta.participant, m.meta.condition): m for m in result.metrics}
    assert by["P01", "no_feedback"].crushed and by["P01", "no_feedback"].peak_force_n == pytest.approx(1.77, abs=0.03)
    assert by["P02", "no_feedback"].success and by["P03", "no_feedback"].lifted is False
    assert all(by[p, "feedback"].success for p in ("P01", "P02", "P03"))
    rates = result.rates()
    assert rates["feedback"]["success_rate"] == 1.0 and rates["feedback"]["crush_rate"] == 0.0
    assert rates["no_feedback"]["success_rate"] == pytest.approx(1 / 3)
    assert rates["no_feedback"]["crush_rate"] == pytest.approx(1 / 3) and rates["no_feedback"]["trials"] == 3

    c = result.peak_force
    assert c is not None and c.n_pairs == 3 and "raw_tlx" not in result.comparisons
    diffs = sorted(by[p, "no_feedback"].peak_force_n - by[p, "feedback"].peak_force_n for p in ("P01", "P02", "P03"))
    assert c.median_difference == pytest.approx(diffs[1])
    crush = result.comparisons["crush_rate"]  # P01 crushed without feedback only: one discordant pair
    assert (crush.n_pairs, crush.n_nonzero, crush.w_plus, crush.w_minus) == (3, 1, 1.0, 0.0)
    assert crush.p_value == 1.0 and crush.rank_biserial == 1.0
    report = result.report()
    assert "Wilcoxon signed-rank, exact" in report and "symmetric about their median" in report
    assert "crush_rate (no feedback - feedback)" in report
    assert "feedback     3 trials: success 100%, crushed 0%" in report

    assert result.figure == tmp_path / "study.png" and result.figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert result.figure_panels == PANEL_TITLES

    rows = result.rows()
    assert list(rows[0]) == list(COLUMNS) and rows[0]["raw_tlx"] is None
    table = result.table().splitlines()
    assert table[0].split() == list(COLUMNS) and len(table) == 7
    with result.write_csv(tmp_path / "metrics.csv").open() as f:
        read = list(csv.DictReader(f))
    assert len(read) == 6 and read[1]["crushed"] == "True" and read[0]["time_to_lift_s"] != ""


def test_each_trial_is_converted_with_its_own_calibration():
    a = analyse_trials(_study((8, 8)))
    b = analyse_trials([t._replace(extra={**t.extra, "max_sensor_force": 650}) if t.meta.participant == "P01" else t
                        for t in _study((8, 8))])
    assert b.metrics[0].peak_force_n > a.metrics[0].peak_force_n  # same counts, lower full scale: more newtons
    assert b.metrics[2].peak_force_n == a.metrics[2].peak_force_n
    assert analyse_trials(_study((8, 8)), max_sensor_force=650).max_sensor_force == [650.0] * 4


def test_a_participant_in_one_condition_only_is_named_unless_left_out():
    trials = _study() + [_trial("P04", 1, "feedback", 3)]
    with pytest.raises(MetricsError, match=r"^P04 \(feedback only\): a paired comparison needs every participant"):
        analyse_trials(trials)
    result = analyse_trials(trials, allow_unpaired=True)
    assert result.left_out == ["P04"] and result.peak_force.n_pairs == 3 and len(result.metrics) == 7
    assert any("P04" in n for n in result.notes)


def test_too_few_pairs_is_a_note_not_a_crash():
    result = analyse_trials(_study((8,)))
    assert result.peak_force is None and any("at least 2 participants" in n for n in result.notes)


def test_lab_trials_need_the_experimenters_outcome_and_use_it():
    lab = [t._replace(extra={**t.extra, "sim": False}) for t in _study((8, 8))]
    with pytest.raises(MetricsError, match=r"P01_t01.yaml: a lab trial without the experimenter's outcome; .*outcome"):
        analyse_trials(lab)
    judged = [t._replace(extra={**t.extra, "outcome": {"lifted": False, "crushed": True}}) for t in lab]
    result = analyse_trials(judged)
    assert all(m.crushed and not m.success for m in result.metrics)
    bad = [judged[0]._replace(extra={**judged[0].extra, "outcome": {"lifted": "yes"}})] + judged[1:]
    with pytest.raises(MetricsError, match="P01_t01.yaml: outcome must be"):
        analyse_trials(bad)


def test_a_trial_without_a_calibration_or_twice_in_the_folder_is_named():
    trials = _study((8, 8))
    no_cal = [trials[0]._replace(extra={"sim": True})] + trials[1:]
    with pytest.raises(MetricsError, match="P01_t01.yaml: max_sensor_force is None, not a positive count"):
        analyse_trials(no_cal)
    twice = trials + [trials[0]._replace(sidecar=Path("old/P01_t01.yaml"))]
    with pytest.raises(MetricsError, match="both trial 1 of P01"):
        analyse_trials(twice)
    with pytest.raises(MetricsError, match="no trials to analyse"):
        analyse_trials([])


def test_the_questionnaire_is_carried_and_compared_when_every_pair_answered():
    scores = {("P01", "feedback"): 20, ("P01", "no_feedback"): 55, ("P02", "feedback"): 30,
              ("P02", "no_feedback"): 60, ("P03", "feedback"): 25, ("P03", "no_feedback"): 35}
    answered = [t._replace(extra={**t.extra, "tlx": TlxRatings(*(6 * [scores[t.meta.participant, t.meta.condition]]))
                                  .to_dict()}) for t in _study()]
    result = analyse_trials(answered)
    assert [m.raw_tlx for m in result.metrics] == [20, 55, 60, 30, 25, 35]
    tlx = result.comparisons["raw_tlx"]
    assert tlx.n_pairs == 3 and tlx.median_difference == 30 and tlx.rank_biserial == 1.0
    partly = answered[:-1] + [_study()[-1]]
    result = analyse_trials(partly)
    assert "raw_tlx" not in result.comparisons and any("raw TLX not compared" in n for n in result.notes)
    assert result.metrics[-1].raw_tlx is None


def test_a_missing_or_empty_folder_is_one_line_with_the_fix(tmp_path, monkeypatch):
    with pytest.raises(MetricsError, match=r"nowhere: no such folder of trials; record a session first .*rehearse"):
        analyse_folder(tmp_path / "nowhere")
    (tmp_path / "empty").mkdir()
    with pytest.raises(MetricsError, match=r"empty: no trials in this folder"):
        analyse_folder(tmp_path / "empty")
    monkeypatch.setenv("HRI_TRIALS", str(tmp_path / "mine"))
    assert default_trials_folder() == tmp_path / "mine"
    monkeypatch.delenv("HRI_TRIALS")
    assert default_trials_folder() == REPO / "trials"
