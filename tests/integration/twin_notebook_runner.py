"""Run one notebook top to bottom, headless, its kernel on the master this process's environment names.

    python twin_notebook_runner.py NOTEBOOK OUT.json

As a lab engineer runs a course notebook on the lab PC (tests/integration/test_lab_twin_notebooks.py
points the environment at the lab twin): every cell, errors allowed, nothing saved. OUT.json gets,
per code cell, what it printed and its error, the autograded cells' points as nbgrader counts them, and
the check cells' points as they print them (a check cell is read-only and worth no nbgrader points: its
points are the files').
"""

from __future__ import annotations

import json
import re
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbgrader.utils import determine_grade, is_grade, is_solution

from hri_teleop.ros.kernel import ipc_kernel_config


def run(path: Path, timeout_s: int = 300) -> dict:
    nb = nbformat.read(str(path), as_version=4)
    started = time.monotonic()
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=timeout_s, startup_timeout=120, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()
    cells, grades, checks = [], {}, {}
    for number, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        stdout = "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream" and o.name == "stdout")
        stderr = "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream" and o.name == "stderr")
        error = next((f"{o.ename}: {o.evalue.strip()[:600]}" for o in cell.outputs if o.output_type == "error"), "")
        grade_id = cell.metadata.get("nbgrader", {}).get("grade_id", "")
        cells.append({"number": number, "grade_id": grade_id, "stdout": stdout, "stderr": stderr, "error": error})
        if is_grade(cell) and not is_solution(cell):
            grades[grade_id] = list(determine_grade(cell))
        total = re.findall(r"^total: ([0-9.]+)/([0-9.]+)", stdout, re.M)
        if total:
            checks[grade_id] = [float(total[-1][0]), float(total[-1][1])]
    return {"cells": cells, "grades": grades, "checks": checks, "seconds": time.monotonic() - started}


if __name__ == "__main__":
    result = run(Path(sys.argv[1]))
    Path(sys.argv[2]).write_text(json.dumps(result), encoding="utf-8")
