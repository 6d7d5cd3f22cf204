"""The Gradescope results.json of one submission: a test per part, visibility, and what was not judged.

Parts judged on the hidden inputs alone stay hidden from students until the grades are published
(``after_published``), so a submission cannot be tuned to them; the rest is ``visible`` at once.
A check the grader could not finish (a timeout, a grader crash) still lists its parts, at 0, and
the top-level ``output`` names it in one line, so neither a student nor the TA mistakes it for a grade.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.grading.exercises.registry import checks, exercise
from hri_teleop.grading.points import part_tables
from hri_teleop.grading.results import CheckResult, gradescope_json

__all__ = ["Unjudged", "part_tables", "visibility", "results_payload"]

VISIBLE, AFTER_PUBLISHED = "visible", "after_published"


@dataclass(frozen=True)
class Unjudged:
    """A check the grader could not finish, and why in a few words ("timed out after 600 s")."""

    check: str
    reason: str


def visibility(check: str, part_name: str) -> str:
    """``after_published`` for a part judged on hidden inputs only, else ``visible``."""
    table = part_tables().get(check, {})
    hidden = exercise(check).hidden_parts if check in checks() else ()
    hidden_names = {table[key][0] for key in hidden if key in table}
    return AFTER_PUBLISHED if part_name in hidden_names else VISIBLE


def _unjudged_tests(item: Unjudged) -> List[Dict[str, Any]]:
    return [{"name": f"{item.check}: {name}", "score": 0.0, "max_score": points, "status": "failed",
             "visibility": visibility(item.check, name),
             "output": f"not judged: the grader {item.reason}; course staff will regrade it (no need to resubmit)"}
            for name, points in part_tables()[item.check].values()]


def results_payload(results: Sequence[CheckResult], unjudged: Sequence[Unjudged] = (),
                    notes: Sequence[str] = (), execution_time_s: float = 0.0,
                    order: Sequence[str] = (), notebook_tests: Optional[Mapping[str, Sequence[Dict[str, Any]]]] = None,
                    notebooks_unjudged: Sequence[Tuple[str, str]] = ()) -> Dict[str, Any]:
    """results.json for Gradescope: ``results`` as graded, ``unjudged`` checks at 0, top-level output.

    ``order`` lists the checks in the order students should see them (default: as given);
    ``notebook_tests`` (notebook -> its tests) follow them. The output's first line names what
    was not judged (``notebooks_unjudged``: (notebook, why)); ``notes`` (where the package was
    found, the checks' own notes) follow.
    """
    payload = gradescope_json(results)
    by_name = iter(payload["tests"])
    grouped: Dict[str, List[Dict[str, Any]]] = {}
    for result in results:
        for part in result.parts:
            test = dict(next(by_name))
            test["visibility"] = visibility(result.check, part.name)
            grouped.setdefault(result.check, []).append(test)
    for item in unjudged:
        grouped[item.check] = _unjudged_tests(item)
    checks = [c for c in order if c in grouped] + [c for c in grouped if c not in order]
    for name, nb_tests in (notebook_tests or {}).items():
        grouped[name] = [dict(t) for t in nb_tests]
        checks.append(name)
    tests = [dict(test, number=f"{i}.{j}") for i, check in enumerate(checks, 1)
             for j, test in enumerate(grouped[check], 1)]
    lines: List[str] = []
    if unjudged or notebooks_unjudged:
        lines.append("Not judged: " + "; ".join([f"{u.check} (the grader {u.reason})" for u in unjudged]
                                                + [f"{name} ({why})" for name, why in notebooks_unjudged])
                     + ". Those parts show 0 until course staff regrade; you need not resubmit.")
    lines.extend(dict.fromkeys(list(notes) + [n for r in results for n in r.notes]))
    # Plain text everywhere: a name or an output a student wrote is never read as HTML or Markdown.
    out: Dict[str, Any] = {"score": round(sum(t["score"] for t in tests), 6), "tests": tests,
                           "visibility": VISIBLE, "stdout_visibility": "hidden", "output_format": "text",
                           "test_output_format": "text", "test_name_format": "text"}
    if execution_time_s:
        out["execution_time"] = round(execution_time_s, 1)
    if lines:
        out["output"] = "\n".join(lines)
    return out
