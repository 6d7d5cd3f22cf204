"""Lateness a student cannot forge: the LMS export decides, the submission's own timestamp.txt is shown and
never followed, and an unknown time is said, never waived.

First over an OUT written by hand (the end of make grade: late lines, grades.csv, lms.csv, the report's
rows, the run's lines), then through `make grade` itself on plain folders, with honest students in the batch.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
from pathlib import Path
from typing import Dict, Iterator, List, Tuple

import pytest
from grading_helpers import REPO, answer_text, grader_env, open_folder, write_package

from hri_teleop.grading.batch.class_results import read_class, write_rows, write_summary
from hri_teleop.grading.batch.finish import add_totals, apply_late
from hri_teleop.grading.batch.late import read_late_policy
from hri_teleop.grading.batch.lms import lms_table
from hri_teleop.grading.batch.report_data import late_rows

#: What the secret file holds: it must appear nowhere the grader writes.
SECRET = "root:$6$SECRET-7f3a9c:19000:0:99999:7:::"
LATE_YAML = 'deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\ncap: 50%\n'
#: The LMS export: honest a minute late (1 day started), forger 2 days and a second (3 days), linker and
#: garbage as the LMS saw them; nobody has no row.
TIMES = ("student,assignment,submitted_at\n"
         "honest,*,2026-12-02T00:00:00+01:00\n"
         "forger,*,2026-12-03T23:59:01+01:00\n"
         "linker,*,2026-12-01T23:00:00+01:00\n"
         "garbage,*,2026-12-02T10:00:00+01:00\n")


@pytest.fixture
def root() -> Iterator[Path]:
    yield from open_folder("hri-late-hostile-")


def _submissions(root: Path) -> Tuple[Path, Path]:
    """DIR with five students' task4/ (nbgrader's layout) and their timestamp.txt; the secret outside DIR."""
    secret = root / "shadow"
    secret.write_text(SECRET + "\n")
    secret.chmod(0o600)
    submitted = root / "submitted"
    stamps: Dict[str, str] = {"honest": "2026-12-01 23:00:00.000000",       # nbgrader's UTC: the truth
                              "forger": "2026-11-30 12:00:00.000000",       # forged: on time by its own word
                              "nobody": "2026-11-30 12:00:00.000000"}       # forged, and no row in the LMS export
    for student in ("honest", "forger", "linker", "garbage", "nobody"):
        folder = submitted / student / "task4"
        write_package(folder / "hri_lab", {"config/robot_params.yaml": answer_text("config/robot_params.yaml")})
        if student in stamps:
            (folder / "timestamp.txt").write_text(stamps[student])
    (submitted / "linker" / "task4" / "timestamp.txt").symlink_to(secret)
    (submitted / "garbage" / "task4" / "timestamp.txt").write_text(
        "<script>alert(1)</script>" + SECRET + "A" * 3 * 1024 ** 2)
    return submitted, secret


def _nothing_leaked(out: Path) -> None:
    for dirpath, _dirs, files in os.walk(out):
        for name in files:
            data = (Path(dirpath) / name).read_bytes()
            assert b"SECRET-7f3a9c" not in data and b"<script>alert" not in data, Path(dirpath) / name


def _fake_out(root: Path, submitted: Path) -> Path:
    """OUT as make grade's jobs leave it in folders mode: everyone graded 10/10 on robot-params."""
    out = root / "out"
    entries = []
    for student in sorted(p.name for p in submitted.iterdir()):
        (out / student).mkdir(parents=True)
        (out / student / "feedback.txt").write_text("robot-params: 10/10\n")
        (out / student / "results.json").write_text(json.dumps(
            {"score": 10, "tests": [{"name": "robot-params: loads", "score": 10, "max_score": 10}]}))
        entries.append({"student": student, "score": 10.0, "max_score": 10.0, "status": "graded", "seconds": 1.0,
                        "message": ""})
    write_summary(out, entries)
    write_rows(out / "grades.csv", ["student", "score"], [{"student": e["student"], "score": "10"} for e in entries])
    return out


def _rows(out: Path) -> Dict[str, Dict[str, str]]:
    with open(out / "grades.csv", newline="") as fh:
        return {r["student"]: r for r in csv.DictReader(fh)}


#: (late_penalty, total) in grades.csv with the LMS export, and without it (every time unknown).
WITH_TIMES = {"honest": ("1", "9"), "forger": ("3", "7"), "linker": ("0", "10"), "garbage": ("1", "9"),
              "nobody": ("unknown", "")}
WITHOUT_TIMES = {s: ("unknown", "") for s in WITH_TIMES}


def test_the_lms_export_decides_a_forged_or_linked_timestamp_gains_nothing_and_unknown_is_said(root):
    submitted, _secret = _submissions(root)
    out = _fake_out(root, submitted)
    (submitted / "late.yaml").write_text(LATE_YAML)
    said: List[str] = []
    apply_late(out, read_late_policy(submitted / "late.yaml"), lambda name, _a: submitted / name, progress=said.append)
    results = read_class(out, late_policy="late.yaml")
    add_totals(out / "grades.csv", results)
    assert {s: (r["late_penalty"], r["total"]) for s, r in _rows(out).items()} == WITHOUT_TIMES
    assert [r[-1] for r in lms_table(results)[1]] == [""] * 5  # no total to import until the times are known
    unknown = [line for line in said if "submission time unknown" in line]
    assert sorted(line.split(":")[1].strip() for line in unknown) == sorted(WITH_TIMES), said
    _nothing_leaked(out)

    (submitted / "times.csv").write_text(TIMES)
    (submitted / "late.yaml").write_text(LATE_YAML + "times: times.csv\n")
    said.clear()
    apply_late(out, read_late_policy(submitted / "late.yaml"), lambda name, _a: submitted / name, progress=said.append)
    results = read_class(out, late_policy="late.yaml")
    add_totals(out / "grades.csv", results)
    assert {s: (r["late_penalty"], r["total"]) for s, r in _rows(out).items()} == WITH_TIMES
    assert {r[0]: r[-1] for r in lms_table(results)[1]} == {s: t for s, (_p, t) in WITH_TIMES.items()}
    feedback = {s: (out / s / "feedback.txt").read_text().splitlines()[0] for s in WITH_TIMES}
    assert ("late policy: submitted 2026-12-03 23:59:01+01:00 (times.csv, the LMS export; the submission's a "
            "sub-folder's timestamp.txt says 2026-11-30 12:00:00+00:00 (not used)), 2 d after the deadline") \
        in feedback["forger"]
    assert "penalty 30% of 10 points = 3" in feedback["forger"]
    assert "timestamp.txt is a link (not followed)" in feedback["linker"]
    assert "timestamp.txt is larger than 1024 bytes" in feedback["garbage"]
    assert "submission time unknown (times.csv has no row for nobody, files" in feedback["nobody"]
    assert [line for line in said if line.startswith("late policy: nobody: submission time unknown")]
    assert {(r.student, r.lateness.stamp_refused) for r in late_rows(results.students)} == {
        ("honest", False), ("forger", False), ("linker", True), ("garbage", True), ("nobody", False)}
    _nothing_leaked(out)


def _make_grade(submitted: Path, out: Path, *variables: str) -> Tuple[int, str, str]:
    proc = subprocess.Popen(["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}", *variables],
                            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=grader_env(),
                            start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=600)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        raise
    return proc.returncode, stdout, stderr


@pytest.mark.ros
def test_make_grade_takes_lateness_from_the_lms_export_and_never_from_what_students_wrote(root):
    submitted, _secret = _submissions(root)
    (submitted / "late.yaml").write_text(LATE_YAML)
    out = root / "grades"
    code, stdout, stderr = _make_grade(submitted, out, "CHECKS=robot-params", "JOBS=2")
    assert code == 0, stdout[-3000:] + stderr[-3000:]
    rows = _rows(out)
    assert all(r["status"] == "graded" and r["score"] == "10" for r in rows.values()), rows
    assert {s: (r["late_penalty"], r["total"]) for s, r in rows.items()} == WITHOUT_TIMES
    for student in WITH_TIMES:  # one line each in the run's output
        assert len([line for line in stdout.splitlines()
                    if line.startswith(f"late policy: {student}: submission time unknown")]) == 1, stdout
    _nothing_leaked(out)

    (submitted / "times.csv").write_text(TIMES)
    (submitted / "late.yaml").write_text(LATE_YAML + "times: times.csv\n")
    code, stdout, stderr = _make_grade(submitted, out, "REPORT=1")
    assert code == 0, stdout[-3000:] + stderr[-3000:]
    rows = _rows(out)
    assert {s: (r["late_penalty"], r["total"]) for s, r in rows.items()} == WITH_TIMES
    with open(out / "lms.csv", newline="") as fh:
        assert {r["SIS Login ID"]: r["Task 4 total"] for r in csv.DictReader(fh)} == {
            s: t for s, (_p, t) in WITH_TIMES.items()}
    report = (out / "report.html").read_text()
    assert "timestamp.txt is a link (not followed)" in report and "times.csv has no row for nobody" in report
    assert "late policy: linker: files: times.csv, the LMS export; the submission's a sub-folder's timestamp.txt " \
           "is a link (not followed)" in stdout, stdout
    _nothing_leaked(out)


@pytest.mark.ros
def test_make_grade_on_an_nbgrader_course_takes_lms_and_exchange_times_and_never_the_students(root):
    """Course mode: three students of a one-notebook course; the late line opens nbgrader's HTML feedback too."""
    import shutil
    from datetime import datetime, timedelta, timezone

    from grading_helpers import nbgrader_course

    course = nbgrader_course(root / "course", "preparation", ["ex01_fsr_and_arduino"])
    secret = root / "shadow"
    secret.write_text(SECRET + "\n")
    secret.chmod(0o600)
    submitted = course / "submitted"
    for student in ("honest", "forger", "linker"):
        shutil.copytree(course / "release" / "preparation", submitted / student / "preparation")
    deadline = datetime.now(timezone.utc).replace(microsecond=0) - timedelta(hours=2)
    (submitted / "honest" / "preparation" / "timestamp.txt").write_text(
        (deadline + timedelta(minutes=1)).strftime("%Y-%m-%d %H:%M:%S.%f UTC"))  # the truth, as nbgrader writes it
    (submitted / "forger" / "preparation" / "timestamp.txt").write_text("2026-01-01 10:00:00.000000 UTC")
    (submitted / "linker" / "preparation" / "timestamp.txt").symlink_to(secret)
    inbound = root / "exchange" / "inbound"  # only the forger submitted through the exchange: now, 2 h late
    (inbound / "forger+preparation+2026-01-01 10:00:00.000000 UTC+AbCd").mkdir(parents=True)
    (course / "times.csv").write_text("student,assignment,submitted_at\n"
                                      f"honest,preparation,{(deadline + timedelta(minutes=1)).isoformat()}\n"
                                      f"linker,preparation,{(deadline - timedelta(hours=1)).isoformat()}\n")
    (course / "late.yaml").write_text(f'deadline: "{deadline.isoformat()}"\nper_day: 10%\n')
    out = root / "grades"
    code, stdout, stderr = _make_grade(submitted, out, "CHECKS=robot-params", "JOBS=2", "TIMEOUT=300")
    rows = _rows(out)
    assert set(rows) == {"honest", "forger", "linker"}, stdout[-3000:] + stderr[-3000:]
    assert {s: (r["late_penalty"], r["total"]) for s, r in rows.items()} == {s: ("unknown", "") for s in rows}
    _nothing_leaked(out)
    _nothing_leaked(course / "feedback")

    (course / "late.yaml").write_text(f'deadline: "{deadline.isoformat()}"\nper_day: 10%\ntimes: times.csv\n'
                                      f"exchange: {root / 'exchange'}\n")
    code, stdout, stderr = _make_grade(submitted, out, "REPORT=1")
    assert code == 0, stdout[-3000:] + stderr[-3000:]
    rows = _rows(out)
    maximum = float(rows["honest"]["preparation_max"])
    assert {s: r["late_penalty"] for s, r in rows.items()} == {
        "honest": f"{0.1 * maximum:g}", "forger": f"{0.1 * maximum:g}", "linker": "0"}, rows
    assert "nbgrader's exchange (its inbound folder's change time)" in (out / "forger" / "feedback.txt").read_text()
    pages = sorted((course / "feedback" / "forger" / "preparation").glob("*.html"))
    assert pages and all("timestamp.txt says 2026-01-01 10:00:00+00:00 (not used)" in p.read_text() for p in pages)
    assert "timestamp.txt is a link (not followed)" in (out / "linker" / "feedback.txt").read_text(), rows["linker"]
    assert "late policy: linker: preparation: times.csv, the LMS export; the submission's timestamp.txt is a link " \
           "(not followed)" in stdout, stdout
    _nothing_leaked(out)
    _nothing_leaked(course / "feedback")
