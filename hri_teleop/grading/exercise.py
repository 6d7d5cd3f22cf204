"""What one graded deliverable tells the grader about itself (each exercise module ends with one).

Kept free of the grader's machinery, so the kit (``judge/harness.py``) and every exercise can name it
without importing each other.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple

from hri_teleop.grading.results import CheckResult

__all__ = ["Exercise", "PartTable", "check_name"]

#: part key -> (the part's name as students read it, its points)
PartTable = Mapping[str, Tuple[str, float]]


def check_name(module: str) -> str:
    """The check's name of an exercise module (``mapping_node`` -> ``mapping-node``)."""
    return module.replace("_", "-")


@dataclass(frozen=True)
class Exercise:
    """One deliverable as the grader runs, judges and counts it.

    ``key``: its module's name, the key of :data:`~hri_teleop.grading.exercises.DELIVERABLE_FILES`.
    ``handout``: where the handout asks for it ("Ex. 6-7"). ``assignment``: the nbgrader assignment
    whose files carry its points. ``parts``: its parts in the order judged. ``grade``: path -> result
    (every check takes ``seed`` and ``out_dir``). ``hidden_inputs``: its result names the seed of the
    inputs students never see; ``hidden_parts``: the keys of the parts judged on those inputs alone (Gradescope
    shows them after the grades are published). ``lab_stand_ins``: other deliverables (files in the package) whose lab versions run in
    place of the student's, so a mistake there costs points there only. ``session_s``: about how long
    its ROS sessions take (0: none); the longest start first when checks run side by side.
    ``grade_kwargs``: what else ``grade_submission`` hands it (``graph_cache``); ``batch_cache``: given a
    file, computes there once what every submission's check of a batch reads (the lab's live graph), so
    ``make grade`` hands that file on as the first of ``grade_kwargs``. ``notebook_calls``: the
    names a notebook's check cell calls on ``hri_teleop.course.check`` -> the result they show;
    ``whole_check_calls``: those of them that run the whole check as the files' half of ``make check``
    runs it (the package alone), so that half takes the cell's result.
    """

    key: str
    handout: str
    assignment: str
    parts: PartTable
    grade: Callable[..., CheckResult]
    hidden_inputs: bool = False
    hidden_parts: Tuple[str, ...] = ()
    lab_stand_ins: Tuple[str, ...] = ()
    session_s: float = 0.0
    grade_kwargs: Tuple[str, ...] = ()
    batch_cache: Optional[Callable[[Path], Any]] = None
    notebook_calls: Mapping[str, Callable[..., CheckResult]] = field(default_factory=dict)
    whole_check_calls: Tuple[str, ...] = ()
    public_traces: Mapping[str, Callable[[], List[Tuple[str, Any, float]]]] = field(default_factory=dict)

    @property
    def check(self) -> str:
        """The name results, ``CHECKS=``, reports and Gradescope use (``mapping-node``)."""
        return check_name(self.key)

    @property
    def points(self) -> float:
        """Its parts' points together."""
        return float(sum(points for _name, points in self.parts.values()))

    def part_names(self) -> Dict[str, str]:
        """part key -> its name as students read it."""
        return {key: name for key, (name, _points) in self.parts.items()}

    def call(self, path: Any, **kwargs: Any) -> CheckResult:
        """Its check on ``path`` (a package folder or the file itself)."""
        return self.grade(path, **kwargs)
