"""``make check`` in the student bundle: every notebook headless, then the hri_lab files, with the feedback.

Each notebook runs top to bottom in its own kernel, scored by nbgrader's rule, in a copy of its assignment
folder (its last names kept, so the hidden inputs are those of the notebook in place); then the files get
their checks' points (:mod:`hri_teleop.apps.files_check`). What lost points is printed as its cell shows it.

    python -m hri_teleop.apps.selfcheck FOLDER [--only ex05,ex12] [--timeout 600] [--jobs N]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any, AsyncIterator, Dict, List, MutableMapping, Optional, Sequence, Set, Tuple

import nbformat
from nbclient import NotebookClient
from traitlets.config import Config

from hri_teleop.apps.files_check import FilesHalf, scratch_copy
from hri_teleop.course.check import KEEPS_RESULT
from hri_teleop.grading.judge import reuse
from hri_teleop.ros.kernel import KernelError, install_kernelspec
from hri_teleop.ros.master_api import NO_MASTER_URI

__all__ = ["cell_points", "cell_feedback", "notebook_lines", "default_jobs", "find_notebooks", "kept_checks",
           "private_masters", "run_order", "main"]

#: The notebooks that take longest (ROS, catkin, the checks), started first so that the notebooks
#: side by side end together; the others follow in their folder's order.
SLOW_FIRST = ("ex12", "ex06", "ex09", "ex10", "ex05", "ex02", "ex14", "ex15")
#: Lines of a cell's output shown for a cell that lost points (the last ones: the verdict).
SHOWN_LINES = 15
_ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]|\x1b\][^\x07]*\x07")


def _number(text: str) -> Optional[float]:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def cell_points(cell: Any) -> Tuple[float, float]:
    """(points got, points possible) of one executed autograded code cell, as nbgrader's autograde decides."""
    most = float(cell["metadata"]["nbgrader"]["points"])
    for output in cell.get("outputs", []):
        kind = output.get("output_type")
        if kind == "error" or (kind == "stream" and output.get("name") == "stderr"):
            return 0.0, most
        if kind == "execute_result":  # nbgrader: a number shown as the cell's result is a partial grade
            value = _number(output.get("data", {}).get("text/plain", ""))
            return (min(most, value) if value is not None and value >= 0 else most), most
    return most, most


def cell_feedback(cell: Any, limit: int = SHOWN_LINES) -> List[str]:
    """The text an executed cell shows in the notebook (printed lines, results, the error's last line),
    without colour codes; its last ``limit`` lines when longer."""
    lines: List[str] = []
    for output in cell.get("outputs", []):
        kind = output.get("output_type")
        if kind == "stream":
            lines += str(output.get("text", "")).splitlines()
        elif kind in ("display_data", "execute_result"):
            lines += str(output.get("data", {}).get("text/plain", "")).splitlines()
        elif kind == "error":
            lines.append(f"{output.get('ename', '')}: {output.get('evalue', '')}".strip(": "))
    lines = [_ANSI.sub("", line).rstrip() for line in lines]
    lines = [line for line in lines if line.strip()]
    return lines if len(lines) <= limit else ["..."] + lines[-limit:]


def _grades(nb: Any) -> Dict[str, Any]:
    grades: Dict[str, Any] = {}
    for cell in nb.cells:
        meta = cell.get("metadata", {}).get("nbgrader", {})
        if cell.cell_type == "code" and meta.get("grade") and not meta.get("solution"):
            grades[meta["grade_id"]] = [*cell_points(cell), cell_feedback(cell)]
    return grades


_CHECK_CALL = re.compile(r"\bcheck\.(\w+)\(")


def kept_checks(notebooks: Sequence[Path]) -> Dict[str, Set[str]]:
    """assignment -> the checks whose whole result a check cell of ``notebooks`` keeps for the files' half
    (:data:`hri_teleop.course.check.KEEPS_RESULT`); the files' half starts the others at once."""
    kept: Dict[str, Set[str]] = {}
    for path in notebooks:
        for cell in nbformat.read(str(path), as_version=4).cells:
            if cell.cell_type == "code":
                for name in _CHECK_CALL.findall(cell.source):
                    if name in KEEPS_RESULT:
                        kept.setdefault(path.parent.name, set()).add(KEEPS_RESULT[name])
    return kept


def default_jobs(cpu_count: Optional[int]) -> int:
    """Notebooks at a time: one more than the cores, as the grader's checks (a notebook waits on kernel,
    master and node starts and on its nodes part of its time). The answer key's bundle on a shared 2-core
    machine (load 4-7 from others): 2 at a time 61 and 65 s, 3 at a time 53 and 61 s."""
    return max(1, cpu_count or 1) + 1


def find_notebooks(folder: Path, only: Sequence[str] = ()) -> List[Path]:
    """The exercise notebooks of every assignment under ``folder`` (``ex*.ipynb``), optionally by name prefix."""
    found = sorted(p for p in folder.glob("*/ex*.ipynb") if ".ipynb_checkpoints" not in p.parts)
    if only:
        found = [p for p in found if any(p.stem.startswith(prefix) for prefix in only)]
    return found


def run_order(notebooks: Sequence[Path]) -> List[Path]:
    """The slow notebooks first (:data:`SLOW_FIRST`), the rest in their order."""
    def rank(path: Path) -> int:
        return next((i for i, prefix in enumerate(SLOW_FIRST) if path.stem.startswith(prefix)), len(SLOW_FIRST))
    return sorted(notebooks, key=rank)


def private_masters(env: MutableMapping[str, str]) -> None:
    """Each notebook on a private master of its kernel's own, as the autograder runs it: never on
    ``$ROS_MASTER_URI`` (on the lab PC that master carries the real robot), never in ``HRI_MODE``."""
    if env.get("ROS_MASTER_URI", NO_MASTER_URI) != NO_MASTER_URI:
        print(f"check: grading on private masters (ROS_MASTER_URI={env['ROS_MASTER_URI']} is not used)")
    env["ROS_MASTER_URI"] = NO_MASTER_URI
    env.pop("HRI_MODE", None)


class _Client(NotebookClient):
    """nbclient's client with the kernel's shutdown left to the caller (it overlaps the next notebook)
    and no signal handlers of its own (notebooks run side by side; Ctrl-C stops every kernel)."""

    @asynccontextmanager
    async def async_setup_kernel(self, **kwargs: Any) -> AsyncIterator[None]:
        if self.km is None:
            self.km = self.create_kernel_manager()
        if not self.km.has_kernel:
            await self.async_start_new_kernel(**kwargs)
        if self.kc is None:
            await self.async_start_new_kernel_client()
        yield


class _Pool:
    """Runs notebooks in one event loop; every kernel started is stopped, once, before :meth:`close` returns."""

    def __init__(self, scratch: Path, env: Dict[str, str], timeout_s: int) -> None:
        self.scratch, self.env, self.timeout_s = scratch, env, timeout_s
        self.stops: Dict[_Client, "asyncio.Future[None]"] = {}  # one per kernel started, done when it has stopped
        self.running: Set[_Client] = set()
        self.stopped = False

    async def run(self, index: int, path: Path) -> Dict[str, Any]:
        """Run ``path`` (in a copy of its folder; not saved): {"grades": {id: [got, most, lines]}, "error", "seconds"}."""
        started = time.monotonic()
        nb = nbformat.read(str(path), as_version=4)
        config = Config()  # Unix sockets in a folder of this kernel's own (no port race between kernels)
        config.KernelManager.transport = "ipc"
        config.KernelManager.ip = str(self.scratch / f"k{index}")
        error = ""
        try:
            where = scratch_copy(path.parent.parent, path.parent.name, self.scratch / f"nb{index}")
            client = _Client(nb, config=config, timeout=self.timeout_s, startup_timeout=120, allow_errors=True,
                             resources={"metadata": {"path": str(where)}})
            self.running.add(client)
            try:
                # The kernel's own log (ipykernel's start-up warnings) is not the student's business:
                # what the cells print comes back through the kernel's channels, not its stderr.
                await client.async_execute(env=self.env, stderr=subprocess.DEVNULL)
            finally:
                self.running.discard(client)
                self._stop(client)  # while the next notebook runs
        except asyncio.CancelledError:
            if not self.stopped:  # nbclient's own tasks end so when their kernel is shut down under them
                raise
            error = "stopped"
        except Exception as exc:  # noqa: BLE001 - a dead kernel or a timeout: say it, keep the points so far
            text = str(exc).strip()
            error = f"{type(exc).__name__}: {text.splitlines()[0] if text else ''}"
        return {"grades": _grades(nb), "error": error, "seconds": time.monotonic() - started}

    def _stop(self, client: _Client) -> None:
        """Shut ``client``'s kernel down as Jupyter does (the kernel stops its nodes and roscore), once."""
        async def stop() -> None:
            try:
                await client._async_cleanup_kernel()
            except Exception:  # noqa: BLE001 - already gone
                pass
        if client not in self.stops and client.km is not None:
            self.stops[client] = asyncio.ensure_future(stop())

    def stop(self) -> None:
        """Ctrl-C: no notebook more, and the running ones' kernels shut down (their cells end at once)."""
        self.stopped = True
        for client in list(self.running):
            self._stop(client)

    async def close(self) -> None:
        """Wait for every kernel to have stopped (its nodes and roscore with it)."""
        if self.stops:
            await asyncio.gather(*self.stops.values(), return_exceptions=True)


def notebook_lines(path: Path, result: Dict[str, Any]) -> List[str]:
    """The notebook's points, then each autograded cell that lost points with what the cell shows."""
    got = sum(g for g, _m, _f in result["grades"].values())
    most = sum(m for _g, m, _f in result["grades"].values())
    lines = [f"  {path.parent.name}/{path.name} ... {got:g}/{most:g} points ({result['seconds']:.0f} s)"
             + (f"; stopped: {result['error']}" if result["error"] else "")]
    for grade_id, (g, m, feedback) in result["grades"].items():
        if g < m:
            lines.append(f"      {grade_id}: {g:g}/{m:g}" + (", the cell shows:" if feedback else
                                                               ": the cell shows nothing (it did not run)"))
            lines += [f"        {line}" for line in feedback]
    return lines


async def run_notebooks(notebooks: Sequence[Path], scratch: Path, env: Dict[str, str], timeout_s: int,
                        jobs: int) -> Tuple[float, float, bool]:
    """Run ``notebooks`` ``jobs`` at a time, printing each one's lines when it ends; (points, possible,
    stopped by Ctrl-C or SIGTERM)."""
    pool = _Pool(scratch, env, timeout_s)
    queue = list(enumerate(run_order(notebooks)))
    totals = [0.0, 0.0]

    async def worker() -> None:
        while queue and not pool.stopped:
            index, path = queue.pop(0)
            result = await pool.run(index, path)
            if pool.stopped:
                return
            totals[0] += sum(g for g, _m, _f in result["grades"].values())
            totals[1] += sum(m for _g, m, _f in result["grades"].values())
            print("\n".join(notebook_lines(path, result)), flush=True)

    # Ctrl-C or SIGTERM: no notebook more, the running ones' kernels shut down, and every kernel has
    # stopped as Jupyter stops it (its nodes and roscore with it) before make check ends.
    loop = asyncio.get_running_loop()
    signals = [signal.SIGINT, signal.SIGTERM] if threading.current_thread() is threading.main_thread() else []
    for signum in signals:
        loop.add_signal_handler(signum, pool.stop)
    try:
        await asyncio.gather(*(worker() for _ in range(max(1, min(jobs, len(queue))))))
    finally:
        await asyncio.shield(pool.close())
        for signum in signals:
            loop.remove_signal_handler(signum)
    return totals[0], totals[1], pool.stopped


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="make check", description=__doc__.split("\n")[0])
    parser.add_argument("folder", nargs="?", default=".")
    parser.add_argument("--only", default="", help="comma-separated notebook name prefixes, e.g. ex05,ex12")
    parser.add_argument("--timeout", type=int, default=600, help="seconds per cell")
    parser.add_argument("--jobs", type=int, default=0, help="notebooks at a time (default: one more than the cores)")
    args = parser.parse_args(argv)
    folder = Path(args.folder).resolve()
    only = [p.strip() for p in args.only.split(",") if p.strip()]
    notebooks = find_notebooks(folder, only)
    if not notebooks:
        print(f"check: no notebook {'matching ' + args.only + ' ' if only else ''}in {folder}/*/ex*.ipynb: "
              "run `make check` in the bundle's top folder", file=sys.stderr)
        return 1
    try:
        install_kernelspec()
    except KernelError as exc:
        print(f"check: {exc}", file=sys.stderr)
        return 1
    os.environ.setdefault("HRI_NOTEBOOK_FAST", "1")  # real-time demos run short; the checks are the same
    private_masters(os.environ)
    for key in (reuse.WRITE_ENV, reuse.READ_ENV):  # this run's own results only
        os.environ.pop(key, None)
    scratch = Path(tempfile.mkdtemp(prefix="hri-check-"))
    files: Optional[FilesHalf] = None
    try:
        results = scratch / "results"
        kernel_env = dict(os.environ, **{reuse.WRITE_ENV: str(results)})
        jobs = args.jobs or default_jobs(os.cpu_count())
        print(f"check: {len(notebooks)} notebook(s), each run top to bottom in a copy of its folder "
              f"(your folders are not changed), {min(jobs, len(notebooks))} at a time", flush=True)
        files = FilesHalf(folder, only, scratch / "files")  # the files as they are now, in a copy
        files.start(kept_checks(notebooks))  # the checks no check cell runs whole: beside the notebooks
        try:
            total, most_total, stopped = asyncio.run(run_notebooks(notebooks, scratch, kernel_env, args.timeout,
                                                                   jobs))
        except (asyncio.CancelledError, KeyboardInterrupt):
            total = most_total = 0.0
            stopped = True
        if stopped:
            print("check: stopped (Ctrl-C); every notebook's kernel, its nodes and roscore have stopped",
                  file=sys.stderr, flush=True)
            return 130
        print(f"check: {total:g}/{most_total:g} autograded points in all (the rest is graded by hand)", flush=True)
        os.environ[reuse.READ_ENV] = str(results)
        files.finish()
    finally:
        if files is not None:
            files.join()
        shutil.rmtree(scratch, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
