"""Each part counts once, where hri_teleop.grading.points says (the files); the totals in
docs/instructors.md are what every path computes for the answer key; one student, one seed everywhere.

Unit level: no nbgrader run and no ROS master here (test_make_grade_nbgrader.py and test_gradescope.py
run the real thing once and check the same numbers there). The make grade aggregation runs on a
synthetic OUT through the real finish (grades.csv's totals, lms.csv, the late policy).
"""

from __future__ import annotations

import csv
import json
import shutil
import threading
from pathlib import Path
from typing import Any, Dict, List, Tuple

import pytest

from hri_teleop.course.release import COURSE_DIR
from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS, ASSIGNMENTS
from hri_teleop.grading.batch.class_results import score_columns, write_rows, write_summary
from hri_teleop.grading.batch.finish import finish
from hri_teleop.grading.batch.late import read_late_policy
from hri_teleop.grading.cases.inputs import SEED_ENV, CasesError, default_seed, seed_for, student_seed
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.gradescope.notebooks import cell_tests
from hri_teleop.grading.gradescope.report import results_payload
from hri_teleop.grading.points import (
    CHECK_CALL,
    CHECK_CELLS,
    assignment_points,
    check_cell_problems,
    check_points,
    files_points,
    is_check_cell,
    part_tables,
)
from hri_teleop.grading.results import CheckResult, GradingError, Part

REPO = COURSE_DIR.parent
GUIDE = REPO / "docs" / "instructors.md"
SOURCE = COURSE_DIR / "source"
#: The course facade's functions and the check each runs (hri_teleop.course.check).
FACADE = {"robot_params": "robot-params", "mapping_node": "mapping-node", "sensor_launch": "sensor-launch",
          "teleoperation_parts": "teleoperation", "teleoperation_node": "teleoperation",
          "catkin_package": "catkin-package", "teleoperation_launch": "teleoperation-launch", "graph": "graph"}


def _cells(path: Path) -> list:
    return json.loads(path.read_text(encoding="utf-8"))["cells"]


def _meta(cell: dict) -> dict:
    return cell.get("metadata", {}).get("nbgrader", {})


def _text(cell: dict) -> str:
    return "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]


def _notebooks(assignment: str) -> List[Path]:
    return sorted((SOURCE / assignment).glob("*.ipynb"))


def _autograded(path: Path) -> Dict[str, float]:
    """grade id -> points of the notebook's autograded cells (the answer key gets them all)."""
    return {_meta(c)["grade_id"]: float(_meta(c)["points"]) for c in _cells(path)
            if _meta(c).get("grade") and not _meta(c).get("solution")}


def _by_hand(path: Path) -> float:
    return sum(float(_meta(c)["points"]) for c in _cells(path) if _meta(c).get("grade") and _meta(c).get("solution"))


def _documented() -> Dict[str, Dict[str, float]]:
    """row (assignment or "course") -> column -> points, from the points table of docs/instructors.md."""
    header: List[str] = []
    rows: Dict[str, Dict[str, float]] = {}
    for line in GUIDE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[:2] == ["assignment", "notebooks"]:
            header = cells
        elif header and line.startswith("|") and len(cells) == len(header) and cells[2].isdigit():
            rows[cells[0].split("`")[1] if "`" in cells[0] else cells[0]] = dict(
                zip(header[2:], (float(c) for c in cells[2:])))
        elif header and rows and not line.startswith("|"):
            break
    return rows


def _computed() -> Dict[str, Dict[str, float]]:
    """The same table from the code: the notebooks' nbgrader metadata and the checks' part tables."""
    rows: Dict[str, Dict[str, float]] = {}
    for assignment in ASSIGNMENTS:
        cells = sum(sum(_autograded(p).values()) for p in _notebooks(assignment))
        files = files_points(assignment)
        manual = sum(_by_hand(p) for p in _notebooks(assignment))
        rows[assignment] = {"notebook cells (autograded)": cells, "files (the checks)": files,
                            "autograded": cells + files, "graded by hand": manual, "total": cells + files + manual}
    rows["course"] = {k: sum(rows[a][k] for a in ASSIGNMENTS) for k in rows[ASSIGNMENTS[0]]}
    return rows


DOCUMENTED = _documented()


def test_the_guide_documents_the_points_the_notebooks_and_the_checks_carry():
    assert DOCUMENTED == _computed()
    # every check belongs to one assignment: the files' points are each check's once
    owned = [c for a in ASSIGNMENTS for c in ASSIGNMENT_CHECKS[a]]
    assert sorted(owned) == sorted(CHECKS)
    assert DOCUMENTED["course"]["files (the checks)"] == sum(check_points(c) for c in CHECKS)


def test_every_check_cell_is_read_only_worth_no_points_and_in_the_rule_table():
    found = set()
    for path in sorted(SOURCE.glob("*/*.ipynb")):
        for cell in _cells(path):
            if cell["cell_type"] == "code" and CHECK_CALL.search(_text(cell)):
                meta = _meta(cell)
                assert (meta.get("grade"), meta.get("locked"), meta.get("solution")) == (False, True, False), meta
                assert "points" not in meta, meta
                function = _text(cell).split("check.", 1)[1].split("(", 1)[0]
                found.add((path.parent.name, path.stem, meta["grade_id"], FACADE[function]))
    assert found == {(c.assignment, c.notebook, c.grade_id, c.check) for c in CHECK_CELLS}
    assert check_cell_problems(SOURCE) == []
    for assignment in ASSIGNMENTS:  # the files job of an assignment runs the checks its notebooks show
        assert {c.check for c in CHECK_CELLS if c.assignment == assignment} == set(ASSIGNMENT_CHECKS[assignment])


def _graded_check_cell(repo: Path) -> Path:
    """A course under ``repo`` whose Ex. 5 check cell carries nbgrader points again (the old way)."""
    target = repo / "notebooks" / "source" / "preparation" / "ex05_mapping_node.ipynb"
    target.parent.mkdir(parents=True)
    nb = json.loads((SOURCE / "preparation" / target.name).read_text(encoding="utf-8"))
    for cell in nb["cells"]:
        if _meta(cell).get("grade_id") == "ex5_node":
            cell["metadata"]["nbgrader"].update(grade=True, points=20)
    target.write_text(json.dumps(nb), encoding="utf-8")
    return target


def test_a_check_cell_with_points_is_refused_by_make_grade_and_make_gradescope(tmp_path, monkeypatch):
    from hri_teleop.grading.batch import nbgrader_batch
    from hri_teleop.grading.batch.folders import BatchError
    from hri_teleop.grading.gradescope.build import build_zip

    _graded_check_cell(tmp_path / "repo")
    problems = check_cell_problems(tmp_path / "repo" / "notebooks" / "source")
    assert len(problems) == 1 and "ex05_mapping_node.ipynb: cell ex5_node runs a check and carries 20" in problems[0]
    assert "read-only cell" in problems[0]
    with pytest.raises(GradingError, match="cell ex5_node runs a check"):
        build_zip(tmp_path / "zip", repo=tmp_path / "repo")
    course = tmp_path / "repo" / "notebooks"
    (course / "submitted" / "alice" / "preparation").mkdir(parents=True)
    monkeypatch.setattr(nbgrader_batch, "open_course", lambda *a: None)  # no gradebook needed to refuse
    with pytest.raises(BatchError, match="cell ex5_node runs a check"):
        nbgrader_batch.grade_course(course, course / "submitted", tmp_path / "out")
    assert not (tmp_path / "out").exists()


# -- make grade: grades.csv, lms.csv, the late policy ---------------------------------------------------

def _answer_key_jobs(manual: bool = False) -> List[dict]:
    """make grade's jobs (as summary.json keeps them) for the answer key, before (or after) grading by hand."""
    jobs = []
    for assignment in ASSIGNMENTS:
        auto = sum(sum(_autograded(p).values()) for p in _notebooks(assignment))
        by_hand = sum(_by_hand(p) for p in _notebooks(assignment))
        files = files_points(assignment)
        jobs.append({"student": "key", "assignment": assignment, "kind": "files", "score": files, "max_score": files,
                     "status": "graded", "seconds": 1.0, "message": "", "needs_manual_grade": False})
        jobs.append({"student": "key", "assignment": assignment, "kind": "notebooks",
                     "score": auto + (by_hand if manual else 0.0), "max_score": auto + by_hand, "status": "graded",
                     "seconds": 1.0, "message": "", "needs_manual_grade": not manual})
    return jobs


def test_make_grade_counts_each_part_once_and_its_totals_are_the_documented_ones(tmp_path):
    columns = score_columns(_answer_key_jobs(), ASSIGNMENTS)
    for assignment in ASSIGNMENTS:
        assert float(columns[f"{assignment}_max"]) == DOCUMENTED[assignment]["total"]
        assert float(columns[f"{assignment}_score"]) == DOCUMENTED[assignment]["autograded"]
    course = DOCUMENTED["course"]
    assert float(columns["notebooks_max"]) + float(columns["files_max"]) == course["total"] == sum(
        float(columns[f"{a}_max"]) for a in ASSIGNMENTS)
    assert float(columns["files_score"]) == course["files (the checks)"]
    assert float(columns["notebooks_score"]) + float(columns["files_score"]) == course["autograded"]
    graded = score_columns(_answer_key_jobs(manual=True), ASSIGNMENTS)
    assert sum(float(graded[f"{a}_score"]) for a in ASSIGNMENTS) == course["total"]
    # an assignment whose files were not graded has no score (not the notebooks' part of it)
    broken = [dict(j, status="not graded") if j["kind"] == "files" and j["assignment"] == "lab" else j
              for j in _answer_key_jobs()]
    assert assignment_points(broken)["lab"] == (None, None) and score_columns(broken, ASSIGNMENTS)["lab_score"] == ""

    # the end of make grade (the real finish) over this OUT: totals, lms.csv, a late preparation
    out, submitted = tmp_path / "out", tmp_path / "submitted"
    times = "student,assignment,submitted_at\n"
    for assignment, stamp in (("preparation", "2026-12-01 22:59:01.000000 UTC"),
                              ("lab", "2026-12-08 22:00:00.000000 UTC")):
        (submitted / "key" / assignment).mkdir(parents=True)
        (submitted / "key" / assignment / "timestamp.txt").write_text(stamp)  # nbgrader's: only shown
        times += f"key,{assignment},{stamp}\n"  # the LMS export: these times decide
    (tmp_path / "submitted-at.csv").write_text(times)
    late = tmp_path / "late.yaml"
    late.write_text('deadline: {preparation: "2026-12-01 23:59 Europe/Berlin", lab: "2026-12-08 23:59 Europe/Berlin"}\n'
                    "per_day: 10%\ntimes: submitted-at.csv\n")
    out.mkdir()
    header = ["student", *[f"{a}_{x}" for a in ASSIGNMENTS for x in ("score", "max")], "notebooks_score",
              "notebooks_max", "files_score", "files_max", "needs_manual_grade", "status", "seconds", "message"]
    write_rows(out / "grades.csv", header, [{"student": "key", **columns, "status": "graded"}])
    write_summary(out, [{"student": "key", "status": "graded", "reasons": [], "jobs": _answer_key_jobs()}])
    said: List[str] = []
    finish(out, read_late_policy(late), lambda name, assignment: submitted / name / assignment, ASSIGNMENTS,
           progress=said.append)
    assert not [line for line in said if "unknown" in line], said  # both times known: none waits
    row = next(csv.DictReader(open(out / "grades.csv", encoding="utf-8")))
    penalty = 0.1 * DOCUMENTED["preparation"]["total"]  # a second late: 10 % of the assignment's 55 points
    assert float(row["late_penalty"]) == pytest.approx(penalty)
    assert float(row["total"]) == pytest.approx(course["autograded"] - penalty)
    lms = next(csv.DictReader(open(out / "lms.csv", encoding="utf-8")))
    assert float(lms["Task 4 preparation"]) == pytest.approx(DOCUMENTED["preparation"]["autograded"] - penalty)
    assert float(lms["Task 4 lab"]) == DOCUMENTED["lab"]["autograded"]
    assert float(lms["Task 4 total"]) == pytest.approx(float(row["total"]))
    assert f"of {DOCUMENTED['preparation']['total']:g} points" in (out / "key" / "feedback.txt").read_text()


# -- Gradescope: results.json -------------------------------------------------------------------------------

def _full_marks(check: str) -> CheckResult:
    return CheckResult(check, "", [Part(name, points, True) for name, points in part_tables()[check].values()])


def _payload(assignments: Tuple[str, ...]) -> dict:
    """results.json for the answer key's files and every notebook of ``assignments``, all autograded cells passed."""
    checks = [c for a in assignments for c in ASSIGNMENT_CHECKS[a]]
    tests = {f"{a}/{p.name}": cell_tests(f"{a}/{p.name}", p, _autograded(p), {})
             for a in assignments for p in _notebooks(a)}
    return results_payload([_full_marks(c) for c in checks], order=checks, notebook_tests=tests)


@pytest.mark.parametrize("assignments", [("preparation",), ("lab",), ASSIGNMENTS], ids=lambda a: "+".join(a))
def test_gradescope_counts_the_files_and_the_other_autograded_cells_once(assignments):
    payload = _payload(assignments)
    names = [t["name"] for t in payload["tests"]]
    assert len(names) == len(set(names))
    assert not [n for n in names if "ipynb: " in n and is_check_cell(n.split(": ", 1)[1])], names
    key = assignments[0] if len(assignments) == 1 else "course"
    assert payload["score"] == sum(t["max_score"] for t in payload["tests"]) == DOCUMENTED[key]["autograded"]
    files = sum(t["max_score"] for t in payload["tests"] if ".ipynb: " not in t["name"])
    assert files == DOCUMENTED[key]["files (the checks)"]


# -- one student, one seed ---------------------------------------------------------------------------------

def test_a_students_seed_comes_from_the_id_alone():
    assert student_seed("alice") == student_seed("alice") != student_seed("bob")
    assert 0 <= student_seed("alice") < 2 ** 32


def test_make_grade_gives_the_files_job_and_the_notebooks_kernels_the_students_seed(tmp_path, monkeypatch):
    from hri_teleop.grading.batch import folders, nbgrader_batch
    from hri_teleop.grading.run.jobs import Run

    seen: Dict[str, Any] = {}

    def files_job(argv, log, timeout_s, **kwargs):
        seen["argv"] = list(argv)
        return Run(0, json.dumps({"score": 0, "tests": []}).encode(), 0.1, False)

    def notebooks_job(argv, log, timeout_s, **kwargs):
        seen["env"] = dict(kwargs["env"])
        log.write_text("nbgrader stopped\n")
        return Run(1, b"", 0.1, False)

    monkeypatch.setattr(folders, "run_job", files_job)
    monkeypatch.setattr(nbgrader_batch, "run_job", notebooks_job)
    course = nbgrader_batch.Course(tmp_path, tmp_path / "submitted", "course", f"sqlite:///{tmp_path / 'gb.db'}")
    (tmp_path / "submitted" / "alice" / "preparation").mkdir(parents=True)
    (tmp_path / "out").mkdir()
    nbgrader_batch.grade_files(course, "alice", "preparation", tmp_path / "out", ["robot-params"], None, 60.0)
    argv = seen["argv"]
    assert argv[argv.index("--seed") + 1] == str(student_seed("alice"))
    nbgrader_batch.autograde_in(course, "alice", "preparation", tmp_path / "out", 60.0, threading.Lock(),
                                 lambda line: None, ["nbgrader", "autograde"])
    assert seen["env"][SEED_ENV] == str(student_seed("alice"))
    folders.grade_one(tmp_path / "submitted" / "alice", tmp_path / "out", None, None, seed=student_seed("alice"))
    assert seen["argv"][seen["argv"].index("--seed") + 1] == str(student_seed("alice"))


def test_gradescope_gives_the_files_and_the_uploaded_notebooks_the_students_seed(tmp_path, monkeypatch):
    from hri_teleop.grading.batch.nbgrader_batch import JobOutcome
    from hri_teleop.grading.gradescope import container, notebooks
    from hri_teleop.grading.gradescope.notebooks import COURSE, course_members

    meta = tmp_path / "submission_metadata.json"
    meta.write_text(json.dumps({"users": [{"id": 4711, "email": "alice@uni.example", "sid": "alice"}],
                                "assignment": {"id": 3}}))
    assert container.student_from_metadata(meta) == "alice"
    seed = container.seed_from_metadata(meta)
    assert seed == student_seed("alice")  # as make grade gives student alice
    meta.write_text(json.dumps({"users": [{"id": 4711, "email": "alice@uni.example"}], "assignment": {"id": 4}}))
    assert container.seed_from_metadata(meta) == student_seed("alice@uni.example")

    shipped = tmp_path / "zip"
    for name, data in course_members(REPO / "notebooks"):
        (shipped / name).parent.mkdir(parents=True, exist_ok=True)
        (shipped / name).write_bytes(data)
    asked: List[object] = []

    def autograde(course, student, assignment, *args, **kwargs):
        asked.append(kwargs.get("seed"))
        return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", 1.0, "stopped")

    monkeypatch.setattr(notebooks, "install_kernelspec", lambda: tmp_path)
    monkeypatch.setattr(notebooks, "_alembic_on_path", lambda work: None)
    monkeypatch.setattr(notebooks, "_generate", lambda course, assignment, log: "")
    monkeypatch.setattr(notebooks, "autograde_one", autograde)
    upload = tmp_path / "up" / "ex05_mapping_node.ipynb"
    upload.parent.mkdir()
    shutil.copy(SOURCE / "preparation" / upload.name, upload)
    (tmp_path / "hri_lab").mkdir()
    container.grade_upload_notebooks([upload], tmp_path / "hri_lab", shipped / COURSE, tmp_path / "work", 60.0, seed, None)
    assert asked == [seed]


def test_a_check_in_a_graded_kernel_takes_the_students_seed_and_finds_the_files_jobs_result(tmp_path, monkeypatch):
    from hri_teleop.grading.exercises.mapping_node.check import grade_mapping_node
    from hri_teleop.grading.exercises.robot_params import grade_robot_params
    from hri_teleop.grading.judge import reuse

    root = tmp_path / "autograded" / "alice" / "preparation" / "hri_lab"
    (root / "config").mkdir(parents=True)
    shutil.copy(REPO / "solutions" / "hri_lab" / "config" / "robot_params.yaml", root / "config")
    monkeypatch.delenv(SEED_ENV, raising=False)
    assert default_seed(root) == seed_for(root) == grade_mapping_node(root).seed  # alone: the folder's
    monkeypatch.setenv(SEED_ENV, str(student_seed("alice")))
    assert grade_mapping_node(root).seed == student_seed("alice")  # (no mapping_node.py: judged at once)
    stored = CheckResult("robot-params", str(root / "config" / "robot_params.yaml"), [Part("the files job's", 10, True)])
    reuse.store(tmp_path / "results", "robot-params", student_seed("alice"), root, stored)
    monkeypatch.setenv(reuse.READ_ENV, str(tmp_path / "results"))
    assert [p.name for p in grade_robot_params(root).parts] == ["the files job's"]
    monkeypatch.setenv(SEED_ENV, "alice")
    with pytest.raises(CasesError, match=f"{SEED_ENV}='alice' is not a whole number"):
        default_seed(root)


# -- make check: the files' half -----------------------------------------------------------------------------

def test_make_check_grades_the_checks_the_chosen_notebooks_show():
    from hri_teleop.apps.files_check import checks_for, summary_lines

    assert checks_for("preparation") == ASSIGNMENT_CHECKS["preparation"]
    assert checks_for("lab", ["ex12"]) == ("teleoperation-launch", "catkin-package")
    assert checks_for("lab", ["ex05"]) == () and checks_for("preparation", ["ex01", "ex05"]) == ("mapping-node",)
    lines = summary_lines("lab", [_full_marks("graph"), CheckResult("teleoperation", "", [Part("a", 2, False)])], 3.0)
    assert lines[0] == "  lab/hri_lab: graph 9/9, teleoperation 0/2: 9/11 points (3 s)"
    assert lines[1:] == ["      teleoperation: 0/2", "        [FAIL] a (0/2)",
                         "        (the same in ex08_gamepad_commands.ipynb / ex09_teleoperation_node.ipynb, check cell; "
                         "in a terminal: hri-grade teleoperation lab/hri_lab)"]
