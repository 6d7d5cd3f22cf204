"""``make grade``: every submission in a folder, several at once, each in a process of its own.

Why a process per submission (``hri-grade submission``), driven by a few threads: a grade
must never be lost because of another student -- a crash or hang of the grader on one
submission ends that process only (it is timed out and recorded as not graded), and each
process gives its student code a uid and sandboxes of its own. The lab's live graph
(Ex. 15) is read once up front and shared through a cache file.

Results: ``OUT/<student>/results.json`` (Gradescope format), ``feedback.txt``, plots and
logs per check; ``OUT/grades.csv`` and ``OUT/summary.json`` for all.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Optional, Sequence

__all__ = ["BatchError", "Outcome", "submissions_in", "grade_all"]

_PER_SUBMISSION_TIMEOUT_S = 600.0


class BatchError(RuntimeError):
    """The submissions folder is missing or empty (one line with the fix)."""


@dataclass(frozen=True)
class Outcome:
    student: str
    score: float
    max_score: float
    status: str          # "graded" | "grader error"
    seconds: float
    message: str = ""


def submissions_in(folder: Path) -> List[Path]:
    """One submission per subfolder (nbgrader's submitted/<student>/...), sorted by name."""
    if not folder.is_dir():
        raise BatchError(f"{folder}: no such folder; collect submissions first (nbgrader: notebooks/submitted/) "
                         "or pass the folder, e.g. make grade DIR=path/to/submissions")
    found = sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith("."))
    if not found:
        raise BatchError(f"{folder}: no submission folders in it; expected one subfolder per student")
    return found


def _grade_one(folder: Path, out: Path, graph_cache: Optional[Path], checks: Optional[Sequence[str]]) -> Outcome:
    started = time.monotonic()
    out.mkdir(parents=True, exist_ok=True)
    argv = [sys.executable, "-m", "hri_teleop.grading.cli", "submission", str(folder), "--json", "--out", str(out)]
    if graph_cache is not None:
        argv += ["--graph-cache", str(graph_cache)]
    if checks:
        argv += ["--checks", ",".join(checks)]
    with open(out / "grader.log", "wb") as log:
        proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=log,
                                start_new_session=True)
        try:
            stdout, _ = proc.communicate(timeout=_PER_SUBMISSION_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return Outcome(folder.name, 0.0, 0.0, "grader error", time.monotonic() - started,
                           f"grading took longer than {_PER_SUBMISSION_TIMEOUT_S:.0f} s")
    seconds = time.monotonic() - started
    if proc.returncode not in (0, 1):
        tail = (out / "grader.log").read_text(errors="replace").strip().splitlines()[-1:] or ["no output"]
        return Outcome(folder.name, 0.0, 0.0, "grader error", seconds, tail[0][:300])
    try:
        payload = json.loads(stdout.decode("utf-8"))
    except ValueError:
        return Outcome(folder.name, 0.0, 0.0, "grader error", seconds, "the grader printed no JSON")
    maximum = sum(float(t["max_score"]) for t in payload["tests"])
    return Outcome(folder.name, float(payload["score"]), maximum, "graded", seconds)


def grade_all(folder: Path, out: Path, jobs: Optional[int] = None, checks: Optional[Sequence[str]] = None,
              progress=print) -> int:
    """Grade every submission in ``folder`` into ``out``; 0 when all were graded, 2 if any could not be."""
    from hri_teleop.grading.checks import live_graph
    from hri_teleop.grading.sandbox import sandbox_mode

    subs = submissions_in(folder)
    out.mkdir(parents=True, exist_ok=True)
    jobs = max(1, jobs or os.cpu_count() or 1)
    sandbox_mode()  # says once, up front, when bubblewrap is missing
    graph_cache: Optional[Path] = None
    if not checks or "graph" in checks:
        graph_cache = out / "live_graph.json"
        if graph_cache.exists():
            graph_cache.unlink()  # the lab's graph of today, not of an earlier run
        live_graph(graph_cache)
    progress(f"grading {len(subs)} submission(s) from {folder}, {jobs} at once")
    started = time.monotonic()
    outcomes: Dict[str, Outcome] = {}
    lock = threading.Lock()
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(_grade_one, sub, out / sub.name, graph_cache, checks): sub for sub in subs}
        for future in as_completed(futures):
            sub = futures[future]
            try:
                outcome = future.result()
            except Exception as exc:  # noqa: BLE001 - recorded; the others go on
                outcome = Outcome(sub.name, 0.0, 0.0, "grader error", 0.0, f"{type(exc).__name__}: {exc}")
            with lock:
                outcomes[sub.name] = outcome
                done = len(outcomes)
            line = f"[{done:>{len(str(len(subs)))}}/{len(subs)}] {outcome.student:<24} "
            line += (f"{outcome.score:g}/{outcome.max_score:g}" if outcome.status == "graded"
                     else f"NOT GRADED: {outcome.message}")
            progress(f"{line}  ({outcome.seconds:.1f} s)")
    ordered = [outcomes[s.name] for s in subs]
    with open(out / "grades.csv", "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["student", "score", "max_score", "status", "seconds", "message"])
        for o in ordered:
            writer.writerow([o.student, f"{o.score:g}", f"{o.max_score:g}", o.status, f"{o.seconds:.1f}", o.message])
    (out / "summary.json").write_text(json.dumps([o.__dict__ for o in ordered], indent=2), encoding="utf-8")
    failed = [o for o in ordered if o.status != "graded"]
    progress(f"graded {len(ordered) - len(failed)}/{len(ordered)} in {time.monotonic() - started:.0f} s; "
             f"results in {out} (grades.csv, <student>/feedback.txt)")
    return 2 if failed else 0
