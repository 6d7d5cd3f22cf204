"""What a check returns: parts with points and messages a student can act on, and its JSON forms.

A student must know which thing is wrong and what to do, and one mistake must cost the points of
what it breaks and nothing else: so a check is a list of :class:`Part`, each with its points, a
verdict and, when it fails, a message naming the topic, type, expected value and what arrived,
with plots where a trace was compared. ``gradescope_json`` is what ``hri-grade --json`` prints.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError

__all__ = ["GradingError", "Part", "CheckResult", "gradescope_json", "feedback_text", "not_judged"]


class GradingError(HriTeleopError, RuntimeError):
    """The grader itself could not run (ROS missing, a bad path given to hri-grade): one line with the fix."""


@dataclass(frozen=True)
class Part:
    """One graded behaviour. ``message`` says what is wrong and how to fix it (empty when passed)."""

    name: str
    points: float
    passed: bool
    message: str = ""
    plots: Tuple[str, ...] = ()
    note: str = ""  # shown also when passed (e.g. "voluntary exercise not done")

    @property
    def score(self) -> float:
        return self.points if self.passed else 0.0


def not_judged(name: str, points: float, reason: str) -> Part:
    """A part that could not be looked at because something it needs failed first."""
    return Part(name, points, False, f"not judged: {reason}")


@dataclass(frozen=True)
class CheckResult:
    """All parts of one check of one file. ``seed`` is the hidden inputs' seed (to reproduce them)."""

    check: str
    target: str
    parts: List[Part] = field(default_factory=list)
    seed: Optional[int] = None
    duration_s: float = 0.0
    notes: Tuple[str, ...] = ()

    @property
    def score(self) -> float:
        return sum(p.score for p in self.parts)

    @property
    def max_score(self) -> float:
        return sum(p.points for p in self.parts)

    @property
    def passed(self) -> bool:
        return all(p.passed for p in self.parts)

    @property
    def failed_parts(self) -> List[Part]:
        return [p for p in self.parts if not p.passed]

    def part(self, name: str) -> Part:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(f"{self.check} has no part {name!r}; parts: {[p.name for p in self.parts]}")

    def to_dict(self) -> Dict[str, Any]:
        return {
            "check": self.check, "target": self.target, "seed": self.seed, "score": self.score,
            "max_score": self.max_score, "duration_s": round(self.duration_s, 3), "notes": list(self.notes),
            "parts": [{"name": p.name, "points": p.points, "passed": p.passed, "message": p.message,
                       "plots": list(p.plots), "note": p.note} for p in self.parts],
        }

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> "CheckResult":
        parts = [Part(p["name"], float(p["points"]), bool(p["passed"]), p.get("message", ""),
                      tuple(p.get("plots", ())), p.get("note", "")) for p in d["parts"]]
        return cls(d["check"], d["target"], parts, d.get("seed"), float(d.get("duration_s", 0.0)),
                   tuple(d.get("notes", ())))


def _part_output(part: Part) -> str:
    lines = []
    if part.note:
        lines.append(part.note)
    if not part.passed and part.message:
        lines.append(part.message)
    lines.extend(f"plot (expected vs actual): {p}" for p in part.plots)
    return "\n".join(lines)


def gradescope_json(results: Sequence[CheckResult]) -> Dict[str, Any]:
    """The Gradescope autograder results format: one test per part, and the total score."""
    tests = []
    for result in results:
        for part in result.parts:
            tests.append({
                "name": f"{result.check}: {part.name}",
                "score": part.score,
                "max_score": part.points,
                "status": "passed" if part.passed else "failed",
                "output": _part_output(part),
            })
    notes = [n for r in results for n in r.notes]
    out: Dict[str, Any] = {"score": sum(r.score for r in results), "tests": tests}
    if notes:
        out["output"] = "\n".join(dict.fromkeys(notes))
    return out


def feedback_text(results: Sequence[CheckResult]) -> str:
    """Plain-text feedback for a student: every check, its score, and each failed part's message."""
    lines: List[str] = []
    total = sum(r.score for r in results)
    maximum = sum(r.max_score for r in results)
    for result in results:
        lines.append(f"{result.check} ({result.target}): {result.score:g}/{result.max_score:g}")
        for part in result.parts:
            mark = "ok  " if part.passed else "FAIL"
            lines.append(f"  [{mark}] {part.name} ({part.score:g}/{part.points:g})")
            if part.note:
                lines.append(f"         {part.note}")
            if not part.passed and part.message:
                for line in part.message.splitlines():
                    lines.append(f"         {line}")
            for plot in part.plots:
                lines.append(f"         plot: {plot}")
        if result.seed is not None:
            lines.append(f"  (hidden inputs from seed {result.seed}; rerun with --seed {result.seed})")
    notes = list(dict.fromkeys(n for r in results for n in r.notes))
    lines.extend(f"note: {n}" for n in notes)
    lines.append(f"total: {total:g}/{maximum:g}")
    return "\n".join(lines)
