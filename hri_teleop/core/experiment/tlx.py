"""The workload questionnaire after a trial: raw NASA-TLX (six ratings, their mean is the score).

Raw TLX, without the pairwise weighting, takes a minute after each trial instead of five (why,
and the scales: docs/experiment.md). Pure: :class:`hri_teleop.course.widgets.tlx.TlxWidget` is the
form, ``python -m hri_teleop.apps.trial tlx`` the command line; both store
:meth:`TlxRatings.to_dict` under ``tlx`` in the trial's sidecar.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Mapping, NamedTuple, Optional, Tuple, Union

from hri_teleop.core.experiment.metrics import MetricsError
from hri_teleop.core.experiment.sidecar import update_sidecar

__all__ = ["TlxError", "Subscale", "SUBSCALES", "SUBSCALE_KEYS", "STEP", "TlxRatings", "tlx_from_dict", "optional_tlx",
           "store_tlx"]

#: The scale's resolution: 0, 5, ..., 100.
STEP = 5


class TlxError(MetricsError):
    """A questionnaire answer is unusable (one line: which subscale, what was given, the fix)."""


class Subscale(NamedTuple):
    key: str
    title: str
    question: str
    low: str
    high: str


SUBSCALES: Tuple[Subscale, ...] = (
    Subscale("mental", "Mental demand", "How mentally demanding was the task?", "very low", "very high"),
    Subscale("physical", "Physical demand", "How physically demanding was the task?", "very low", "very high"),
    Subscale("temporal", "Temporal demand", "How hurried or rushed was the pace of the task?", "very low", "very high"),
    Subscale("performance", "Performance", "How successful were you in accomplishing what you were asked to do?",
             "perfect", "failure"),
    Subscale("effort", "Effort", "How hard did you have to work to accomplish your level of performance?",
             "very low", "very high"),
    Subscale("frustration", "Frustration", "How insecure, discouraged, irritated, stressed, and annoyed were you?",
             "very low", "very high"),
)
SUBSCALE_KEYS: Tuple[str, ...] = tuple(s.key for s in SUBSCALES)


def _rating(key: str, value: Any, source: str) -> int:
    where = f"{source}: " if source else ""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or value != value:
        raise TlxError(f"{where}TLX {key} must be a number 0..100 in steps of {STEP}, got {value!r}")
    number = float(value)
    if not 0 <= number <= 100 or number % STEP != 0:
        raise TlxError(f"{where}TLX {key} is {value!r}; rate 0..100 in steps of {STEP} (0, 5, ..., 100)")
    return int(number)


@dataclass(frozen=True)
class TlxRatings:
    """One participant's six ratings after one trial (0..100, steps of 5)."""

    mental: int
    physical: int
    temporal: int
    performance: int
    effort: int
    frustration: int

    def __post_init__(self) -> None:
        for key in SUBSCALE_KEYS:
            object.__setattr__(self, key, _rating(key, getattr(self, key), ""))

    @property
    def raw_tlx(self) -> float:
        """The raw TLX score: the mean of the six ratings (0..100)."""
        total: int = sum(getattr(self, k) for k in SUBSCALE_KEYS)
        return total / float(len(SUBSCALE_KEYS))

    def to_dict(self) -> Dict[str, Union[int, float]]:
        """What the sidecar stores: the six ratings and, for a reader of the YAML, the score."""
        data: Dict[str, Union[int, float]] = {k: getattr(self, k) for k in SUBSCALE_KEYS}
        data["raw_tlx"] = round(self.raw_tlx, 4)
        return data


def tlx_from_dict(data: Any, source: str = "") -> TlxRatings:
    """The ratings stored in a sidecar's ``tlx`` mapping; TlxError naming ``source`` and the problem.

    A stored ``raw_tlx`` is only a convenience for people reading the file: the score is
    always recomputed from the six ratings.
    """
    where = f"{source}: " if source else ""
    if not isinstance(data, Mapping):
        raise TlxError(f"{where}tlx must be a mapping of the six ratings ({', '.join(SUBSCALE_KEYS)}), got {data!r}")
    unknown = sorted(str(k) for k in set(data) - set(SUBSCALE_KEYS) - {"raw_tlx"})  # YAML keys: 0, true, ...
    if unknown:
        raise TlxError(f"{where}tlx has unknown key(s) {', '.join(unknown)}; "
                       f"the subscales are {', '.join(SUBSCALE_KEYS)}")
    missing = [k for k in SUBSCALE_KEYS if k not in data]
    if missing:
        raise TlxError(f"{where}tlx lacks {', '.join(missing)}; rate all six subscales (0..100 in steps of {STEP})")
    return TlxRatings(**{k: _rating(k, data[k], source) for k in SUBSCALE_KEYS})


def store_tlx(sidecar: Union[str, Path], ratings: TlxRatings) -> Dict[str, Any]:
    """Write ``ratings`` under ``tlx`` into the trial's sidecar (other keys kept; atomic); returns the new content."""
    return update_sidecar(sidecar, {"tlx": ratings.to_dict()})


def optional_tlx(data: Mapping[str, Any], source: str = "") -> Optional[TlxRatings]:
    """The sidecar's ratings, or None when the questionnaire was not filled in."""
    value = data.get("tlx")
    return None if value is None else tlx_from_dict(value, source)
