"""Per-trial numbers of the force-feedback experiment, from what a trial recorded.

The analysis notebook, the recording command's summary and the tests must agree on what "peak
grasp force" or "time to grasp" means; :func:`trial_metrics` is that definition, written out in
docs/experiment.md (force through the FSR model and the trial's own calibration).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from hri_teleop.core import fsr
from hri_teleop.core.attachment import Attachment
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.run_record import LIFTED_M, LabRecord, time_above

__all__ = ["MetricsError", "TrialMeta", "TrialMetrics", "CONDITIONS", "calibrated_force_n", "trial_metrics",
           "per_participant", "paired_by_participant"]

#: The experiment's two conditions: the pad rumbles with the force, or never.
CONDITIONS = ("feedback", "no_feedback")


class MetricsError(HriTeleopError, ValueError):
    """A trial cannot be measured (the message names the trial and what is missing)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


@dataclass(frozen=True)
class TrialMeta:
    """Who did what: the trial's metadata, stored with its recording."""

    participant: str
    object_name: str
    condition: str
    trial: int

    def __post_init__(self) -> None:
        if self.condition not in CONDITIONS:
            raise MetricsError(f"condition must be one of {', '.join(CONDITIONS)}, got {self.condition!r}")
        if not str(self.participant).strip():
            raise MetricsError("participant code is empty; use a pseudonym such as P01")

    @property
    def label(self) -> str:
        return f"{self.participant} trial {self.trial} ({self.object_name}, {self.condition})"


@dataclass(frozen=True)
class TrialMetrics:
    """One trial's results (forces in N, times in s; None: did not happen)."""

    meta: TrialMeta
    success: bool
    lifted: bool
    crushed: bool
    peak_force_n: float
    mean_force_n: float
    saturated_s: float
    time_to_grasp_s: Optional[float]
    time_to_lift_s: Optional[float]
    rumble_s: float
    duration_s: float
    raw_tlx: Optional[float] = None  # the participant's raw NASA-TLX after the trial (0..100), if asked


def calibrated_force_n(counts: npt.ArrayLike, max_sensor_force: float,
                       full_travel_force_n: Optional[float] = None) -> npt.NDArray[np.float64]:
    """FSR force (N) of each count, scaled so that ``max_sensor_force`` reads ``full_travel_force_n``."""
    if not max_sensor_force > 0:
        raise MetricsError(f"max_sensor_force must be a positive count, got {max_sensor_force!r}; use the Ex. 11 value")
    full = Attachment().full_travel_force_n if full_travel_force_n is None else float(full_travel_force_n)
    scale = full / float(fsr.count_to_force(float(max_sensor_force)))
    values = np.asarray(counts, dtype=float)
    return np.asarray(fsr.count_to_force(values), dtype=float) * scale


def _first_time(series: Sequence[Tuple[float, float]], above: float) -> Optional[float]:
    for t, v in series:
        if v > above:
            return t
    return None


def trial_metrics(record: LabRecord, meta: TrialMeta, max_sensor_force: float, *,
                  contact_fraction: float = 0.01, full_travel_force_n: Optional[float] = None,
                  outcome_lifted: Optional[bool] = None, outcome_crushed: Optional[bool] = None,
                  raw_tlx: Optional[float] = None) -> TrialMetrics:
    """The metrics of one trial (their definitions: docs/experiment.md).

    ``outcome_lifted``/``outcome_crushed``: the experimenter's judgement in the lab, where
    no sensor sees the object; None takes the simulation's word from ``record``.
    ``raw_tlx``: the workload score stored with the trial (:mod:`hri_teleop.core.experiment.tlx`).
    """
    if not record.count:
        raise MetricsError(f"{meta.label}: no /pub_force samples recorded; was the sensor board running?")
    start = record.start_s()
    times = np.array([t for t, _ in record.count])
    counts = np.array([v for _, v in record.count])
    force = calibrated_force_n(counts, max_sensor_force, full_travel_force_n)
    contact = counts > contact_fraction * max_sensor_force
    saturated = [(t, 1.0 if c >= max_sensor_force else 0.0) for t, c in zip(times, counts)]
    first_contact = _first_time(list(zip(times, counts)), contact_fraction * max_sensor_force)
    first_lift = _first_time(record.object_height, LIFTED_M) if record.object_height else None
    lifted = record.lifted if outcome_lifted is None else bool(outcome_lifted)
    crushed = record.crushed if outcome_crushed is None else bool(outcome_crushed)
    return TrialMetrics(
        meta=meta,
        success=lifted and not crushed,
        lifted=lifted,
        crushed=crushed,
        peak_force_n=float(force.max()),
        mean_force_n=float(force[contact].mean()) if contact.any() else 0.0,
        saturated_s=time_above(saturated, 0.5),
        time_to_grasp_s=None if first_contact is None else float(first_contact - start),
        time_to_lift_s=None if first_lift is None else float(first_lift - start),
        rumble_s=time_above(record.rumble, 0.0),
        duration_s=record.duration_s(),
        raw_tlx=None if raw_tlx is None else float(raw_tlx),
    )


def per_participant(metrics: Sequence[TrialMetrics], value: str, condition: str) -> List[Tuple[str, float]]:
    """(participant, mean of ``value`` over their trials in ``condition``), sorted by participant."""
    groups: Dict[str, List[float]] = {}
    for m in metrics:
        if m.meta.condition == condition:
            v = getattr(m, value)
            if v is not None:
                groups.setdefault(m.meta.participant, []).append(float(v))
    return [(p, float(np.mean(vs))) for p, vs in sorted(groups.items())]


def paired_by_participant(metrics: Sequence[TrialMetrics], value: str
                          ) -> Tuple[List[str], List[float], List[float], List[str]]:
    """Per-participant means of ``value`` in both conditions, for a paired comparison.

    Returns (participants with a value in both conditions, their no_feedback means, their
    feedback means -- in the same order, and the participants left out because one
    condition has no value for them).
    """
    without = dict(per_participant(metrics, value, "no_feedback"))
    with_fb = dict(per_participant(metrics, value, "feedback"))
    both = sorted(set(without) & set(with_fb))
    left_out = sorted(set(m.meta.participant for m in metrics) - set(both))
    return both, [without[p] for p in both], [with_fb[p] for p in both], left_out
