"""Ex. 14's analysis: a folder of recorded trials in, metrics, rates, the paired test and the figure out.

The analysis notebook, ``python -m hri_teleop.apps.trial analyse`` and the tests must compute the
same numbers, so the notebook only calls :func:`analyse_trials` and reads its
:class:`StudyResult`. What counts as success and how participants are paired: docs/experiment.md.
Pure: reading a folder of bags is :func:`hri_teleop.ros.trial.analyse_folder`'s (rosbag).
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

from hri_teleop.core.experiment.metrics import (
    CONDITIONS,
    MetricsError,
    TrialMeta,
    TrialMetrics,
    paired_by_participant,
    trial_metrics,
)
from hri_teleop.core.experiment.stats import PairedComparison, StatsError, paired_comparison
from hri_teleop.core.experiment.tlx import optional_tlx
from hri_teleop.core.paths import TRIALS
from hri_teleop.core.run_record import LabRecord

__all__ = ["LoadedTrial", "StudyResult", "COLUMNS", "default_trials_folder", "measure_trial", "analyse_trials",
           "FIGURE_NAME", "CSV_NAME"]

#: File names the analysis writes into the trials folder by default.
FIGURE_NAME = "study.png"
CSV_NAME = "metrics.csv"

#: The per-trial table's columns (units in the names), in order.
COLUMNS = ("participant", "trial", "object", "condition", "success", "lifted", "crushed", "peak_force_n",
           "mean_force_n", "saturated_s", "time_to_grasp_s", "time_to_lift_s", "rumble_s", "duration_s", "raw_tlx")


class LoadedTrial(NamedTuple):
    """One recorded trial: metadata, what the bag holds, the sidecar's other keys, the sidecar's path."""

    meta: TrialMeta
    record: LabRecord
    extra: Dict[str, Any]
    sidecar: Path


def default_trials_folder() -> Path:
    """Where the analysis looks by default: ``$HRI_TRIALS``, else ``trials/`` in the checkout (the rehearsal's)."""
    env = os.environ.get("HRI_TRIALS", "").strip()
    return Path(env) if env else TRIALS


def _calibration(trial: LoadedTrial, override: Optional[float]) -> float:
    if override is not None:
        return float(override)
    value = trial.extra.get("max_sensor_force")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise MetricsError(f"{trial.sidecar}: max_sensor_force is {value!r}, not a positive count; add the "
                           "session's Ex. 11 value to the file (max_sensor_force: 690) or pass max_sensor_force=")
    return float(value)


def _outcome(trial: LoadedTrial) -> Tuple[Optional[bool], Optional[bool]]:
    outcome = trial.extra.get("outcome")
    if outcome is None:
        if trial.extra.get("sim") is False:
            raise MetricsError(f"{trial.sidecar}: a lab trial without the experimenter's outcome; enter it with "
                               f"`python -m hri_teleop.apps.trial outcome {trial.sidecar} --lifted yes --crushed no`")
        return None, None
    if not isinstance(outcome, Mapping) or not all(isinstance(outcome.get(k), bool) for k in ("lifted", "crushed")):
        raise MetricsError(f"{trial.sidecar}: outcome must be {{lifted: true|false, crushed: true|false}}, got "
                           f"{outcome!r}; enter it again with `python -m hri_teleop.apps.trial outcome`")
    return bool(outcome["lifted"]), bool(outcome["crushed"])


def measure_trial(trial: LoadedTrial, max_sensor_force: Optional[float] = None) -> TrialMetrics:
    """The metrics of one loaded trial, with its calibration, outcome and questionnaire from the sidecar."""
    lifted, crushed = _outcome(trial)
    tlx = optional_tlx(trial.extra, str(trial.sidecar))
    calibration = _calibration(trial, max_sensor_force)  # its error names the sidecar already
    try:
        return trial_metrics(trial.record, trial.meta, calibration,
                             outcome_lifted=lifted, outcome_crushed=crushed,
                             raw_tlx=None if tlx is None else tlx.raw_tlx)
    except MetricsError as exc:
        raise MetricsError(f"{trial.sidecar}: {exc}") from None


def _rounded(value: Any) -> Any:
    return round(value, 4) if isinstance(value, float) else value


@dataclass
class StudyResult:
    """What :func:`analyse_trials` found: per-trial metrics, rates per condition, the paired comparisons."""

    trials: List[LoadedTrial]
    metrics: List[TrialMetrics]
    max_sensor_force: List[float]
    #: value name -> paired comparison (no feedback minus feedback); ``peak_force_n`` is the primary one.
    comparisons: Dict[str, PairedComparison] = field(default_factory=dict)
    #: participants left out of the paired comparison (trials in one condition only)
    left_out: List[str] = field(default_factory=list)
    #: why something was not computed, in words
    notes: List[str] = field(default_factory=list)
    figure: Optional[Path] = None
    figure_panels: Tuple[str, ...] = ()
    folder: Optional[Path] = None

    @property
    def peak_force(self) -> Optional[PairedComparison]:
        """The primary comparison: peak grasp force, no feedback minus feedback (None if not computed)."""
        return self.comparisons.get("peak_force_n")

    def rows(self) -> List[Dict[str, Any]]:
        """One dict per trial with :data:`COLUMNS` (None: did not happen / not asked)."""
        out = []
        for m in self.metrics:
            row: Dict[str, Any] = {"participant": m.meta.participant, "trial": m.meta.trial,
                                   "object": m.meta.object_name, "condition": m.meta.condition}
            for key in COLUMNS[4:]:
                row[key] = _rounded(getattr(m, key))
            out.append(row)
        return out

    def table(self) -> str:
        """The per-trial metrics as an aligned text table."""
        def cell(v: Any) -> str:
            if v is None:
                return "-"
            if isinstance(v, bool):
                return "yes" if v else "no"
            if isinstance(v, float):
                return f"{v:.2f}"
            return str(v)

        rows = [[cell(r[c]) for c in COLUMNS] for r in self.rows()]
        widths = [max([len(c)] + [len(r[i]) for r in rows]) for i, c in enumerate(COLUMNS)]
        lines = ["  ".join(c.ljust(w) for c, w in zip(COLUMNS, widths))]
        lines += ["  ".join(v.ljust(w) for v, w in zip(r, widths)) for r in rows]
        return "\n".join(lines)

    def rates(self) -> Dict[str, Dict[str, float]]:
        """Per condition: trials, success_rate, lift_rate, crush_rate (0..1), mean peak_force_n."""
        out: Dict[str, Dict[str, float]] = {}
        for c in CONDITIONS:
            group = [m for m in self.metrics if m.meta.condition == c]
            n = len(group)
            out[c] = {
                "trials": float(n),
                "success_rate": sum(m.success for m in group) / n if n else float("nan"),
                "lift_rate": sum(m.lifted for m in group) / n if n else float("nan"),
                "crush_rate": sum(m.crushed for m in group) / n if n else float("nan"),
                "mean_peak_force_n": sum(m.peak_force_n for m in group) / n if n else float("nan"),
            }
        return out

    def report(self) -> str:
        """Rates, the paired comparison(s) with their assumptions, and the notes, as text."""
        lines = [f"{len(self.metrics)} trials, {len({m.meta.participant for m in self.metrics})} participants"
                 + (f" ({self.folder})" if self.folder else "")]
        for c, r in self.rates().items():
            if r["trials"]:
                lines.append(f"  {c:<12} {int(r['trials'])} trials: success {r['success_rate']:.0%}, "
                             f"crushed {r['crush_rate']:.0%}, mean peak force {r['mean_peak_force_n']:.2f} N")
        for name, comparison in self.comparisons.items():
            lines.append(comparison.describe(f"{name} (no feedback - feedback)"))
        if self.comparisons:
            lines.append("assumptions: " + next(iter(self.comparisons.values())).assumptions)
        lines += [f"note: {n}" for n in self.notes]
        if self.figure is not None:
            lines.append(f"figure: {self.figure}")
        return "\n".join(lines)

    def write_csv(self, path: Union[str, Path]) -> Path:
        """The per-trial table as CSV (empty cells for None)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(COLUMNS))
            writer.writeheader()
            for row in self.rows():
                writer.writerow({k: "" if v is None else v for k, v in row.items()})
        return path


def _unpaired_names(metrics: Sequence[TrialMetrics], left_out: Sequence[str]) -> str:
    parts = []
    for p in left_out:
        conditions = sorted({m.meta.condition for m in metrics if m.meta.participant == p})
        parts.append(f"{p} ({' and '.join(conditions)} only)")
    return ", ".join(parts)


def _unpaired_message(metrics: Sequence[TrialMetrics], left_out: Sequence[str]) -> str:
    return (f"{_unpaired_names(metrics, left_out)}: a paired comparison needs every participant in both conditions; "
            "record the missing trials, or leave them out of the test with allow_unpaired=True (--allow-unpaired)")


def analyse_trials(trials: Sequence[LoadedTrial], *, max_sensor_force: Optional[float] = None,
                   allow_unpaired: bool = False, folder: Optional[Path] = None) -> StudyResult:
    """Measure and compare the trials (docs/experiment.md); :func:`hri_teleop.plots.study.save_result_figure` draws.

    ``max_sensor_force`` overrides every trial's stored calibration (count at full travel).
    """
    if not trials:
        raise MetricsError("no trials to analyse; record some first (python -m hri_teleop.apps.trial rehearse)")
    seen: Dict[Tuple[str, int], Path] = {}
    for t in trials:
        key = (t.meta.participant, t.meta.trial)
        if key in seen:
            raise MetricsError(f"{t.sidecar} and {seen[key]} are both trial {t.meta.trial} of {t.meta.participant}; "
                               "move one of them out of the folder")
        seen[key] = t.sidecar
    ordered = sorted(trials, key=lambda t: (t.meta.participant, t.meta.trial))
    calibrations = [_calibration(t, max_sensor_force) for t in ordered]
    metrics = [measure_trial(t, c) for t, c in zip(ordered, calibrations)]
    result = StudyResult(trials=list(ordered), metrics=metrics, max_sensor_force=calibrations, folder=folder)

    both, without, with_fb, left_out = paired_by_participant(metrics, "peak_force_n")
    if left_out and not allow_unpaired:
        raise MetricsError(_unpaired_message(metrics, left_out))
    result.left_out = left_out
    if left_out:
        result.notes.append(f"left out of the paired comparison: {_unpaired_names(metrics, left_out)}")
    crushed = [m for m in metrics if m.crushed]
    if crushed:
        result.notes.append(f"{len(crushed)} crushed trial(s): a shell gives way within ~10 ms of the piston bottoming "
                            "out and the force then drops, which a 100 Hz board sees at most once; their peak force "
                            "is a lower bound of what the FSR felt")
    try:
        result.comparisons["peak_force_n"] = paired_comparison(without, with_fb)
    except StatsError as exc:
        result.notes.append(f"peak force not compared: {exc}")
    # The crush rate carries the effect where the FSR saturates (1.77 N at full travel). With
    # one trial per condition the differences are -1, 0 or +1, all tied, and the exact
    # signed-rank test reduces to the exact sign test on the discordant pairs (McNemar's).
    _c_both, crush_without, crush_with, _c_left = paired_by_participant(metrics, "crushed")
    try:
        result.comparisons["crush_rate"] = paired_comparison(crush_without, crush_with)
    except StatsError as exc:
        result.notes.append(f"crush rate not compared: {exc}")
    answered = [m for m in metrics if m.raw_tlx is not None]
    if answered:
        t_both, t_without, t_with, _ = paired_by_participant(answered, "raw_tlx")
        if set(t_both) != set(both):
            result.notes.append(f"raw TLX not compared: answered in both conditions by {len(t_both)} of "
                                f"{len(both)} participants; fill in the missing questionnaires")
        else:
            try:
                result.comparisons["raw_tlx"] = paired_comparison(t_without, t_with)
            except StatsError as exc:
                result.notes.append(f"raw TLX not compared: {exc}")
    return result
