"""What read-only notebook cells print, run without a kernel: rounded numbers with their units."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

from hri_teleop.course import sim
from hri_teleop.course.release import COURSE_DIR

#: A float as Python's repr prints it when nobody rounded it: 3.4600000000000026, 701.0
_RAW_FLOAT = re.compile(r"\d\.\d{6,}|\b\d+\.0\b")


def _cell(notebook: Path, grade_id: str) -> str:
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    return next("".join(c["source"]) for c in cells if c["metadata"].get("nbgrader", {}).get("grade_id") == grade_id)


def test_ex11s_simulated_press_prints_its_samples_rounded_with_units():
    notebook = COURSE_DIR / "source" / "lab" / "ex11_calibration.ipynb"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(_cell(notebook, "press"), {"sim": sim})  # the course's own read-only cell
    printed = out.getvalue()
    assert not _RAW_FLOAT.search(printed), printed
    assert re.search(r"t = \d+\.\d\d s: \d+", printed), printed


def test_samples_are_described_rounded_with_their_units():
    series = [(3.4600000000000026, 701.0), (3.4700000000000024, 699.0), (3.5, 0.045678)]
    assert sim.describe_samples(series, "gripper width", "m", last=2) == (
        "3 samples (time_s, gripper width); the last 2: t = 3.47 s: 699 m, t = 3.50 s: 0.0457 m")
