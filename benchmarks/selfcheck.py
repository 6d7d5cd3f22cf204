"""Benchmark 8: the student bundle's ``make check``, the whole bundle and one exercise.

A bundle as ``make release`` packs it, set up (not timed) and given the answer key; each run is ``make
check`` as a student types it. The figure is its median wall time and its share of the target
(:data:`PROMISE_S`); the reference, from the same run, is the sum of the seconds make check prints for each
notebook and the files' checks (measured side by side). A run short of full points is a :class:`BenchError`.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import statistics
import subprocess
import tarfile
import time
from pathlib import Path
from typing import Callable, Dict, List, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.course.bundle import assemble_bundle, pack_bundle
from hri_teleop.course.release import copy_answer_key, prepare_course_copy
from hri_teleop.grading.assignments import ASSIGNMENTS

Progress = Callable[[str], None]

#: Runs of each row: full, smoke.
RUNS = {False: 3, True: 1}
#: What make check may take on a 2-core machine (issue 43): the whole bundle, one exercise (s).
PROMISE_S = {"whole": 60.0, "one": 15.0}
#: The exercise of the one-exercise row (the issue measured ONLY=ex08: 30 s), and the smoke size's
#: stand-in for the whole bundle (two short notebooks).
ONE = "ex08"
SMOKE_WHOLE = "ex04,ex08"
#: A make check or make setup that takes longer has hung (s): the benchmark stops it and says so.
HANG_S = 900.0
_NOTEBOOK = re.compile(r"^  \S+/(ex\S+)\.ipynb \.\.\. ([\d.]+)/([\d.]+) points \((\d+) s\)")
_FILES = re.compile(r"^  \S+/hri_lab: .*: ([\d.]+)/([\d.]+) points \((\d+) s\)$")


def student_env() -> Dict[str, str]:
    """A student's shell: the machine's own PATH, no ROS, no project .venv, no HRI_ settings."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "VIRTUAL_ENV", "PYTHON", "HRI_"))}
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if ".venv" not in p)
    env["SDL_VIDEODRIVER"] = env["SDL_AUDIODRIVER"] = "dummy"
    return env


def _make(bundle: Path, *args: str) -> Tuple[float, str]:
    """Wall time and output of ``make -C bundle ARGS`` in a session of its own (killed whole on a hang)."""
    started = time.monotonic()
    proc = subprocess.Popen(["make", "--no-print-directory", "-C", str(bundle), *args], env=student_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        output, _ = proc.communicate(timeout=HANG_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        raise BenchError(f"make {' '.join(args)} in the bundle did not end within {HANG_S:.0f} s; "
                         f"run it by hand in {bundle} to see where") from None
    seconds = time.monotonic() - started
    if proc.returncode != 0:
        tail = "\n  ".join(output.strip().splitlines()[-8:])
        raise BenchError(f"make {' '.join(args)} in the bundle failed (exit {proc.returncode}):\n  {tail}")
    return seconds, output


def prepare_bundle(work: Path, progress: Progress) -> Path:
    """The answer key in a bundle as ``make release`` packs it, unpacked and set up."""
    if work.exists():
        shutil.rmtree(work)
    course = prepare_course_copy(work)
    archive = pack_bundle(assemble_bundle(course / "release", work / "assembled", ASSIGNMENTS), work / "bundle.tar.gz")
    home = work / "home"
    home.mkdir()
    home.chmod(0o755)  # the grader's student uid reads the files (as root), as a student's home allows
    with tarfile.open(archive) as tar:
        tar.extractall(home)
    bundle = home / "task4"
    seconds, _ = _make(bundle, "setup")
    progress(f"selfcheck: bundle set up in {seconds:.0f} s (not timed below)")
    copy_answer_key(bundle, course)
    return bundle


def printed_seconds(output: str) -> Tuple[float, float, float, int]:
    """(points, possible, the seconds make check printed for its notebooks and files, notebooks run)."""
    got = most = seconds = 0.0
    notebooks = 0
    for line in output.splitlines():
        found = _NOTEBOOK.match(line) or _FILES.match(line)
        if found:
            g, m, s = (float(x) for x in found.groups()[-3:])
            got, most, seconds = got + g, most + m, seconds + s
            notebooks += 1 if found.re is _NOTEBOOK else 0
    return got, most, seconds, notebooks


def measure(bundle: Path, only: str, runs: int, progress: Progress, what: str) -> Dict[str, float]:
    """``runs`` of ``make check [ONLY=only]``: the median wall time and the median printed sum."""
    walls: List[float] = []
    sums: List[float] = []
    notebooks = 0
    for k in range(runs):
        wall, output = _make(bundle, "check", *([f"ONLY={only}"] if only else []))
        got, most, printed, notebooks = printed_seconds(output)
        if notebooks == 0 or most == 0 or got < most:
            tail = "\n  ".join(output.strip().splitlines()[-6:])
            raise BenchError(f"make check {what} gave the answer key {got:g}/{most:g} over {notebooks} notebook(s), "
                             f"not full points:\n  {tail}")
        walls.append(wall)
        sums.append(printed)
        progress(f"selfcheck: {what} run {k + 1}: {wall:.1f} s (its notebooks and files printed {printed:.0f} s)")
    return {"median_s": statistics.median(walls), "max_s": max(walls), "printed_sum_s": statistics.median(sums),
            "notebooks": float(notebooks), "runs": float(runs)}


def _row(name: str, kind: str, values: Dict[str, float]) -> BenchRow:
    promise = PROMISE_S[kind]
    values = dict(values, promise_s=promise, share_of_promise=values["median_s"] / promise)
    figure = (f"median {values['median_s']:.1f} s of {values['runs']:.0f} (max {values['max_s']:.1f} s), "
              f"{values['notebooks']:.0f} notebook(s) and their files' checks, answer key; "
              f"{values['share_of_promise']:.0%} of the {promise:.0f} s target")
    reference = (f"the notebooks' and checks' own times as make check prints them, summed: "
                 f"{values['printed_sum_s']:.0f} s (measured side by side)")
    return BenchRow(name, figure, reference, values["median_s"] / max(values["printed_sum_s"], 1.0),
                    "wall / sum of own times", values)


def run(options: BenchOptions, progress: Progress) -> List[BenchRow]:
    bundle = prepare_bundle(options.out_dir / "selfcheck", progress)
    runs = RUNS[options.smoke]
    whole = measure(bundle, SMOKE_WHOLE if options.smoke else "", runs, progress, "whole")
    one = measure(bundle, ONE, runs, progress, f"ONLY={ONE}")
    return [_row("make check, whole bundle" + (f" (smoke: ONLY={SMOKE_WHOLE})" if options.smoke else ""),
                 "whole", whole),
            _row(f"make check ONLY={ONE}", "one", one)]
