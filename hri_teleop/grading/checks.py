"""The checks of every exercise, run by name: ``hri-grade``, ``make grade`` and the notebooks' cells use these.

One check per handout deliverable (``hri_teleop/grading/exercises`` registers them), each returning a
:class:`~hri_teleop.grading.results.CheckResult`; ``grade_submission`` runs them all on one package.
``check`` raises AssertionError with the student's feedback unless every part passes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

from hri_teleop.grading.cases.inputs import default_seed
from hri_teleop.grading.exercises.registry import exercise, exercises
from hri_teleop.grading.results import CheckResult, GradingError, feedback_text
from hri_teleop.grading.run.jobs import run_all
from hri_teleop.grading.run.workspace import find_package_root

__all__ = ["CHECKS", "grade", "check", "grade_submission", "default_check_jobs"]

PathLike = Union[str, Path]

#: check name -> its function (path, seed=, out_dir=, ...) -> result, in the registry's order.
CHECKS: Dict[str, Callable[..., CheckResult]] = {found.check: found.grade for found in exercises()}


def grade(check: str, path: PathLike, **kwargs: Any) -> CheckResult:
    """Run the check named ``check`` (one of CHECKS) on ``path``."""
    if check not in CHECKS:
        raise GradingError(f"unknown check {check!r}; use one of {', '.join(CHECKS)}")
    return CHECKS[check](path, **kwargs)


def check(name: str, path: PathLike, **kwargs: Any) -> CheckResult:
    """For an autograded cell: the check's result, or AssertionError with the feedback unless every part passes."""
    result = grade(name, path, **kwargs)
    if not result.passed:
        raise AssertionError("\n" + feedback_text([result]))
    return result


def default_check_jobs(cpu_count: Optional[int]) -> int:
    """How many checks of one submission run at once by default: one more than the cores (1 if unknown).

    A check waits on process starts and sockets part of its time (the answer key's seven checks keep
    2 cores 75 % busy at one per core): answer key, 2 cores, idle, wall time at 2 / 3 / 4 checks at
    once: 7.8 / 6.4 / 7.3 s.
    """
    return max(1, cpu_count or 1) + 1


def grade_submission(folder: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                     graph_cache: Optional[PathLike] = None, checks: Optional[Sequence[str]] = None,
                     jobs: int = 1) -> List[CheckResult]:
    """Every check on one student's package (missing files give failed checks, not errors), ``jobs``
    checks at a time (each has its own sandbox, master and clock: the verdicts do not depend on it)."""
    folder = Path(folder).expanduser()
    if not folder.is_dir():
        raise GradingError(f"{folder}: not a folder; give the student's hri_lab package folder (or their submission)")
    if jobs < 1:
        raise GradingError(f"--jobs {jobs}: give how many checks may run at once, at least 1")
    root = find_package_root(folder)
    seed = default_seed(root) if seed is None else seed

    checks = tuple(CHECKS) if checks is None else tuple(checks)

    def one(name: str) -> Callable[[], CheckResult]:
        found = exercise(name)
        kwargs: Dict[str, Any] = {"seed": seed, "out_dir": out_dir}
        if "graph_cache" in found.grade_kwargs:
            kwargs["graph_cache"] = graph_cache
        return lambda: found.grade(root, **kwargs)

    if jobs == 1:
        return [one(name)() for name in checks]
    order = sorted(checks, key=lambda c: -exercise(c).session_s)  # the longest sessions start first
    done: Dict[str, CheckResult] = {}
    failed: List[BaseException] = []

    def collect(name: str, result: Optional[CheckResult], error: Optional[BaseException]) -> None:
        if error is not None:
            failed.append(error)
        elif result is not None:
            done[name] = result

    run_all([(name, one(name)) for name in order], jobs, collect)
    if failed:
        raise failed[0]
    return [done[name] for name in checks]
