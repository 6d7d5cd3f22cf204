"""The class report's numbers on synthetic results: distribution, item analysis, not judged, lms.csv, the page.

No grading runs here (test_make_grade.py runs one real batch): each function gets records built
by hand, so every threshold is pinned. About 2 s (the two PNG figures).
"""

from __future__ import annotations

import csv
import json
from datetime import datetime, timedelta, timezone

import pytest

from hri_teleop.grading.batch.class_results import read_class, write_rows, write_summary
from hri_teleop.grading.batch.finish import add_totals, apply_late, mark_feedback_html, set_feedback_lines
from hri_teleop.grading.batch.late import ALL_ASSIGNMENTS, LatePolicy, judge_lateness, read_late_policy
from hri_teleop.grading.batch.lms import lms_table, write_lms
from hri_teleop.grading.batch.report import write_report
from hri_teleop.grading.batch.report_data import (
    FILES_ONLY,
    AssignmentScore,
    ClassResults,
    Job,
    PartResult,
    StudentRecord,
    classify_reason,
    distributions,
    histogram,
    item_rates,
    not_judged,
    slowest,
)

UTC = timezone.utc
DEADLINE = datetime(2026, 12, 1, 22, 59, tzinfo=UTC)
POLICY = LatePolicy("late.yaml", {ALL_ASSIGNMENTS: DEADLINE}, per_day=0.1, cap=0.5)


def _student(name: str, score, maximum=10.0, parts=(), jobs=(), late=()) -> StudentRecord:
    graded = score is not None
    penalty = sum(lt.points(maximum) for lt in late)
    return StudentRecord(name, "graded" if graded else "not graded",
                         (AssignmentScore(FILES_ONLY, score, maximum if graded else None, penalty),),
                         tuple(jobs) or (Job(name, FILES_ONLY, "graded" if graded else "not graded", 1.0),),
                         (), tuple(parts), tuple(late))


def test_histogram_puts_each_score_in_its_bar_and_the_maximum_in_the_last():
    bins = histogram([0.0, 0.999, 1.0, 9.999, 10.0, 12.0, -1.0], 10.0, bins=10)
    assert [n for _lo, _hi, n in bins] == [3, 1, 0, 0, 0, 0, 0, 0, 0, 3]
    assert bins[0][:2] == (0.0, 1.0) and bins[-1][:2] == (9.0, 10.0)
    assert histogram([1.0], 0.0) == []


def test_item_rates_count_full_points_only_and_sort_worst_first():
    parts = {"a": [PartResult("loads", 1, 1), PartResult("mass", 2, 2), PartResult("gains", 0.5, 1)],
             "b": [PartResult("loads", 1, 1), PartResult("mass", 1.999, 2), PartResult("gains", 1, 1)],
             "c": [PartResult("loads", 0, 1)]}
    rates = item_rates([_student(s, 1.0, parts=p) for s, p in parts.items()])
    # 1.999 of 2 is not full points; on a tie of the rate the lower mean share comes first
    assert [(r.item, r.n, r.full) for r in rates] == [("gains", 2, 1), ("mass", 2, 1), ("loads", 3, 2)]
    assert rates[0].mean_fraction == pytest.approx(0.75) and rates[1].mean_fraction == pytest.approx(0.99975)
    assert rates[2].rate == pytest.approx(2 / 3)


def test_distributions_use_the_scores_after_penalties_and_leave_the_ungraded_out():
    late = judge_lateness(POLICY, "bob", FILES_ONLY, DEADLINE + timedelta(seconds=1), "timestamp.txt")
    results = ClassResults("folders", (FILES_ONLY,),
                           (_student("ann", 10.0), _student("bob", 10.0, late=[late]), _student("cy", None)))
    assert distributions(results) == [("total", [10.0, 9.0], 10.0)]
    floor = _student("dee", 0.5, late=[judge_lateness(POLICY, "dee", FILES_ONLY, DEADLINE + timedelta(days=30))])
    assert floor.total == 0.0  # the penalty never takes the total below 0


@pytest.mark.parametrize("message, kind", [
    ("grading took longer than 600 s", "timeout"),
    ("nbgrader autograde took longer than 45 s (stopped in ex01.ipynb)", "timeout"),
    ("nbgrader autograde failed in ex01.ipynb: DeadKernelError: Kernel died", "kernel died"),
    ("hri_lab/x -> /etc/passwd links outside the submission (...)", "refused (link outside the submission)"),
    ("the grader printed no JSON", "crash"),
    ("something else", "other"),
])
def test_a_not_judged_reason_is_classified(message, kind):
    assert classify_reason(message) == kind


def test_not_judged_lists_each_failed_job_once_with_its_log_and_slowest_sorts_by_time():
    jobs = [Job("ada", "lab", "not graded", 45.0, "nbgrader autograde took longer than 45 s", "ada/lab/autograde.log"),
            Job("ada", "lab/hri_lab", "graded", 9.0)]
    ada = StudentRecord("ada", "not graded", (), tuple(jobs),
                        ("lab: nbgrader autograde took longer than 45 s", "no assignment folder in x (see y.log)"))
    rows = not_judged([ada, _student("bob", 1.0)])
    assert [(r.what, r.kind, r.where) for r in rows] == [("lab", "timeout", "ada/lab/autograde.log"),
                                                           ("submission", "nothing found", "y.log")]
    assert [(j.student, j.seconds) for j in slowest([ada, _student("bob", 1.0)], n=2)] == [("ada", 45.0), ("ada", 9.0)]


def test_lms_csv_has_canvas_identity_columns_a_number_per_assignment_and_blank_for_ungraded(tmp_path):
    two = ClassResults("course", ("preparation", "lab"), (
        StudentRecord("bob", "graded", (AssignmentScore("preparation", 7.25, 10.0, 0.0),
                                        AssignmentScore("lab", 20.0, 40.0, 4.0))),
        StudentRecord("ada", "not graded", (AssignmentScore("preparation", 9.0, 10.0),
                                            AssignmentScore("lab", None, None)))))
    header, rows = lms_table(two)
    assert header == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Task 4 preparation", "Task 4 lab",
                      "Task 4 total"]
    assert rows == [["ada", "", "", "ada", "", "9", "", ""], ["bob", "", "", "bob", "", "7.25", "16", "23.25"]]
    text = write_lms(tmp_path / "lms.csv", two).read_bytes()
    assert "Waiting for grading by hand" not in write_report(tmp_path, two).read_text()
    waiting = ClassResults("course", ("lab",), (StudentRecord("bob", "graded", manual=("lab",)),))
    assert "Waiting for grading by hand (1)</h2>" in write_report(tmp_path, waiting).read_text()
    assert not text.startswith(b"\xef\xbb\xbf") and b"Points Possible" not in text


def test_the_report_escapes_what_students_wrote_and_links_the_figures(tmp_path):
    evil = "<script>alert(1)</script>"
    job = Job("mallory", FILES_ONLY, "not graded", 3.0, f"crash: {evil}", "mallory/grader.log")
    results = ClassResults("folders", (FILES_ONLY,), (
        _student("ann", 10.0, parts=[PartResult(f"robot-params: {evil}", 0, 1)]),
        StudentRecord("mallory", "not graded", (AssignmentScore(FILES_ONLY, None, None),), (job,), (job.message,))))
    page = write_report(tmp_path, results).read_text()
    assert evil not in page and "&lt;script&gt;" in page
    assert "Not judged (1)" in page and 'href="./mallory/grader.log"' in page and "No late policy" in page
    sneaky = Job("javascript:alert(1)", FILES_ONLY, "not graded", 1.0, "crash", "javascript:alert(1)/grader.log")
    page = write_report(tmp_path, ClassResults("folders", (FILES_ONLY,), (StudentRecord(
        sneaky.student, "not graded", (), (sneaky,)),))).read_text()
    assert 'href="./javascript%3Aalert%281%29/grader.log"' in page
    assert (tmp_path / "report-scores.png").read_bytes()[:4] == b"\x89PNG"
    assert (tmp_path / "report-items.png").read_bytes()[:4] == b"\x89PNG"


def test_one_student_regraded_keeps_everyone_elses_rows_and_summary(tmp_path):
    write_rows(tmp_path / "grades.csv", ["student", "score"], [{"student": "ann", "score": "1"},
                                                               {"student": "bob", "score": "2"}])
    write_summary(tmp_path, [{"student": "ann", "status": "graded"}, {"student": "bob", "status": "graded"}])
    write_rows(tmp_path / "grades.csv", ["student", "score"], [{"student": "bob", "score": "5"}], {"bob"})
    write_summary(tmp_path, [{"student": "bob", "status": "not graded"}], {"bob"})
    assert list(csv.reader(open(tmp_path / "grades.csv"))) == [["student", "score"], ["ann", "1"], ["bob", "5"]]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert [(e["student"], e["status"]) for e in summary] == [("ann", "graded"), ("bob", "not graded")]


def _folders_out(tmp_path):
    """OUT of a folders run with ann on time and bob a second late (nbgrader's timestamp.txt in each, shown only)."""
    out, submitted = tmp_path / "out", tmp_path / "submitted"
    entries = []
    for student, at in (("ann", "2026-12-01 22:59:00 UTC"), ("bob", "2026-12-01 22:59:01 UTC")):
        (submitted / student).mkdir(parents=True)
        (submitted / student / "timestamp.txt").write_text(at)
        (out / student).mkdir(parents=True)
        (out / student / "feedback.txt").write_text("robot-params: 8/10\n")
        (out / student / "results.json").write_text(json.dumps(
            {"score": 8, "tests": [{"name": "robot-params: loads", "score": 8, "max_score": 10}]}))
        entries.append({"student": student, "score": 8.0, "max_score": 10.0, "status": "graded", "seconds": 1.0,
                        "message": ""})
    write_summary(out, entries)
    write_rows(out / "grades.csv", ["student", "score"], [{"student": e["student"], "score": "8"} for e in entries])
    return out, submitted


def _late_yaml(tmp_path):
    """POLICY as late.yaml with the LMS export beside it: ann at the deadline, bob a second after (as their
    timestamp.txt say, which are only shown)."""
    (tmp_path / "submitted-at.csv").write_text("student,assignment,submitted_at\n"
                                               "ann,*,2026-12-01 22:59:00 UTC\nbob,*,2026-12-01 22:59:01 UTC\n")
    (tmp_path / "late.yaml").write_text('deadline: "2026-12-01 22:59 UTC"\nper_day: 10%\ncap: 50%\n'
                                        "times: submitted-at.csv\n")
    policy = read_late_policy(tmp_path / "late.yaml")
    assert (policy.deadlines, policy.per_day, policy.cap) == (POLICY.deadlines, POLICY.per_day, POLICY.cap)
    return policy


def test_the_late_policy_reaches_summary_feedback_and_totals_and_a_rerun_replaces_its_line(tmp_path):
    out, submitted = _folders_out(tmp_path)
    policy = _late_yaml(tmp_path)
    for _run in range(2):  # a second run (STUDENT=..., or another late.yaml) does not add a second line
        apply_late(out, policy, lambda name, _a: submitted / name)
    feedback = (out / "bob" / "feedback.txt").read_text().splitlines()
    assert feedback[0].startswith("late policy: submitted 2026-12-01 22:59:01+00:00 (submitted-at.csv, the LMS "
                                  "export; the submission's timestamp.txt says 2026-12-01 22:59:01+00:00 (not used)), "
                                  "1 s after"), feedback[0]
    assert feedback[0].endswith("penalty 10% of 10 points = 1") and feedback[1:] == ["", "robot-params: 8/10"]
    assert (out / "ann" / "feedback.txt").read_text().count("late policy") == 1
    results = read_class(out, late_policy=policy.source)
    add_totals(out / "grades.csv", results)
    rows = list(csv.DictReader(open(out / "grades.csv")))
    assert [(r["student"], r["late_penalty"], r["total"]) for r in rows] == [("ann", "0", "8"), ("bob", "1", "7")]
    apply_late(out, None, lambda name, _a: submitted / name)  # the policy removed: no line, no penalty
    assert "late policy" not in (out / "bob" / "feedback.txt").read_text()
    assert read_class(out).students[1].total == 8.0


def test_feedback_lines_and_html_blocks_replace_the_earlier_ones(tmp_path):
    path = tmp_path / "feedback.txt"
    set_feedback_lines(path, ["late policy: one"])
    assert path.read_text() == "late policy: one\n"
    set_feedback_lines(tmp_path / "none.txt", [])
    assert not (tmp_path / "none.txt").exists()
    page = tmp_path / "ex01.html"
    page.write_text("<html><body class=x>\n<h1>Ex. 1</h1></body></html>")
    mark_feedback_html(page, "late policy: 1 day <late>")
    mark_feedback_html(page, "late policy: 2 days <late>")
    text = page.read_text()
    assert text.count("hri-late-policy") == 1 and "2 days &lt;late&gt;" in text
    assert text.index("hri-late-policy") < text.index("<h1>")


def test_a_student_not_graded_now_adds_no_stale_parts_to_the_item_analysis(tmp_path):
    out, _submitted = _folders_out(tmp_path)
    write_summary(out, [{"student": "bob", "score": 0.0, "max_score": 0.0, "status": "not graded", "seconds": 600.0,
                         "message": "grading took longer than 600 s"}], {"bob"})  # his results.json is a run before
    rates = item_rates(read_class(out).students)
    assert [(r.item, r.n) for r in rates] == [("robot-params: loads", 1)]
