"""The checks of the notebooks: each judges one deliverable, prints its feedback, returns its points.

A check is the last line of a read-only check cell: the student sees the points and the feedback
that ``hri-grade`` and ``make grade`` give the same files. nbgrader gives the cell no points: a
deliverable's points are counted once, with the files (:mod:`hri_teleop.grading.points`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Dict, Union

from hri_teleop.grading.exercises.registry import exercises
from hri_teleop.grading.results import CheckResult, feedback_text

PathLike = Union[str, Path]

#: The last line a check cell prints: where its points count (hri_teleop.grading.points).
POINTS_NOTE = ("these points are your hri_lab files': the course counts them once, with the files you hand in "
               "(this notebook cell adds none)")


def score(result: CheckResult) -> float:
    """Print a check's feedback and return its points: the last line of a check cell.

    The points are the files' (a failing part costs its points, the rest are kept, as ``hri-grade``
    and ``make grade`` score them); the cell itself is read-only and worth no nbgrader points.
    """
    print(feedback_text([result]))
    print(f"note: {POINTS_NOTE}")
    return float(result.score)


def calls() -> Dict[str, Callable[..., CheckResult]]:
    """The names a notebook's check cell calls (``check.mapping_node(PACKAGE)``) -> the result they show:
    each exercise's ``notebook_calls``."""
    return {name: call for found in exercises() for name, call in found.notebook_calls.items()}


#: The calls whose check cell runs its whole check as the files' half of ``make check`` runs it (the
#: package alone, no other argument), so that the files' half takes the cell's result
#: (:mod:`hri_teleop.grading.judge.reuse`); the others (Ex. 8's class alone, one exercise's catkin parts)
#: judge less than their check: the files' half runs those. call name -> its check.
KEEPS_RESULT: Dict[str, str] = {name: found.check for found in exercises() for name in found.whole_check_calls}

#: What a notebook's check cell calls: each exercise's notebook calls (``score`` and the rest serve them).
__all__ = sorted(calls())


def __getattr__(name: str) -> Callable[..., float]:
    """``check.<call>(package, ...)``: the exercise's check, its feedback printed, its points returned."""
    call = calls().get(name)
    if call is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

    def cell(package: PathLike, *args: Any, **kwargs: Any) -> float:
        return score(call(package, *args, **kwargs))

    cell.__name__ = name
    cell.__doc__ = call.__doc__
    return cell
