"""Benchmark 5: every notebook of the course headless, and ``make setup`` when nothing is missing.

Both are waits a person sits through. Notebooks run one at a time as ``make test`` runs them, each
graded as nbgrader would (a failing notebook is a :class:`BenchError`, never a time), against a
one-cell notebook on the same kernel; ``make setup`` against the import check it ends with, plus a
``bash -x`` run that names its slowest line. Every process started carries a marker and is stopped
at the end. The rules: docs/benchmarks.md.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import time
import uuid
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.paths import REPO
from hri_teleop.ros.kernel import KERNEL_NAME

__all__ = [
    "NOTEBOOKS_ROW", "SETUP_ROW", "SMOKE_NOTEBOOKS", "SETUP_FLOOR_CODE", "run",
    "short_name", "notebook_problems", "floor_positions", "notebooks_figure", "line_costs",
]

SETUP_SCRIPT = REPO / "tools" / "setup.sh"
NOTEBOOKS_ROW = "notebooks headless"
SETUP_ROW = "make setup, nothing missing"
#: The cheapest notebooks (a few seconds each): ``--smoke`` proves the benchmark runs, not how fast.
#: ex01 needs no ROS (~1.5 s), ex11 starts a roscore and a node (~4.5 s): one of each assignment.
SMOKE_NOTEBOOKS = ("ex01_fsr_and_arduino", "ex11_calibration")
#: The floor notebook: one trivial cell on the course's kernel.
FLOOR_CELL = "1 + 1"
#: The import check tools/setup.sh ends with: the reference of a no-op setup.
SETUP_FLOOR_CODE = "import rospy, actionlib, rosbag, genpy"
FLOOR_RUNS, FLOOR_RUNS_SMOKE = 3, 1
SETUP_RUNS, SETUP_RUNS_SMOKE = 5, 2
#: Environment variable that marks every process this benchmark starts (kernels, roscores, setup).
MARKER_ENV = "HRI_BENCH_NOTEBOOKS_RUN"
#: How long processes we started may take to end after the last run (kernels stop their roscore at exit).
LEFTOVER_GRACE_S = 10.0
#: What setup prints when it had something to do: then the run did not measure "nothing missing".
_SETUP_DID_WORK = re.compile(r"^setup: (installing|creating|upgrading)", re.MULTILINE)

Progress = Callable[[str], None]


# -- pure helpers ---------------------------------------------------------------------------------

def short_name(stem: str) -> str:
    """``ex12_13_teleoperation_launch`` -> ``ex12_13``: the exercise numbers, as the handout names them."""
    match = re.match(r"ex\d+(?:_\d+)*(?=_|$)", stem)
    return match.group(0) if match else stem


def notebook_problems(name: str, result: Mapping[str, object]) -> List[str]:
    """Why a :func:`hri_teleop.course.release.run_source` result is not a success (empty: it is).

    The same rule as ``make test``'s notebook test: no cell raised or wrote to stderr, and
    every autograded cell got full marks -- a time of a notebook that failed measures nothing.
    """
    problems = [f"{name}: {error}" for error in result.get("errors", [])]  # type: ignore[union-attr]
    grades: Mapping[str, Sequence[float]] = result.get("grades", {})  # type: ignore[assignment]
    for grade_id, (got, most) in sorted(grades.items()):
        if got != most:
            problems.append(f"{name}: autograded cell {grade_id} got {got:g} of {most:g} points")
    return problems


def floor_positions(notebooks: int, runs: int) -> List[int]:
    """Before which notebooks (0-based) the floor runs: spread through the run, not all at its start.

    The machine is shared and its load drifts; floor runs among the notebooks see the load
    the notebooks saw, so the ratio holds. 13 notebooks, 3 runs: before the 3rd, 7th, 11th.
    """
    return [min(notebooks - 1, max(0, int((k + 0.5) * notebooks / runs))) for k in range(runs)] if notebooks else []


def notebooks_figure(times_s: Mapping[str, float], total_s: float, slowest: int = 2) -> str:
    """``13 notebooks in 142 s, one at a time (slowest ex12_13 31 s, ex14 20 s)``."""
    ranked = sorted(times_s.items(), key=lambda item: -item[1])[:slowest]
    named = ", ".join(f"{short_name(stem)} {seconds:.1f} s" for stem, seconds in ranked)
    count = len(times_s)
    return (f"{count} notebook{'s' if count != 1 else ''} in {total_s:.1f} s, one at a time"
            + (f" (slowest {named})" if named else ""))


_TRACE_LINE = re.compile(r"^\++\t(\d+\.\d+)\t([^\t]*):(\d+)\t")


def line_costs(trace: str, end_epoch_s: float) -> List[Tuple[str, int, float, int]]:
    """Wall time per script line from a ``bash -x`` trace, slowest first.

    The trace's PS4 is ``+<TAB>$EPOCHREALTIME<TAB>$BASH_SOURCE:$LINENO<TAB>``; each traced
    command is charged the time until the next one starts (the last one until
    ``end_epoch_s``), so a line's cost includes the processes it runs -- a loop's line adds up
    over its iterations. Returns (file, line, seconds, commands traced).
    """
    events = []
    for text in trace.splitlines():
        match = _TRACE_LINE.match(text)
        if match:
            events.append((float(match.group(1)), match.group(2), int(match.group(3))))
    costs: Dict[Tuple[str, int], List[float]] = {}
    for index, (started, source, line) in enumerate(events):
        ended = events[index + 1][0] if index + 1 < len(events) else end_epoch_s
        entry = costs.setdefault((source, line), [0.0, 0])
        entry[0] += max(0.0, ended - started)
        entry[1] += 1
    ranked = [(source, line, seconds, int(count)) for (source, line), (seconds, count) in costs.items()]
    return sorted(ranked, key=lambda item: -item[2])


def _table_text(text: str, limit: int = 48) -> str:
    """Script text safe inside a Markdown table cell (no pipes, one line, short)."""
    text = " ".join(text.split())
    if len(text) > limit:
        text = text[:limit - 1] + "…"
    return text.replace("|", "\\|").replace("`", "'")


# -- the marker: every process started carries it ----------------------------------------------------

@contextmanager
def _environment(**values: str) -> Iterator[None]:
    """Set environment variables for what runs inside (kernels, setup inherit them); restore after."""
    before = {name: os.environ.get(name) for name in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _marked_processes(marker: str) -> Dict[int, str]:
    """pid -> command line of every process but this one whose environment has ``MARKER_ENV=marker``.

    Read from /proc (ROS 1 runs on Linux only); processes of other users are unreadable and skipped.
    """
    needle = f"{MARKER_ENV}={marker}".encode()
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            if needle not in (entry / "environ").read_bytes().split(b"\0"):
                continue
            status = (entry / "stat").read_text()
            if status.rsplit(")", 1)[-1].split()[0] == "Z":  # a zombie is dead, only not reaped yet
                continue
            found[int(entry.name)] = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
        except (OSError, IndexError):  # gone meanwhile, or another user's
            continue
    return found


def _stop_leftovers(marker: str, grace_s: float = LEFTOVER_GRACE_S) -> List[str]:
    """Wait for what this run started to end; stop what is left (SIGTERM, then SIGKILL, by pid) and name it."""
    deadline = time.monotonic() + grace_s
    left = _marked_processes(marker)
    while left and time.monotonic() < deadline:
        time.sleep(0.2)
        left = _marked_processes(marker)
    for sig in (signal.SIGTERM, signal.SIGKILL) if left else ():
        for pid in _marked_processes(marker):
            try:
                os.kill(pid, sig)
            except OSError:  # ended meanwhile
                pass
        deadline = time.monotonic() + 3.0
        while _marked_processes(marker) and time.monotonic() < deadline:
            time.sleep(0.1)
    return [f"{pid} {command[:120]}" for pid, command in left.items()]


# -- row 1: the notebooks ---------------------------------------------------------------------------

def _source_course(work_dir: Path) -> Path:
    """The course's source half in ``work_dir/course`` (the student versions are not run here)."""
    from hri_teleop.course.release import prepare_course_copy  # noqa: PLC0415 - loads nbgrader (2 s): only the notebooks row

    return prepare_course_copy(work_dir, release=False)


def _floor_notebook(path: Path) -> Path:
    """A one-cell notebook on the course's kernel (the kernel name the source notebooks use)."""
    import nbformat  # noqa: PLC0415 - heavy (0.7 s): only the notebooks row

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(FLOOR_CELL)]
    nb.metadata["kernelspec"] = {"name": KERNEL_NAME, "display_name": KERNEL_NAME, "language": "python"}
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, str(path))
    return path


def _execute(path: Path) -> Tuple[float, Dict[str, object]]:
    """Wall time of one :func:`hri_teleop.course.release.run_source` call (read, kernel up, cells, kernel down, grading)."""
    from hri_teleop.course.release import run_source  # noqa: PLC0415 - loads nbgrader (2 s): only the notebooks row

    started = time.monotonic()
    result = run_source(path)
    return time.monotonic() - started, result


def _notebooks_row(options: BenchOptions, progress: Progress) -> BenchRow:
    from hri_teleop.course.release import source_notebooks  # noqa: PLC0415 - loads nbgrader (2 s): only the notebooks row

    work = options.out_dir / "notebooks"
    course = _source_course(work)
    notebooks = source_notebooks(course)
    if options.smoke:
        notebooks = [nb for nb in notebooks if nb.stem in SMOKE_NOTEBOOKS]
    expected = len(SMOKE_NOTEBOOKS) if options.smoke else len(source_notebooks())
    if not notebooks or len(notebooks) != expected:
        raise BenchError(f"found {len(notebooks)} notebooks in {course / 'source'}, expected {expected}: "
                         f"is notebooks/source/ complete?")
    floor_path = _floor_notebook(work / "floor" / "floor.ipynb")
    floor_runs = FLOOR_RUNS_SMOKE if options.smoke else FLOOR_RUNS
    import nbclient  # noqa: F401, PLC0415 - heavy: imported before the first timed call, not inside it
    import nbgrader.utils  # noqa: F401, PLC0415 - the same

    floors_before = floor_positions(len(notebooks), floor_runs)
    with _environment(HRI_NOTEBOOK_FAST="1"):
        _check_floor(*_execute(floor_path))  # warm-up: the kernel's files into the page cache
        floors_s: List[float] = []
        times_s: Dict[str, float] = {}
        for number, notebook in enumerate(notebooks, 1):
            for _ in range(floors_before.count(number - 1)):
                seconds, result = _execute(floor_path)
                _check_floor(seconds, result)
                floors_s.append(seconds)
                progress(f"notebook floor {len(floors_s)}/{floor_runs} (kernel start, `{FLOOR_CELL}`, shutdown): "
                         f"{seconds:.2f} s")
            seconds, result = _execute(notebook)
            problems = notebook_problems(notebook.stem, result)
            if problems:
                raise BenchError(f"notebook {notebook.stem} failed, so it has no time:\n  " + "\n  ".join(problems[:10]))
            times_s[notebook.stem] = seconds
            progress(f"notebook {number}/{len(notebooks)} {notebook.stem}: {seconds:.1f} s")
    floor_s = statistics.median(floors_s)
    total_s = sum(times_s.values())
    count = len(times_s)
    values = {"total_s": total_s, "floor_s": floor_s, "notebooks": float(count),
              "slowest_s": max(times_s.values()), **{f"{stem}_s": s for stem, s in times_s.items()}}
    return BenchRow(
        benchmark=NOTEBOOKS_ROW,
        figure=notebooks_figure(times_s, total_s),
        reference=f"{count} × floor {floor_s:.2f} s = {count * floor_s:.1f} s (hri-teleop kernel, one cell "
                  f"`{FLOOR_CELL}`, median of {floor_runs})",
        ratio=total_s / (count * floor_s),
        ratio_means=f"total / ({count} × floor)",
        values=values,
    )


def _check_floor(seconds: float, result: Mapping[str, object]) -> None:
    problems = notebook_problems("floor notebook", result)
    if problems or not math.isfinite(seconds):
        raise BenchError("the one-cell notebook does not run on the hri-teleop kernel (run `make setup`):\n  "
                         + "\n  ".join(problems[:5]))


# -- row 2: make setup --------------------------------------------------------------------------------

def _timed(argv: Sequence[str], what: str, cwd: Path = REPO) -> Tuple[float, str]:
    """Wall time of one command that must succeed; its stdout and stderr."""
    started = time.monotonic()
    proc = subprocess.run(list(argv), cwd=str(cwd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=1800)
    seconds = time.monotonic() - started
    if proc.returncode != 0:
        tail = "\n".join(proc.stdout.strip().splitlines()[-10:])
        raise BenchError(f"{what} failed (exit {proc.returncode}):\n{tail}")
    return seconds, proc.stdout


def _setup_once(make: str, what: str) -> float:
    seconds, output = _timed([make, "--no-print-directory", "setup"], what)
    if _SETUP_DID_WORK.search(output):
        raise BenchError(f"{what} still had something to do, so it did not measure 'nothing missing':\n{output.strip()}")
    return seconds


def _traced_setup(trace_path: Path) -> List[Tuple[str, int, float, int]]:
    """One ``tools/setup.sh`` run under ``bash -x`` with timestamps; its cost per line.

    PS4 is set inside the shell: bash ignores PS4 from the environment when run as root.
    The trace goes to its own file (BASH_XTRACEFD), so setup's own output stays as it is.
    """
    script = ('exec 9>"$1"; BASH_XTRACEFD=9; PS4=$\'+\\t$EPOCHREALTIME\\t${BASH_SOURCE}:$LINENO\\t\'; '
              'set -x; . "$2"')
    trace_path.parent.mkdir(parents=True, exist_ok=True)
    _timed(["bash", "-c", script, "bash", str(trace_path), str(SETUP_SCRIPT)], "tools/setup.sh under bash -x")
    return line_costs(trace_path.read_text(encoding="utf-8", errors="replace"), time.time())


def _setup_row(options: BenchOptions, progress: Progress) -> BenchRow:
    make = shutil.which("make")
    if make is None:
        raise BenchError("make not found: install it (apt-get install make) to time `make setup`")
    python = REPO / ".venv" / "bin" / "python"
    if not python.is_file():
        raise BenchError(f"{python} not found: run `make setup` first")
    runs = SETUP_RUNS_SMOKE if options.smoke else SETUP_RUNS
    # Untimed first run: whatever is missing gets installed now, so the timed runs find nothing to do.
    _timed([make, "--no-print-directory", "setup"], "make setup (first, untimed run)")
    setup_s, floor_s = [], []
    for number in range(1, runs + 1):
        setup_s.append(_setup_once(make, "make setup"))
        floor_s.append(_timed([str(python), "-c", SETUP_FLOOR_CODE], f"python -c '{SETUP_FLOOR_CODE}'")[0])
        progress(f"make setup {number}/{runs}: {setup_s[-1]:.2f} s (import floor {floor_s[-1]:.2f} s)")
    median_s, floor_median_s = statistics.median(setup_s), statistics.median(floor_s)
    lines = _traced_setup(options.out_dir / "setup" / "setup-trace.txt")
    values = {"median_s": median_s, "floor_s": floor_median_s, "runs": float(runs),
              "min_s": min(setup_s), "max_s": max(setup_s)}
    where = ""
    if lines:
        source, line, seconds, count = lines[0]
        text = _script_line(Path(source), line)
        values.update({"slowest_line": float(line), "slowest_line_s": seconds})
        where = (f"; slowest line {Path(source).name}:{line} `{_table_text(text)}` {seconds:.2f} s"
                 + (f" over {count} commands" if count > 1 else ""))
        progress("make setup, cost per line (bash -x): " + "; ".join(
            f"{Path(s).name}:{n} {sec:.3f} s ×{c}" for s, n, sec, c in lines[:6]))
    return BenchRow(
        benchmark=SETUP_ROW,
        figure=f"median {median_s:.2f} s of {runs} runs{where}",
        reference=f".venv python -c '{SETUP_FLOOR_CODE}' {floor_median_s:.2f} s (median of {runs}, "
                  f"setup's own last check)",
        ratio=median_s / floor_median_s,
        ratio_means="median / import check",
        values=values,
    )


def _script_line(path: Path, number: int) -> str:
    try:
        return path.read_text(encoding="utf-8").splitlines()[number - 1]
    except (OSError, IndexError):
        return ""


# -- both ----------------------------------------------------------------------------------------------

def run(options: BenchOptions, progress: Progress) -> List[BenchRow]:
    """Both rows (notebooks, then make setup); a :class:`BenchError` if a run fails or leaves processes."""
    marker = uuid.uuid4().hex
    rows: List[BenchRow] = []
    failure: Optional[BaseException] = None
    with _environment(**{MARKER_ENV: marker}):
        try:
            rows.append(_notebooks_row(options, progress))
            rows.append(_setup_row(options, progress))
        except BaseException as exc:  # noqa: BLE001 - stop what was started, then raise it
            failure = exc
    left = _stop_leftovers(marker, grace_s=LEFTOVER_GRACE_S if failure is None else 2.0)
    if failure is not None:
        raise failure
    if left:
        raise BenchError("still running after the benchmark (now stopped): " + "; ".join(left))
    return rows
