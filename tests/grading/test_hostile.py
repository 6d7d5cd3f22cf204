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
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import List, Set, Tuple

import pytest
from grading_helpers import answer_text, grader_env, hri_grade, open_folder, write_package

from hri_teleop.ros.proc_table import STUDENT_UID_BASE, proc_stat, process_trees

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


def _no_student_processes_left(uids: Set[int]) -> bool:
    """No live process runs as one of ``uids`` (this batch's student uids: other tests grade beside it)."""
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                uid = os.stat(f"/proc/{entry}").st_uid
            except OSError:
                continue
            found = proc_stat(f"/proc/{entry}/stat") if uid in uids else None
            if found is not None and found[1] not in (b"Z", b"X"):
                return False
    return True


def _batch_watching_its_processes(*args: str, timeout_s: float) -> Tuple["subprocess.CompletedProcess[str]", Set[int]]:
    """``hri-grade ARGS``, and every pid of its process tree seen while it ran (polled every 20 ms).

    A student's uid is STUDENT_UID_BASE + the pid of the grader process that runs its code, a
    process of this tree: so these are the only uids this batch's student code can run as."""
    exe = Path(sys.executable).with_name("hri-grade")
    if not exe.exists():
        pytest.fail("hri-grade is not installed: run 'make setup' (pyproject.toml [project.scripts])")
    proc = subprocess.Popen([str(exe), *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=grader_env(), stdin=subprocess.DEVNULL)
    seen: Set[int] = set()
    chunks: List[str] = []
    reader = threading.Thread(target=lambda: chunks.append(proc.stdout.read() if proc.stdout else ""), daemon=True)
    reader.start()
    deadline = time.monotonic() + timeout_s
    while proc.poll() is None and time.monotonic() < deadline:
        seen.update(process_trees([proc.pid]))
        time.sleep(0.02)
    if proc.poll() is None:
        proc.kill()
    proc.wait()
    reader.join(30.0)
    return subprocess.CompletedProcess(proc.args, proc.returncode, "".join(chunks), ""), seen


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
    proc, pids = _batch_watching_its_processes("batch", str(tmp_path / "submitted"), "--out", str(tmp_path / "grades"),
                                               "--jobs", "2", "--checks", "mapping-node", timeout_s=400)
    assert proc.returncode == 0, proc.stdout
    uids = {STUDENT_UID_BASE + pid for pid in pids}
    assert len(pids) > 2, "the batch's jobs were never seen: the check below would be empty"
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
    while not _no_student_processes_left(uids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _no_student_processes_left(uids), "student processes outlived their grading"


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
