"""`make grade` on an nbgrader course: nbgrader's autograde for every submission, several at once, then feedback.

A small copy of the course (the preparation with two of its notebooks: Ex. 1 runs no ROS,
Ex. 4 grades the student's robot_params.yaml), so the whole run stays near a minute. Five
students hand in: a notebook that hangs (and starts a process that leaves its session;
first in name order, so its timeout runs beside the others), the answer key, the untouched
release, a robot_params.yaml that is a link to a file of the
instructor's, and a notebook that kills its kernel. While the first autogrades start, the
test holds the gradebook locked for longer than SQLite's default busy timeout (5 s), as a
slow concurrent writer would.
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import signal
import sqlite3
import subprocess
import threading
import time
from html import escape
from pathlib import Path

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course

from hri_teleop.grading.points import check_points, is_check_cell

pytestmark = pytest.mark.ros

ASSIGNMENT = "preparation"
NOTEBOOKS = ("ex01_fsr_and_arduino", "ex04_robot_params")
SECRET = "TOP-SECRET-INSTRUCTOR-TOKEN"
TIMEOUT_S = 45
LOCK_S = 7.0


@pytest.fixture(scope="module")
def course(tmp_path_factory) -> Path:
    """A course like notebooks/ with two notebooks of the preparation, its student version generated."""
    from hri_teleop.course.nodes import STUDENT_PACKAGE
    from hri_teleop.grading.cases.templates import generate_templates

    root = nbgrader_course(tmp_path_factory.mktemp("nbcourse") / "course", ASSIGNMENT, list(NOTEBOOKS))
    generate_templates(SOLUTIONS, root / "release" / ASSIGNMENT / STUDENT_PACKAGE)
    return root


def _answer_key_package(target: Path) -> None:
    from hri_teleop.grading.cases.templates import generate_answers

    generate_answers(SOLUTIONS, target)


def _replace_first_solution(folder: Path, notebook: str, code: str) -> None:
    import nbformat

    path = folder / f"{notebook}.ipynb"
    nb = nbformat.read(str(path), as_version=4)
    cell = next(c for c in nb.cells if c.cell_type == "code" and c.metadata.get("nbgrader", {}).get("solution"))
    cell.source = code
    nbformat.write(nb, str(path))


def _submissions(course: Path, work: Path) -> Path:
    submitted = course / "submitted"
    if submitted.exists():
        shutil.rmtree(submitted)
    alice = submitted / "alice" / ASSIGNMENT  # the answer key
    alice.mkdir(parents=True)
    for name in NOTEBOOKS:
        shutil.copy(course / "source" / ASSIGNMENT / f"{name}.ipynb", alice)
    _answer_key_package(alice / "hri_lab")
    shutil.copytree(course / "release" / ASSIGNMENT, submitted / "bob" / ASSIGNMENT)  # the untouched release
    ada = submitted / "ada" / ASSIGNMENT  # hangs, after starting a process in a session of its own
    shutil.copytree(alice, ada)
    _replace_first_solution(ada, NOTEBOOKS[0], (
        "import subprocess, time\n"
        "escapee = subprocess.Popen(['sleep', '600'], start_new_session=True)\n"
        "while True:\n    time.sleep(1)\n"))  # (its kernel's sandbox lets it write nowhere but its own folder)
    dave = submitted / "dave" / ASSIGNMENT  # robot_params.yaml is a link to the instructor's file
    shutil.copytree(alice, dave)
    (work / "secret.txt").write_text(SECRET + "\n")
    linked = dave / "hri_lab" / "config" / "robot_params.yaml"
    linked.unlink()
    linked.symlink_to(work / "secret.txt")
    erin = submitted / "erin" / ASSIGNMENT  # the kernel dies
    shutil.copytree(alice, erin)
    _replace_first_solution(erin, NOTEBOOKS[0], "import os, signal\nos.kill(os.getpid(), signal.SIGKILL)\n")
    return submitted


def _points(course: Path):
    """(autograded points, all points) of the assignment, from the source notebooks' nbgrader metadata."""
    auto = total = 0.0
    for name in NOTEBOOKS:
        for cell in json.loads((course / "source" / ASSIGNMENT / f"{name}.ipynb").read_text())["cells"]:
            meta = cell.get("metadata", {}).get("nbgrader", {})
            if meta.get("grade"):
                total += meta["points"]
                auto += 0 if meta.get("solution") else meta["points"]
    return auto, total


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            return fh.read().rsplit(b")", 1)[1].split()[0] not in (b"Z", b"X")
    except OSError:
        return False


def _processes_of(folder: Path):
    """Live processes that run in ``folder`` (a kernel's working folder is its autograded folder) or name it."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit() and int(entry) != os.getpid():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as fh:
                    cmdline = fh.read().replace(b"\0", b" ").decode(errors="replace")
                cwd = os.readlink(f"/proc/{entry}/cwd")
            except OSError:
                continue
            if (str(folder) in cmdline or cwd.startswith(str(folder))) and _alive(int(entry)):
                found.append(f"{entry} (in {cwd}): {cmdline}")
    return found


def _make_grade(submitted: Path, out: Path, on_line=None, timeout_s: float = 300.0, **variables: str):
    """Run `make -s -o setup grade DIR=... OUT=...`; returns (returncode, stdout lines, stderr)."""
    argv = ["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}",
            *[f"{k}={v}" for k, v in variables.items()]]
    stderr_path = out.parent / f"{out.name}.stderr"
    with open(stderr_path, "w") as stderr:
        proc = subprocess.Popen(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=stderr, text=True, env=grader_env(),
                                start_new_session=True)
        watchdog = threading.Timer(timeout_s, lambda: os.killpg(proc.pid, signal.SIGKILL))  # make and all it started
        watchdog.start()
        lines = []
        try:
            for line in proc.stdout:
                lines.append(line.rstrip("\n"))
                if on_line:
                    on_line(lines[-1])
            proc.wait()
        finally:
            watchdog.cancel()
    return proc.returncode, lines, stderr_path.read_text()


def _hold_gradebook(db: Path, seconds: float, held: list) -> None:
    con = sqlite3.connect(str(db), isolation_level=None, timeout=30)
    con.execute("BEGIN EXCLUSIVE")
    held.append(time.monotonic())
    time.sleep(seconds)
    con.execute("COMMIT")
    con.close()
    held.append(time.monotonic())


PROGRESS = re.compile(r"^\[\s*(\d+)/(\d+)\] (\S+) (\S+) (.+) \((\d+\.\d) s\)$")


def test_make_grade_autogrades_an_nbgrader_course_in_parallel_and_survives_hostile_submissions(course, tmp_path):
    from nbgrader.api import Gradebook

    submitted = _submissions(course, tmp_path)
    for student, at in (("alice", "2026-12-01 22:59:01.000000 UTC"), ("bob", "2026-12-01 22:59:00.000000 UTC")):
        (submitted / student / ASSIGNMENT / "timestamp.txt").write_text(at)  # as nbgrader collect writes it
    # the times that decide: the LMS export beside late.yaml (alice a second late, the others on time); the
    # timestamp.txt above is only shown
    (course / "submitted-at.csv").write_text(
        "student,assignment,submitted_at\n"
        f"alice,{ASSIGNMENT},2026-12-01 22:59:01.000000 UTC\nbob,{ASSIGNMENT},2026-12-01 22:59:00.000000 UTC\n"
        "ada,*,2026-12-01 20:00 UTC\ndave,*,2026-12-01 20:00 UTC\nerin,*,2026-12-01 20:00 UTC\n")
    (course / "late.yaml").write_text(f'deadline: {{{ASSIGNMENT}: "2026-12-01 23:59 Europe/Berlin"}}\nper_day: 10%\n'
                                      "times: submitted-at.csv\n")
    out = tmp_path / "grades"
    held: list = []
    locker = []

    def on_line(line: str) -> None:
        if line.startswith("autograding ") and not locker:
            locker.append(threading.Thread(target=_hold_gradebook, args=(course / "gradebook.db", LOCK_S, held)))
            locker[0].start()

    started = time.monotonic()
    code, lines, stderr = _make_grade(submitted, out, on_line, JOBS="2", TIMEOUT=str(TIMEOUT_S), CHECKS="robot-params")
    elapsed = time.monotonic() - started
    for thread in locker:
        thread.join()
    text = "\n".join(lines) + "\n" + stderr
    print(f"\n{text}\nmake grade: {elapsed:.0f} s")
    assert code == 2, text  # some submissions could not be graded: make says so
    assert len(held) == 2, "the gradebook lock was never taken"

    # progress: [k/N] student assignment score/max (time), one line per job, k counting up to N
    progress = [PROGRESS.match(line) for line in lines if line.startswith("[")]
    assert all(progress), text
    jobs = {(m.group(3), m.group(4)): m.group(5) for m in progress}
    students = ["ada", "alice", "bob", "dave", "erin"]
    assert set(jobs) == {(s, a) for s in students for a in (ASSIGNMENT, f"{ASSIGNMENT}/hri_lab")}, text
    assert [int(m.group(1)) for m in progress] == list(range(1, 11)) and {m.group(2) for m in progress} == {"10"}
    auto, total = _points(course)
    assert jobs[("alice", ASSIGNMENT)] == f"{auto:g}/{total:g}", text
    assert re.fullmatch(rf"[0-2]/{total:g}", jobs[("bob", ASSIGNMENT)]), text  # the release scores (almost) nothing
    assert jobs[("ada", ASSIGNMENT)] == (f"NOT GRADED: nbgrader autograde took longer than {TIMEOUT_S} s "
                                         f"(stopped in {NOTEBOOKS[0]}.ipynb)"), text
    assert "robot_params.yaml" in jobs[("dave", ASSIGNMENT)] and "links outside" in jobs[("dave", ASSIGNMENT)]
    assert "DeadKernelError" in jobs[("erin", ASSIGNMENT)], text
    assert "gradebook was locked" not in text, "a 60 s busy timeout outlasts a 7 s lock: no autograde may fail on it"

    # nbgrader's gradebook: the graded submissions, every autograded cell of the answer key at full points;
    # Ex. 4's check cell is none of them: its points are the files' (hri_teleop.grading.points)
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}", "hri-task4-teleoperation") as gb:
        key = gb.find_submission(ASSIGNMENT, "alice")
        assert (key.score, key.max_score, key.code_score, key.max_code_score) == (auto, total, auto, auto)
        for notebook in key.notebooks:
            for grade in notebook.grades:
                assert grade.auto_score in (None, grade.max_score), (notebook.name, grade.name, grade.auto_score)
                assert not is_check_cell(grade.name), grade.name
        release = gb.find_submission(ASSIGNMENT, "bob")
        assert release.max_score == total and release.score <= 2
        bob_score = release.score

    # HTML feedback (nbgrader generate_feedback) for the graded ones only; nothing of the secret anywhere
    for student in ("alice", "bob"):
        for name in NOTEBOOKS:
            html = course / "feedback" / student / ASSIGNMENT / f"{name}.html"
            assert html.is_file() and html.stat().st_size > 1000, html
    for student in ("ada", "dave", "erin"):
        assert not (course / "autograded" / student).exists() and not (course / "feedback" / student).exists()
    for folder in (course / "autograded", course / "feedback", out):
        for path in folder.rglob("*"):
            if path.is_file():
                assert SECRET not in path.read_text(errors="replace"), path

    # grades.csv: one row per student, the assignment's points (its notebooks' plus its files', each part
    # once) and the total, status with the reason
    with open(out / "grades.csv") as fh:
        rows = {row["student"]: row for row in csv.DictReader(fh)}
    assert list(rows) == students
    assert rows["alice"]["status"] == "graded" and rows["alice"]["message"] == ""
    files = check_points("robot-params")
    assert float(rows["alice"]["notebooks_score"]) == auto and float(rows["alice"]["notebooks_max"]) == total
    assert float(rows["alice"][f"{ASSIGNMENT}_score"]) == auto + files == \
        float(rows["alice"]["notebooks_score"]) + float(rows["alice"]["files_score"])
    assert float(rows["alice"][f"{ASSIGNMENT}_max"]) == total + files == \
        float(rows["alice"]["notebooks_max"]) + float(rows["alice"]["files_max"])
    assert rows["alice"]["needs_manual_grade"] == ASSIGNMENT  # the written answers wait for a grader
    assert rows["bob"]["status"] == "graded" and float(rows["bob"]["notebooks_score"]) == bob_score
    for student, words in (("ada", "took longer than"), ("dave", "links outside"), ("erin", "Kernel died")):
        assert rows[student]["status"] == "not graded" and words in rows[student]["message"], rows[student]
        assert rows[student][f"{ASSIGNMENT}_score"] == rows[student]["notebooks_score"] == ""

    # the student files graded beside: Gradescope results and feedback per student
    results = json.loads((out / "alice" / "results.json").read_text())
    assert results["score"] == 10 and all(t["status"] == "passed" for t in results["tests"])
    assert float(rows["alice"]["files_score"]) == float(rows["alice"]["files_max"]) == 10
    assert "robot-params" in (out / "bob" / "feedback.txt").read_text()
    assert (out / "alice" / ASSIGNMENT / "autograde.log").is_file()
    # each notebook after the first ran in the kernel started while the one before ran
    log = (out / "alice" / ASSIGNMENT / "autograde.log").read_text()
    assert log.count("took the spare kernel started ahead") == len(NOTEBOOKS) - 1, log

    # Ex. 4's check cell took the files job's result for the same package and the same seed (the student's,
    # in the files job's --seed and the kernel's HRI_GRADE_SEED) instead of running it again, and said
    # where its points count
    from hri_teleop.course.check import POINTS_NOTE
    from hri_teleop.grading.judge.reuse import REUSED_NOTE

    for student in ("alice", "bob"):
        ex04 = (course / "autograded" / student / ASSIGNMENT / "ex04_robot_params.ipynb").read_text()
        assert REUSED_NOTE[:60] in ex04 and POINTS_NOTE[:40] in ex04, student

    # the class report, lms.csv and the late policy (alice a second late: 10 % of the points; bob on time)
    rows = {row["student"]: row for row in csv.DictReader(open(out / "grades.csv"))}
    points = total + files  # the assignment's: the late policy takes its share of these
    assert (rows["alice"]["late_penalty"], rows["bob"]["late_penalty"]) == (f"{0.1 * points:g}", "0")
    assert float(rows["alice"]["total"]) == pytest.approx(auto + files - 0.1 * points) and rows["ada"]["total"] == ""
    lms = {row["SIS Login ID"]: row for row in csv.DictReader(open(out / "lms.csv"))}
    assert float(lms["alice"]["Task 4 total"]) == pytest.approx(float(rows["alice"]["total"]))
    assert float(lms["bob"]["Task 4 total"]) == float(rows["bob"]["notebooks_score"]) + float(rows["bob"]["files_score"])
    late = (f"late policy, {ASSIGNMENT}: submitted 2026-12-01 23:59:01+01:00 (submitted-at.csv, the LMS export; "
            "the submission's timestamp.txt says 2026-12-01 22:59:01+00:00 (not used)), 1 s after the deadline")
    assert (out / "alice" / "feedback.txt").read_text().startswith(late), (out / "alice" / "feedback.txt").read_text()
    for name in NOTEBOOKS:  # nbgrader's HTML feedback carries the line too (escaped)
        assert escape(late) in (course / "feedback" / "alice" / ASSIGNMENT / f"{name}.html").read_text()
    report = (out / "report.html").read_text()
    for words in ("Not judged (3)", "<td>timeout</td>", "<td>kernel died</td>", "refused (link outside",
                  f"{ASSIGNMENT}/ex04_robot_params:", "robot-params: loads", "Late submissions (1)",
                  "Waiting for grading by hand (1)"):
        assert words in report, words
    assert "ex04_robot_params: ex4_file" not in report  # the check's parts are items once, as the files' parts

    # STUDENT=bob: only bob's jobs run again; everyone else's rows, the report's other students stay
    code, lines, stderr = _make_grade(submitted, out, STUDENT="bob", CHECKS="robot-params")
    assert code == 0, "\n".join(lines) + stderr
    assert sorted(line.split()[1] for line in lines if line.startswith("[")) == ["bob", "bob"], lines
    again = {row["student"]: row for row in csv.DictReader(open(out / "grades.csv"))}
    assert list(again) == students and all(again[s] == rows[s] for s in students if s != "bob")
    assert again["bob"]["status"] == "graded" and "Not judged (3)" in (out / "report.html").read_text()

    # graded by hand (a written answer of alice's at full points), then REPORT=1: nothing graded, her score updated
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}", "hri-task4-teleoperation") as gb:
        manual = next(g for n in gb.find_submission(ASSIGNMENT, "alice").notebooks for g in n.grades
                      if g.auto_score is None)
        manual.manual_score, by_hand = manual.max_score, manual.max_score
        gb.db.commit()
    code, lines, stderr = _make_grade(submitted, out, REPORT="1")
    assert code == 0 and not [line for line in lines if line.startswith("[")], "\n".join(lines) + stderr
    after = {row["student"]: row for row in csv.DictReader(open(out / "grades.csv"))}
    assert float(after["alice"][f"{ASSIGNMENT}_score"]) == auto + by_hand + files
    assert float(after["alice"]["total"]) == pytest.approx(auto + by_hand + files - 0.1 * points)
    assert after["bob"] == again["bob"]

    # nothing of the hung submission is left: the process its kernel started in a session of its own neither
    # (its working folder is ada's, in the course)
    assert _processes_of(course) == []


def test_make_grade_names_what_is_wrong_with_the_course_in_one_line(course, tmp_path):
    out = tmp_path / "grades"
    errors = []

    def grade(folder: Path) -> str:
        code, lines, stderr = _make_grade(folder, out, timeout_s=120)
        assert code != 0 and not (out / "grades.csv").exists(), lines
        errors.append(stderr)
        return stderr

    # a folder under submitted/<student>/ that is no assignment of the course
    broken = tmp_path / "broken"
    (broken / "source" / ASSIGNMENT).mkdir(parents=True)
    shutil.copy(course / "nbgrader_config.py", broken)
    (broken / "submitted" / "alice" / "task4").mkdir(parents=True)
    stderr = grade(broken / "submitted")
    assert "alice/task4: the course has no source/task4" in stderr and "rename the folder" in stderr, stderr
    # an assignment that has source/ but was never generated into the gradebook
    shutil.copy(course / "gradebook.db", broken / "gradebook.db")
    (broken / "source" / "lab").mkdir()
    (broken / "submitted" / "alice" / "task4").rename(broken / "submitted" / "alice" / "lab")
    stderr = grade(broken / "submitted")
    assert "'lab' is not in the gradebook" in stderr and "make release" in stderr, stderr
    # no submissions in it
    shutil.rmtree(broken / "submitted" / "alice")
    assert "no submission folders" in grade(broken / "submitted")
    # a late.yaml beside the course that cannot be used: said before anything is graded
    (broken / "late.yaml").write_text("deadline: 2026-12-01 23:59:00\nper_day: 10%\n")
    stderr = grade(broken / "submitted")
    assert f"{broken / 'late.yaml'}: deadline" in stderr and "no time zone" in stderr, stderr
    # DIR missing
    assert "nowhere: no such folder" in grade(tmp_path / "nowhere")
    for stderr in errors:  # one line of ours (make adds its own "Error" line)
        assert len([line for line in stderr.splitlines() if line.startswith("hri-grade:")]) == 1, stderr
        assert len([line for line in stderr.splitlines() if not line.startswith("make")]) == 1, stderr


def test_make_grade_says_when_nbgrader_is_missing(course, tmp_path):
    (tmp_path / "hide" / "nbgrader").mkdir(parents=True)  # a Python without nbgrader: importing it fails
    (tmp_path / "hide" / "nbgrader" / "__init__.py").write_text("raise ImportError('No module named nbgrader')\n")
    (course / "submitted" / "zoe" / ASSIGNMENT).mkdir(parents=True, exist_ok=True)
    try:
        proc = subprocess.run(["make", "-s", "-o", "setup", "grade", f"DIR={course / 'submitted'}",
                               f"OUT={tmp_path / 'grades'}"], cwd=REPO, capture_output=True, text=True, timeout=120,
                              env=grader_env(PYTHONPATH=str(tmp_path / "hide")))
    finally:
        shutil.rmtree(course / "submitted" / "zoe")
    assert proc.returncode != 0
    assert "nbgrader is not installed" in proc.stderr and "make setup" in proc.stderr, proc.stderr


def test_each_assignments_files_get_the_checks_its_notebooks_call():
    """make grade grades submitted/<student>/<assignment>/hri_lab with the checks that assignment's notebooks call."""
    from hri_teleop.course.release import COURSE_DIR
    from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS, ASSIGNMENTS
    from hri_teleop.grading.checks import CHECKS

    for assignment in ASSIGNMENTS:
        called = set()
        for path in (COURSE_DIR / "source" / assignment).glob("*.ipynb"):
            # grade_<check>(...) or the facade's check.<check>(...); Ex. 8/9 split teleoperation in two
            for name in re.findall(r"\b(?:grade_|check\.)(\w+)\(", path.read_text()):
                called.add(re.sub(r"^teleoperation_(parts|node)$", "teleoperation", name).replace("_", "-"))
        assert called <= set(CHECKS), called
        assert set(ASSIGNMENT_CHECKS[assignment]) == called, assignment
