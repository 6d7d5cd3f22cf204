"""``make check`` in the student bundle: run every notebook headless and print its autograded points.

Before handing in, a student sees what the autograder will make of the notebooks and files: each
notebook runs top to bottom in its own ``hri-teleop`` kernel in its assignment folder, as nbgrader's
autograde runs it, and each autograded cell scores by nbgrader's rule (an error or stderr: 0; a
number as the result: that many points; else full points). The notebooks are not written back.

    python -m hri_teleop.apps.selfcheck FOLDER [--only ex05,ex12] [--timeout 600]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, MutableMapping, Optional, Sequence, Tuple

import nbformat
from nbclient import NotebookClient

from hri_teleop.ros.kernel import KernelError, install_kernelspec, ipc_kernel_config
from hri_teleop.ros.master_api import NO_MASTER_URI

__all__ = ["cell_points", "notebook_points", "find_notebooks", "private_masters", "main"]


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


def notebook_points(path: Path, timeout_s: int = 600) -> Dict[str, Any]:
    """Run one notebook (not saved) and return {"grades": {grade_id: [got, most]}, "error": str, "seconds": s}."""
    nb = nbformat.read(str(path), as_version=4)
    started = time.monotonic()
    error = ""
    try:
        # The kernel's own log (ipykernel's start-up warnings) is not the student's business:
        # what the cells print comes back through the kernel's channels, not its stderr.
        with ipc_kernel_config() as config:
            NotebookClient(nb, config=config, timeout=timeout_s, startup_timeout=120, allow_errors=True,
                           resources={"metadata": {"path": str(path.parent)}}).execute(stderr=subprocess.DEVNULL)
    except Exception as exc:  # noqa: BLE001 - a dead kernel or a timeout: say it, keep the points so far
        error = f"{type(exc).__name__}: {str(exc).strip().splitlines()[0] if str(exc).strip() else ''}"
    grades: Dict[str, List[float]] = {}
    for cell in nb.cells:
        meta = cell.get("metadata", {}).get("nbgrader", {})
        if cell.cell_type == "code" and meta.get("grade") and not meta.get("solution"):
            got, most = cell_points(cell)
            grades[meta["grade_id"]] = [got, most]
    return {"grades": grades, "error": error, "seconds": time.monotonic() - started}


def find_notebooks(folder: Path, only: Sequence[str] = ()) -> List[Path]:
    """The exercise notebooks of every assignment under ``folder`` (``ex*.ipynb``), optionally by name prefix."""
    found = sorted(p for p in folder.glob("*/ex*.ipynb") if ".ipynb_checkpoints" not in p.parts)
    if only:
        found = [p for p in found if any(p.stem.startswith(prefix) for prefix in only)]
    return found


def private_masters(env: MutableMapping[str, str]) -> None:
    """Each notebook on a private master of its kernel's own, as the autograder runs it: never on
    ``$ROS_MASTER_URI`` (on the lab PC that master carries the real robot), never in ``HRI_MODE``."""
    if env.get("ROS_MASTER_URI", NO_MASTER_URI) != NO_MASTER_URI:
        print(f"check: grading on private masters (ROS_MASTER_URI={env['ROS_MASTER_URI']} is not used)")
    env["ROS_MASTER_URI"] = NO_MASTER_URI
    env.pop("HRI_MODE", None)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="make check", description=__doc__.split("\n")[0])
    parser.add_argument("folder", nargs="?", default=".")
    parser.add_argument("--only", default="", help="comma-separated notebook name prefixes, e.g. ex05,ex12")
    parser.add_argument("--timeout", type=int, default=600, help="seconds per cell")
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
    total = most_total = 0.0
    print(f"check: {len(notebooks)} notebook(s), each run top to bottom (not saved)", flush=True)
    for path in notebooks:
        print(f"  {path.parent.name}/{path.name} ...", end="", flush=True)
        result = notebook_points(path, args.timeout)
        got = sum(g for g, _m in result["grades"].values())
        most = sum(m for _g, m in result["grades"].values())
        total, most_total = total + got, most_total + most
        print(f" {got:g}/{most:g} points ({result['seconds']:.0f} s)"
              + (f"; stopped: {result['error']}" if result["error"] else ""), flush=True)
        for grade_id, (g, m) in result["grades"].items():
            if g < m:
                print(f"      {grade_id}: {g:g}/{m:g} -- open the notebook and run this cell to see why")
    print(f"check: {total:g}/{most_total:g} autograded points in all (the rest is graded by hand)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
