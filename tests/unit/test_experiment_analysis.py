"""Ex. 14's analysis on simulated trials whose truth is known (lock-step runs, no ROS): metrics, rates,
the paired comparison, the questionnaire, the figure, and one-line errors for bad input."""

from __future__ import annotations

import csv
import math
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
from hri_teleop.core.run_record import LabRecord
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


# Hand-made trials (no simulation): the FSR saw 0, the peak count, 100 and 0 at 10.0, 10.5, 11.0 and 12.0 s of
# a board calibrated at 700 counts; the object was 2 cm up from 11 s on if lifted; the pad rumbled 0.25 s.
# Peak forces through the FSR model: 300 -> 0.2046 N, 350 -> 0.2748, 400 -> 0.3618, 450 -> 0.4707,
# 500 -> 0.6085, 700 -> 1.77 (the full travel).
def _lab(peak_count: float, lifted: bool = True, crushed: bool = False) -> LabRecord:
    up = 0.02 if lifted else 0.0
    return LabRecord(count=[(10.0, 0.0), (10.5, float(peak_count)), (11.0, 100.0), (12.0, 0.0)],
                     object_height=[(10.0, 0.0), (11.0, up), (12.0, up)],
                     rumble=[(10.0, 0.0), (10.5, 0.4), (10.75, 0.0), (12.0, 0.0)], lifted=lifted, crushed=crushed)


def _hand(participant: str, number: int, condition: str, peak_count: float, lifted: bool = True,
          crushed: bool = False, **extra) -> LoadedTrial:
    sidecar = {"sim": True, "max_sensor_force": 700}
    sidecar.update(extra)
    return LoadedTrial(TrialMeta(participant, "egg", condition, number), _lab(peak_count, lifted, crushed), sidecar,
                       Path(f"trials/{participant}_t{number:02d}.yaml"))


def _hand_study():
    """P01 crushes the egg without feedback; everyone squeezes harder without it."""
    return [_hand("P01", 1, "feedback", 300), _hand("P01", 2, "no_feedback", 700, lifted=False, crushed=True),
            _hand("P02", 1, "no_feedback", 500), _hand("P02", 2, "feedback", 400),
            _hand("P03", 1, "feedback", 350), _hand("P03", 2, "no_feedback", 450)]


def _error(trials, **kwargs) -> str:
    with pytest.raises(MetricsError) as info:
        analyse_trials(trials, **kwargs)
    return str(info.value)


def test_the_report_gives_counts_rates_both_comparisons_the_assumptions_and_the_notes_word_for_word():
    result = analyse_trials(_hand_study(), folder=Path("trials"))
    assert result.report().splitlines() == [
        "6 trials, 3 participants (trials)",
        "  feedback     3 trials: success 100%, crushed 0%, mean peak force 0.28 N",
        "  no_feedback  3 trials: success 67%, crushed 33%, mean peak force 0.95 N",
        "peak_force_n (no feedback - feedback): median difference 0.247 over 3 pairs; Wilcoxon signed-rank, exact, "
        "two-sided: W+ = 6, W- = 0, p = 0.250 (n = 3 nonzero); rank-biserial r = +1.00",
        "crush_rate (no feedback - feedback): median difference 0 over 3 pairs; Wilcoxon signed-rank, exact, "
        "two-sided: W+ = 1, W- = 0, p = 1.000 (n = 1 nonzero); rank-biserial r = +1.00",
        "assumptions: pairs independent of each other (one pair per participant); differences at least ordinal; "
        "differences symmetric about their median; zero differences dropped, ties get mean ranks",
        "note: 1 crushed trial(s): a shell gives way within ~10 ms of the piston bottoming out and the force then "
        "drops, which a 100 Hz board sees at most once; their peak force is a lower bound of what the FSR felt",
    ]
    result.figure = Path("trials/study.png")
    assert result.report().splitlines()[-1] == "figure: trials/study.png"
    unnamed = analyse_trials(_hand_study())
    assert unnamed.folder is None and unnamed.report().splitlines()[0] == "6 trials, 3 participants"


def test_a_condition_without_trials_has_no_rates_and_no_line_in_the_report():
    result = analyse_trials([_hand("P01", 1, "feedback", 300), _hand("P02", 1, "feedback", 400, lifted=False)],
                            allow_unpaired=True)
    rates = result.rates()
    assert list(rates) == ["feedback", "no_feedback"]
    assert rates["feedback"] == {"trials": 2.0, "success_rate": 0.5, "lift_rate": 0.5, "crush_rate": 0.0,
                                 "mean_peak_force_n": pytest.approx((0.2046 + 0.3618) / 2, abs=1e-4)}
    assert rates["no_feedback"]["trials"] == 0.0
    assert all(math.isnan(rates["no_feedback"][k])
               for k in ("success_rate", "lift_rate", "crush_rate", "mean_peak_force_n"))
    assert result.report().splitlines()[:2] == [
        "2 trials, 2 participants", "  feedback     2 trials: success 50%, crushed 0%, mean peak force 0.28 N"]
    assert result.report().splitlines()[2] == ("note: left out of the paired comparison: P01 (feedback only), "
                                               "P02 (feedback only)")


def test_the_rates_count_success_lifts_and_crushes_per_condition():
    trials = [_hand("P01", 1, "feedback", 300), _hand("P01", 2, "no_feedback", 700, lifted=True, crushed=True),
              _hand("P02", 1, "no_feedback", 500, lifted=False), _hand("P02", 2, "feedback", 400),
              _hand("P03", 1, "feedback", 350, lifted=False), _hand("P03", 2, "no_feedback", 450),
              _hand("P04", 1, "no_feedback", 450), _hand("P04", 2, "feedback", 450)]
    rates = analyse_trials(trials).rates()
    assert rates["feedback"] == {"trials": 4.0, "success_rate": 0.75, "lift_rate": 0.75, "crush_rate": 0.0,
                                 "mean_peak_force_n": pytest.approx((0.2046 + 0.3618 + 0.2748 + 0.4707) / 4,
                                                                    abs=1e-4)}
    assert rates["no_feedback"] == {"trials": 4.0, "success_rate": 0.5, "lift_rate": 0.75, "crush_rate": 0.25,
                                    "mean_peak_force_n": pytest.approx((1.77 + 0.6085 + 0.4707 + 0.4707) / 4,
                                                                       abs=1e-4)}


def test_the_rows_round_floats_to_4_decimals_and_keep_none_for_what_did_not_happen():
    rows = analyse_trials(_hand_study()).rows()
    assert rows[1] == {"participant": "P01", "trial": 2, "object": "egg", "condition": "no_feedback",
                       "success": False, "lifted": False, "crushed": True, "peak_force_n": 1.77,
                       "mean_force_n": 0.9027, "saturated_s": 0.5, "time_to_grasp_s": 0.5, "time_to_lift_s": None,
                       "rumble_s": 0.25, "duration_s": 2.0, "raw_tlx": None}
    assert [r["peak_force_n"] for r in rows] == [0.2046, 1.77, 0.6085, 0.3618, 0.2748, 0.4707]
    assert [r["mean_force_n"] for r in rows] == [0.12, 0.9027, 0.3219, 0.1986, 0.1551, 0.2531]
    assert [r["time_to_lift_s"] for r in rows] == [1.0, None, 1.0, 1.0, 1.0, 1.0]


def test_the_table_says_yes_no_and_dash_with_two_decimals_in_columns_two_spaces_apart():
    table = analyse_trials(_hand_study()[:2], allow_unpaired=True).table()
    assert table.splitlines() == [
        "participant  trial  object  condition    success  lifted  crushed  peak_force_n  mean_force_n  saturated_s  "
        "time_to_grasp_s  time_to_lift_s  rumble_s  duration_s  raw_tlx",
        "P01          1      egg     feedback     yes      yes     no       0.20          0.12          0.00         "
        "0.50             1.00            0.25      2.00        -      ",
        "P01          2      egg     no_feedback  no       no      yes      1.77          0.90          0.50         "
        "0.50             -               0.25      2.00        -      ",
    ]
    long = analyse_trials([_hand("Participant-0001", 1, "feedback", 300)], allow_unpaired=True).table().splitlines()
    assert long[0].startswith("participant       trial  ") and long[1].startswith("Participant-0001  1      ")


def test_the_csv_has_the_columns_and_an_empty_cell_for_none_in_a_new_folder(tmp_path):
    path = analyse_trials(_hand_study()[:2], allow_unpaired=True).write_csv(tmp_path / "new" / "deeper" / "m.csv")
    assert path == tmp_path / "new" / "deeper" / "m.csv"
    assert path.read_text().splitlines() == [
        "participant,trial,object,condition,success,lifted,crushed,peak_force_n,mean_force_n,saturated_s,"
        "time_to_grasp_s,time_to_lift_s,rumble_s,duration_s,raw_tlx",
        "P01,1,egg,feedback,True,True,False,0.2046,0.12,0.0,0.5,1.0,0.25,2.0,",
        "P01,2,egg,no_feedback,False,False,True,1.77,0.9027,0.5,0.5,,0.25,2.0,",
    ]


def test_the_trials_are_ordered_by_participant_then_trial_number_whatever_the_folders_order():
    shuffled = [_hand("P02", 2, "feedback", 400), _hand("P01", 2, "no_feedback", 450), _hand("P02", 1, "no_feedback",
                                                                                              500),
                _hand("P01", 1, "feedback", 300)]
    result = analyse_trials(shuffled)
    assert [(t.meta.participant, t.meta.trial) for t in result.trials] == [("P01", 1), ("P01", 2), ("P02", 1),
                                                                           ("P02", 2)]
    assert [m.peak_force_n for m in result.metrics] == pytest.approx([0.2046, 0.4707, 0.6085, 0.3618], abs=1e-4)


@pytest.mark.parametrize("value", [0, -5, 0.0, True, "700", None])
def test_a_sidecar_calibration_that_is_not_a_positive_count_is_refused_naming_the_file(value):
    trials = _hand_study()
    trials[2] = trials[2]._replace(extra={"sim": True, "max_sensor_force": value})
    assert _error(trials) == (f"trials/P02_t01.yaml: max_sensor_force is {value!r}, not a positive count; add the "
                              "session's Ex. 11 value to the file (max_sensor_force: 690) or pass max_sensor_force=")


def test_a_calibration_of_one_count_is_positive_and_read_as_a_float():
    trials = [t._replace(extra={**t.extra, "max_sensor_force": 1}) for t in _hand_study()[:2]]
    result = analyse_trials(trials, allow_unpaired=True)
    assert result.max_sensor_force == [1.0, 1.0] and all(type(v) is float for v in result.max_sensor_force)
    assert [m.saturated_s for m in result.metrics] == [1.5, 1.5]  # every count of 1 or more is full travel
    overridden = analyse_trials([t._replace(extra={"sim": True}) for t in _hand_study()], max_sensor_force=650)
    assert overridden.max_sensor_force == [650.0] * 6 and all(type(v) is float for v in overridden.max_sensor_force)
    assert overridden.metrics[1].saturated_s == 0.5  # 700 counts of a board calibrated at 650


def test_without_a_sim_flag_or_an_outcome_the_recordings_word_is_taken():
    trials = [t._replace(extra={"max_sensor_force": 700}) for t in _hand_study()]
    result = analyse_trials(trials)
    assert [(m.lifted, m.crushed, m.success) for m in result.metrics[:2]] == [(True, False, True),
                                                                              (False, True, False)]


def test_a_lab_trial_without_an_outcome_says_how_to_enter_it():
    trials = _hand_study()
    trials[3] = trials[3]._replace(extra={**trials[3].extra, "sim": False})
    assert _error(trials) == ("trials/P02_t02.yaml: a lab trial without the experimenter's outcome; enter it with "
                              "`python -m hri_teleop.apps.trial outcome trials/P02_t02.yaml --lifted yes --crushed no`")


@pytest.mark.parametrize("outcome", [{"lifted": True}, {"crushed": False}, {"lifted": True, "crushed": "no"},
                                     {"lifted": 1, "crushed": False}, "lifted", ["lifted", "crushed"]])
def test_an_outcome_without_both_words_as_true_or_false_is_refused(outcome):
    trials = _hand_study()
    trials[0] = trials[0]._replace(extra={**trials[0].extra, "sim": False, "outcome": outcome})
    assert _error(trials) == ("trials/P01_t01.yaml: outcome must be {lifted: true|false, crushed: true|false}, got "
                              f"{outcome!r}; enter it again with `python -m hri_teleop.apps.trial outcome`")


def test_the_experimenters_outcome_overrides_the_recording_lifted_and_crushed_each_in_its_place():
    trials = _hand_study()
    trials[1] = trials[1]._replace(extra={**trials[1].extra, "outcome": {"lifted": True, "crushed": False}})
    trials[0] = trials[0]._replace(extra={**trials[0].extra, "sim": False,
                                          "outcome": {"lifted": False, "crushed": True}})
    result = analyse_trials(trials)
    assert [(m.lifted, m.crushed, m.success) for m in result.metrics[:2]] == [(False, True, False),
                                                                              (True, False, True)]
    assert result.comparisons["crush_rate"].w_minus == 1.0  # P01 crushed with feedback only now


def test_a_trial_that_cannot_be_measured_is_named_by_its_sidecar():
    trials = _hand_study()
    trials[4] = trials[4]._replace(record=LabRecord())
    assert _error(trials) == ("trials/P03_t01.yaml: P03 trial 1 (egg, feedback): no /pub_force samples recorded; "
                              "was the sensor board running?")


def test_no_trials_or_one_trial_twice_is_one_line_with_the_fix():
    assert _error([]) == "no trials to analyse; record some first (python -m hri_teleop.apps.trial rehearse)"
    trials = _hand_study() + [_hand("P02", 2, "feedback", 300)._replace(sidecar=Path("old/P02_t02.yaml"))]
    assert _error(trials) == ("old/P02_t02.yaml and trials/P02_t02.yaml are both trial 2 of P02; "
                              "move one of them out of the folder")
    same_number = _hand_study() + [_hand("P04", 2, "feedback", 300), _hand("P04", 1, "no_feedback", 300)]
    assert len(analyse_trials(same_number).metrics) == 8  # trial 2 of P04 is not trial 2 of P02


def test_every_participant_in_one_condition_only_is_named_with_that_condition():
    trials = _hand_study() + [_hand("P04", 1, "feedback", 300), _hand("P05", 1, "no_feedback", 300),
                              _hand("P05", 2, "no_feedback", 400)]
    assert _error(trials) == ("P04 (feedback only), P05 (no_feedback only): a paired comparison needs every "
                              "participant in both conditions; record the missing trials, or leave them out of the "
                              "test with allow_unpaired=True (--allow-unpaired)")
    result = analyse_trials(trials, allow_unpaired=True)
    assert result.left_out == ["P04", "P05"] and result.peak_force.n_pairs == 3
    assert result.notes[0] == "left out of the paired comparison: P04 (feedback only), P05 (no_feedback only)"
    assert analyse_trials(_hand_study(), allow_unpaired=True).left_out == []


def _answered(trial: LoadedTrial, score: int) -> LoadedTrial:
    return trial._replace(extra={**trial.extra, "tlx": TlxRatings(*(6 * [score])).to_dict()})


def test_one_pair_is_compared_by_nothing_and_each_comparison_says_why():
    result = analyse_trials([_answered(_hand("P01", 1, "feedback", 300), 20),
                             _answered(_hand("P01", 2, "no_feedback", 450), 45)])
    assert result.comparisons == {} and result.metrics[1].raw_tlx == 45.0
    assert result.notes == [
        "peak force not compared: 1 pair(s) cannot be compared; a paired test needs at least 2 participants",
        "crush rate not compared: 1 pair(s) cannot be compared; a paired test needs at least 2 participants",
        "raw TLX not compared: 1 pair(s) cannot be compared; a paired test needs at least 2 participants",
    ]


def test_the_questionnaire_is_compared_only_when_every_paired_participant_answered_both():
    scores = {"P01": (20, 55), "P02": (30, 40), "P03": (25, 35)}  # (feedback, no feedback)
    trials = [_answered(t, scores[t.meta.participant][t.meta.condition == "no_feedback"]) for t in _hand_study()]
    tlx = analyse_trials(trials).comparisons["raw_tlx"]
    assert (tlx.n_pairs, tlx.median_difference, tlx.w_plus, tlx.w_minus) == (3, 10.0, 6.0, 0.0)
    result = analyse_trials(trials[:5] + [_hand_study()[5]])
    assert "raw_tlx" not in result.comparisons and result.notes[-1] == (
        "raw TLX not compared: answered in both conditions by 2 of 3 participants; fill in the missing questionnaires")
    none = analyse_trials(_hand_study())
    assert "raw_tlx" not in none.comparisons and not any("TLX" in n for n in none.notes)


def test_the_comparisons_are_no_feedback_minus_feedback():
    result = analyse_trials(_hand_study())
    peak = result.peak_force
    assert peak is result.comparisons["peak_force_n"]
    assert (peak.n_pairs, peak.w_plus, peak.w_minus) == (3, 6.0, 0.0)
    assert peak.median_difference == pytest.approx(0.6085 - 0.3618, abs=1e-4)
    crush = result.comparisons["crush_rate"]
    assert (crush.n_pairs, crush.n_nonzero, crush.w_plus, crush.w_minus, crush.median_difference) == (3, 1, 1.0, 0.0,
                                                                                                     0.0)


def test_a_blank_hri_trials_means_the_checkouts_folder(monkeypatch):
    monkeypatch.setenv("HRI_TRIALS", "  ")
    assert default_trials_folder() == REPO / "trials"
    monkeypatch.setenv("HRI_TRIALS", " /data/trials ")
    assert default_trials_folder() == Path("/data/trials")


def test_a_questionnaire_off_the_scale_is_named_by_its_sidecar():
    trials = _hand_study()
    trials[0] = _answered(trials[0], 20)._replace(extra={**trials[0].extra, "tlx": {
        "mental": 41, "physical": 0, "temporal": 0, "performance": 0, "effort": 0, "frustration": 0}})
    assert _error(trials) == "trials/P01_t01.yaml: TLX mental is 41; rate 0..100 in steps of 5 (0, 5, ..., 100)"


def test_one_trial_is_measured_with_its_sidecars_calibration_unless_one_is_given_and_a_missing_one_named_once():
    from hri_teleop.core.experiment.analysis import measure_trial

    trial = _hand("P01", 1, "feedback", 350, max_sensor_force=350)
    assert measure_trial(trial).saturated_s == 0.5 and measure_trial(trial).peak_force_n == pytest.approx(1.77)
    assert measure_trial(trial, 700).saturated_s == 0.0
    assert measure_trial(trial, 700).peak_force_n == pytest.approx(0.2748, abs=1e-4)
    with pytest.raises(MetricsError) as info:
        measure_trial(trial._replace(extra={"sim": True}))
    assert str(info.value) == ("trials/P01_t01.yaml: max_sensor_force is None, not a positive count; add the "
                               "session's Ex. 11 value to the file (max_sensor_force: 690) or pass max_sensor_force=")
