"""Hostile submissions are graded (failed, with a clear message) without affecting anyone else.

An endless loop, a fork bomb, 100 MB of output, sys.exit at import and a write outside the
student's folder, graded by `hri-grade batch` two at a time next to a good submission: every
grade is recorded, the good one gets full marks, nothing is written outside, nothing is left
running. Then the same without bubblewrap (HRI_GRADE_SANDBOX=none, which batch grades only when told
to: --unsandboxed).
"""

from __future__ import annotations

import csv
import os
import time
from pathlib import Path

import pytest
from grading_helpers import answer_text, grader_env, hri_grade, open_folder, write_package

pytestmark = pytest.mark.ros

GOOD = answer_text("scripts/mapping_node.py")


def _hostile(head: str) -> str:
    return GOOD.replace("import rospy\n", head + "import rospy\n", 1)


@pytest.fixture
def outside():
    """A folder outside every submission (world-readable, like the instructor's files)."""
    yield from open_folder("hri-hostile-outside-")


def _submissions(root: Path, outside: Path, names) -> None:
    heads = {
        "endless_loop": "while True:\n    pass\n",
        "fork_bomb": "import os\nwhile True:\n    try:\n        os.fork()\n    except OSError:\n        pass\n",
        "huge_output": "import sys\nfor _ in range(100):\n    sys.stdout.write('x' * (1024 * 1024))\n",
        "sys_exit_at_import": "import sys\nsys.exit(3)\n",
        "writes_outside": f"open({str(outside / 'HACKED.txt')!r}, 'w').write('hacked')\n",
    }
    for name in names:
        text = GOOD if name == "good" else _hostile(heads[name])
        write_package(root / name / "hri_lab", {"scripts/mapping_node.py": text})


def _no_student_processes_left() -> bool:
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                uid = os.stat(f"/proc/{entry}").st_uid
                with open(f"/proc/{entry}/stat", "rb") as fh:
                    state = fh.read().rsplit(b")", 1)[1].split()[0]
            except (OSError, IndexError):
                continue
            if uid >= 200000 and state not in (b"Z", b"X"):
                return False
    return True


def _grades(out: Path):
    with open(out / "grades.csv") as fh:
        return {row["student"]: row for row in csv.DictReader(fh)}


EXPECTED_WORDS = {
    "endless_loop": "still running after",
    "fork_bomb": "processes and threads",
    "huge_output": "output limit",
    "sys_exit_at_import": "exited with status 3",
    "writes_outside": "outside its own folder",
}


def test_hostile_submissions_fail_clearly_and_the_good_one_keeps_full_marks(tmp_path, outside):
    names = ["good", *EXPECTED_WORDS]
    _submissions(tmp_path / "submitted", outside, names)
    proc = hri_grade("batch", str(tmp_path / "submitted"), "--out", str(tmp_path / "grades"), "--jobs", "2",
                     "--checks", "mapping-node", timeout=400)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    grades = _grades(tmp_path / "grades")
    assert set(grades) == set(names)
    assert all(row["status"] == "graded" for row in grades.values()), grades
    assert grades["good"]["score"] == grades["good"]["max_score"] == "20"
    for name, words in EXPECTED_WORDS.items():
        assert grades[name]["score"] == "0", name
        feedback = (tmp_path / "grades" / name / "feedback.txt").read_text()
        assert words in feedback, f"{name}: {words!r} not in\n{feedback}"
        assert os.path.getsize(tmp_path / "grades" / name / "feedback.txt") < 50_000
    assert not (outside / "HACKED.txt").exists()
    deadline = time.monotonic() + 5
    while not _no_student_processes_left() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _no_student_processes_left(), "student processes outlived their grading"


def test_without_bubblewrap_the_grader_says_so_once_and_still_contains_them(tmp_path, outside):
    names = ["good", "sys_exit_at_import", "huge_output"]
    _submissions(tmp_path / "submitted", outside, names)
    proc = hri_grade("batch", str(tmp_path / "submitted"), "--out", str(tmp_path / "grades"), "--jobs", "2",
                     "--checks", "mapping-node", "--unsandboxed", env=grader_env(HRI_GRADE_SANDBOX="none"),
                     timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.count("without bubblewrap") == 1, proc.stdout
    assert "without bubblewrap" not in proc.stderr, "notes go to stdout (nbgrader scores stderr as a failure)"
    grades = _grades(tmp_path / "grades")
    assert grades["good"]["score"] == "20" and grades["sys_exit_at_import"]["score"] == "0"
    assert "output limit" in (tmp_path / "grades" / "huge_output" / "feedback.txt").read_text()
