"""The Gradescope autograder's pure steps: the upload's layout, results.json's visibility and output, the seed, the zip."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import pytest

from hri_teleop.core.paths import REPO
from hri_teleop.course.bundle import solution_texts
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.exercises.registry import exercises
from hri_teleop.grading.gradescope.build import build_zip
from hri_teleop.grading.gradescope.container import CONFIG_NAME, Config, load_config, seed_from_metadata
from hri_teleop.grading.gradescope.layout import find_upload
from hri_teleop.grading.gradescope.notebooks import COURSE, cell_tests, course_members, without_solutions
from hri_teleop.grading.gradescope.report import (
    Unjudged,
    part_tables,
    results_payload,
    visibility,
)
from hri_teleop.grading.results import CheckResult, GradingError, Part

PACKAGE = {"config/robot_params.yaml": "robot_name: panda\n", "scripts/mapping_node.py": "print('map')\n",
           "launch/sensor.launch": "<launch/>\n", "graph.yaml": "nodes: []\n"}


def _write(root: Path, files: dict) -> Path:
    for relative, text in files.items():
        (root / relative).parent.mkdir(parents=True, exist_ok=True)
        (root / relative).write_text(text)
    return root


def _zip(path: Path, files: dict) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, text in files.items():
            zf.writestr(name, text)
    return path


# -- the upload's layout ----------------------------------------------------------------------

def test_a_package_nested_in_folders_is_found_and_named(tmp_path):
    _write(tmp_path / "sub" / "Task 4" / "catkin_ws" / "src" / "hri_lab", PACKAGE)
    upload = find_upload(tmp_path / "sub", tmp_path / "work")
    assert sorted(upload.found) == sorted(PACKAGE)
    assert (upload.hri_lab / "scripts" / "mapping_node.py").read_text() == "print('map')\n"
    assert "found your package in Task 4/catkin_ws/src/hri_lab/" in upload.notes


def test_a_zip_inside_a_zip_with_macosx_copies_is_opened_and_the_copies_ignored(tmp_path):
    inner = {f"hri_lab/{k}": v for k, v in PACKAGE.items()}
    inner.update({f"__MACOSX/hri_lab/._{Path(k).name}": "junk" for k in PACKAGE})
    inner["hri_lab/.DS_Store"] = "junk"
    inner_zip = _zip(tmp_path / "inner.zip", inner)
    (tmp_path / "sub").mkdir()
    with zipfile.ZipFile(tmp_path / "sub" / "submission.zip", "w") as zf:
        zf.write(inner_zip, "work/inner.zip")
        zf.writestr("__MACOSX/work/._inner.zip", "junk")
    upload = find_upload(tmp_path / "sub", tmp_path / "work")
    assert sorted(upload.found) == sorted(PACKAGE)
    assert "found your package in submission.zip/work/inner.zip/hri_lab/" in upload.notes
    assert not [p for p in upload.hri_lab.rglob("*") if p.name.startswith("._") or p.name == ".DS_Store"]


def test_files_loose_at_the_root_are_put_in_their_places(tmp_path):
    _write(tmp_path / "sub", {Path(k).name: v for k, v in PACKAGE.items()})
    _write(tmp_path / "sub", {"analysis.ipynb": "{}", ".ipynb_checkpoints/analysis-checkpoint.ipynb": "{}"})
    upload = find_upload(tmp_path / "sub", tmp_path / "work")
    assert sorted(upload.found) == sorted(PACKAGE)
    assert "took scripts/mapping_node.py from mapping_node.py" in upload.notes
    assert [p.name for p in upload.notebooks] == ["analysis.ipynb"]


def test_the_folder_with_most_files_wins_and_fills_its_gaps_from_elsewhere(tmp_path):
    _write(tmp_path / "sub" / "old", {"scripts/mapping_node.py": "old\n"})
    files = {k: v for k, v in PACKAGE.items() if k != "graph.yaml"}
    _write(tmp_path / "sub" / "hri_lab", files)
    _write(tmp_path / "sub", {"notes/graph.yaml": "nodes: [x]\n"})
    upload = find_upload(tmp_path / "sub", tmp_path / "work")
    assert (upload.hri_lab / "scripts" / "mapping_node.py").read_text() == "print('map')\n"
    assert (upload.hri_lab / "graph.yaml").read_text() == "nodes: [x]\n"
    assert "took graph.yaml from notes/graph.yaml" in upload.notes


def test_an_upload_without_package_files_gets_an_empty_package_and_says_what_to_upload(tmp_path):
    _write(tmp_path / "sub", {"essay.txt": "hello"})
    upload = find_upload(tmp_path / "sub", tmp_path / "work")
    assert upload.found == [] and upload.hri_lab.is_dir() and not any(upload.hri_lab.iterdir())
    assert any("upload your hri_lab folder" in n for n in upload.notes)


def test_a_zip_member_outside_the_archive_is_refused_in_one_line(tmp_path):
    _zip(tmp_path / "sub" / "evil.zip", {"../../etc/evil": "x"})
    with pytest.raises(GradingError, match="points outside the archive"):
        find_upload(tmp_path / "sub", tmp_path / "work")
    assert not (tmp_path / "etc").exists()


def test_a_zip_that_unpacks_past_the_limit_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr("hri_teleop.grading.gradescope.layout.MAX_UNPACKED_BYTES", 1000)
    _zip(tmp_path / "sub" / "big.zip", {"hri_lab/graph.yaml": "x" * 2000})
    with pytest.raises(GradingError, match="unpacks to more than"):
        find_upload(tmp_path / "sub", tmp_path / "work")
    _zip(tmp_path / "sub" / "big.zip", {"hri_lab/graph.yaml": "x" * 700})  # under it, the zip included: opened
    assert find_upload(tmp_path / "sub", tmp_path / "work").found == ["graph.yaml"]


# -- results.json ------------------------------------------------------------------------------

def _result(check: str, failed: tuple = ()) -> CheckResult:
    parts = [Part(name, points, key not in failed, "fix it" if key in failed else "")
             for key, (name, points) in part_tables()[check].items()]
    return CheckResult(check, "x", parts, seed=3, notes=("a note",))


def test_hidden_input_parts_are_after_published_and_their_public_neighbours_visible():
    tables = part_tables()
    assert set(tables) == set(CHECKS)
    for found in exercises():
        assert set(found.hidden_parts) <= set(tables[found.check]), f"{found.check}: {found.hidden_parts} not all in its table"
    mapping = tables["mapping-node"]
    assert visibility("mapping-node", mapping["hidden"][0]) == "after_published"
    assert visibility("mapping-node", mapping["values"][0]) == "visible"  # the public trace
    teleop = tables["teleoperation"]
    assert visibility("teleoperation", teleop["node_twist"][0]) == "after_published"
    assert visibility("teleoperation", teleop["node_start"][0]) == "visible"  # topic names, no hidden values
    assert visibility("graph", mapping["hidden"][0]) == "visible"  # the name belongs to mapping-node only


def test_results_have_a_test_per_part_the_total_and_the_notes():
    payload = results_payload([_result("mapping-node", ("clip", "hidden")), _result("robot-params")],
                              notes=["found your package in hri_lab/"], execution_time_s=12.34)
    maximum = sum(p for _, p in part_tables()["mapping-node"].values()) + sum(
        p for _, p in part_tables()["robot-params"].values())
    assert payload["score"] == maximum - 3 - 5
    assert sum(t["max_score"] for t in payload["tests"]) == maximum
    failed = [t for t in payload["tests"] if t["status"] == "failed"]
    assert [t["visibility"] for t in failed] == ["visible", "after_published"]
    assert all("fix it" in t["output"] for t in failed)
    assert payload["output"] == "found your package in hri_lab/\na note"
    assert payload["execution_time"] == 12.3 and payload["stdout_visibility"] == "hidden"
    json.dumps(payload)


def test_a_check_not_judged_lists_its_parts_at_zero_and_the_output_names_it_first():
    payload = results_payload([_result("robot-params")], [Unjudged("teleoperation", "timed out after 180 s")],
                              order=["teleoperation", "robot-params"])
    lines = payload["output"].splitlines()
    assert lines[0].startswith("Not judged: teleoperation (the grader timed out after 180 s)")
    teleop = [t for t in payload["tests"] if t["name"].startswith("teleoperation: ")]
    assert len(teleop) == len(part_tables()["teleoperation"]) and all(t["score"] == 0 for t in teleop)
    assert payload["tests"][0]["name"].startswith("teleoperation: ") and payload["tests"][0]["number"] == "1.1"
    assert payload["score"] == _result("robot-params").score
    assert "Not judged" not in results_payload([_result("robot-params")]).get("output", "")


# -- the seed, the config, the zip --------------------------------------------------------------

def test_the_seed_follows_the_students_not_the_upload(tmp_path):
    def seed(users, assignment=7):
        path = tmp_path / "meta.json"
        path.write_text(json.dumps({"id": 99, "users": [{"id": u} for u in users], "assignment": {"id": assignment}}))
        return seed_from_metadata(path)
    assert seed([1, 2]) == seed([2, 1]) != seed([1]) != seed([3])
    assert seed([1]) == seed([1], assignment=8)  # one student, one seed: in every assignment, as under make grade
    assert seed_from_metadata(tmp_path / "missing.json") is None
    assert seed([]) is None


def test_the_config_defaults_to_every_check_and_refuses_an_unknown_one(tmp_path):
    assert load_config(tmp_path / CONFIG_NAME) == Config()
    (tmp_path / CONFIG_NAME).write_text(json.dumps({"checks": ["graph", "grpah"]}))
    with pytest.raises(GradingError, match="grpah"):
        load_config(tmp_path / CONFIG_NAME)


def test_the_zip_has_both_scripts_at_its_root_and_no_answer_key(tmp_path):
    target = build_zip(tmp_path, ["robot-params", "graph"])
    with zipfile.ZipFile(target) as zf:
        infos = {i.filename: i for i in zf.infolist()}
        config = json.loads(zf.read(CONFIG_NAME))
    for script in ("setup.sh", "run_autograder"):
        assert (infos[script].external_attr >> 16) & 0o111, f"{script} is not executable"
    assert config["checks"] == ["robot-params", "graph"]
    assert "tools/setup.sh" in infos and "grading/traces/mapping_public.bag" in infos
    assert not [n for n in infos if n.startswith(("solutions/", "tests/")) or "__pycache__" in n]
    assert build_zip(tmp_path / "again", ["robot-params", "graph"]).read_bytes() == target.read_bytes()


# -- the course's notebooks ---------------------------------------------------------------------

def test_the_zip_carries_every_course_notebook_with_its_tests_and_none_of_its_answers(tmp_path):
    target = build_zip(tmp_path, ["robot-params"])
    sources = sorted((REPO / "notebooks" / "source").glob("*/*.ipynb"))
    with zipfile.ZipFile(target) as zf:
        shipped = {n: zf.read(n).decode() for n in zf.namelist() if n.startswith("course/source/")}
        assert "course/nbgrader_config.py" in zf.namelist()
    assert sorted(shipped) == [f"course/source/{p.parent.name}/{p.name}" for p in sources]
    regions = solution_texts(course_dir=REPO / "notebooks")  # the leak check's own reading of the regions
    looked_for = 0
    for path in sources:
        source = json.loads(path.read_text())
        text = shipped[f"course/source/{path.parent.name}/{path.name}"]
        answers = {line.strip() for where, lines in regions.items() if where.startswith(f"{path}#")
                   for line in lines if len(line.strip()) > 3}
        looked_for += len(answers)
        kept = json.loads(text)["cells"]
        lines = {line.strip() for c in kept for line in "".join(c["source"]).split("\n")}
        assert not answers & lines, f"{path.name} carries answers"
        tests = [c["source"] for c in source["cells"] if c.get("metadata", {}).get("nbgrader", {}).get("grade")
                 and not c["metadata"]["nbgrader"].get("solution")]
        assert tests == [c["source"] for c in kept if c.get("metadata", {}).get("nbgrader", {}).get("grade")
                         and not c["metadata"]["nbgrader"].get("solution")], f"{path.name}: its tests changed"
    assert looked_for > 20


def test_a_solution_region_keeps_its_markers_and_loses_its_lines_and_a_bare_answer_cell_empties():
    cell = {"cell_type": "code", "outputs": [{"output_type": "stream", "text": "42"}], "execution_count": 3,
            "metadata": {"nbgrader": {"solution": True, "grade_id": "a"}},
            "source": "x = 1\n### BEGIN SOLUTION\nanswer = 42\n### END SOLUTION\ny = 2"}
    text = {"cell_type": "markdown", "metadata": {"nbgrader": {"solution": True, "grade_id": "b"}},
            "source": ["The rumble ", "saturates."]}
    test = {"cell_type": "code", "outputs": [], "execution_count": None, "metadata": {"nbgrader": {"grade": True}},
            "source": "assert answer == 42\n### BEGIN HIDDEN TESTS\nassert answer > 0\n### END HIDDEN TESTS"}
    cells = without_solutions({"cells": [cell, text, test], "metadata": {}})["cells"]
    assert cells[0]["source"] == "x = 1\n### BEGIN SOLUTION\n### END SOLUTION\ny = 2" and cells[0]["outputs"] == []
    assert cells[1]["source"] == "" and cells[2] == test
    assert cell["source"].count("42") == 1  # the original is left alone


def test_notebook_tests_follow_the_checks_and_a_notebook_not_judged_is_named_first():
    nb_test = {"name": "preparation/ex01_fsr_and_arduino.ipynb: ex1a_rate", "score": 0.0, "max_score": 1.0,
               "status": "failed", "visibility": "visible", "output": "not judged"}
    payload = results_payload([_result("robot-params")], notes=["a note"],
                              notebook_tests={"preparation/ex01_fsr_and_arduino.ipynb": [nb_test]},
                              notebooks_unjudged=[("preparation/ex01_fsr_and_arduino.ipynb", "it took too long")])
    assert payload["tests"][-1]["name"] == nb_test["name"] and payload["tests"][-1]["number"] == "2.1"
    assert payload["output"].splitlines()[0] == ("Not judged: preparation/ex01_fsr_and_arduino.ipynb (it took too "
                                                 "long). Those parts show 0 until course staff regrade; you need "
                                                 "not resubmit.")
    assert payload["score"] == _result("robot-params").score


def _notebook(path: Path, cells: list) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))
    return path


def _grade_cell(grade_id: str, points: float, source: str, solution: bool = False) -> dict:
    return {"cell_type": "code", "source": source, "outputs": [], "execution_count": None,
            "metadata": {"nbgrader": {"grade": True, "solution": solution, "grade_id": grade_id, "points": points}}}


def test_a_cell_with_hidden_tests_is_after_published_and_a_failed_cell_says_what_to_do(tmp_path):
    source = _notebook(tmp_path / "ex.ipynb", [
        _grade_cell("seen", 2, "assert rate_hz == 10"),
        _grade_cell("hidden", 1, "assert x\n### BEGIN HIDDEN TESTS\nassert y\n### END HIDDEN TESTS"),
        _grade_cell("written", 2, "YOUR ANSWER HERE", solution=True)])
    tests = cell_tests("lab/ex.ipynb", source, {"seen": 2.0, "hidden": 0.0, "written": 1.0},
                       {"hidden": "AssertionError: y"})
    assert [(t["name"], t["score"], t["max_score"], t["visibility"]) for t in tests] == [
        ("lab/ex.ipynb: seen", 2.0, 2.0, "visible"), ("lab/ex.ipynb: hidden", 0.0, 1.0, "after_published")]
    assert tests[1]["status"] == "failed" and tests[1]["output"].startswith("AssertionError: y\nThis cell checks")
    unjudged = cell_tests("lab/ex.ipynb", source, {"seen": 2.0}, {}, "it took too long")
    assert [t["score"] for t in unjudged] == [0.0, 0.0] and all("not judged: it took too long" in t["output"]
                                                                 for t in unjudged)


def test_a_notebook_run_that_fails_is_not_judged_and_other_notebooks_are_named(tmp_path, monkeypatch):
    from hri_teleop.grading.batch.nbgrader_batch import JobOutcome
    from hri_teleop.grading.gradescope import notebooks

    shipped = tmp_path / "zip"
    for name, data in course_members(REPO / "notebooks"):
        (shipped / name).parent.mkdir(parents=True, exist_ok=True)
        (shipped / name).write_bytes(data)
    why = "nbgrader autograde took longer than 600 s (stopped in ex01_fsr_and_arduino.ipynb)"
    monkeypatch.setattr(notebooks, "install_kernelspec", lambda: tmp_path)
    monkeypatch.setattr(notebooks, "_alembic_on_path", lambda work: None)
    monkeypatch.setattr(notebooks, "_generate", lambda course, assignment, log: "")
    monkeypatch.setattr(notebooks, "autograde_one", lambda course, student, assignment, *a, **k: JobOutcome(
        student, assignment, "notebooks", 0.0, 0.0, "not graded", 600.0, why))
    uploaded = [_notebook(tmp_path / "up" / "a" / "ex01_fsr_and_arduino.ipynb", []),
                _notebook(tmp_path / "up" / "notes.ipynb", []),
                _notebook(tmp_path / "up" / "old" / "copy" / "ex01_fsr_and_arduino.ipynb",
                          [{"cell_type": "markdown", "source": "an old copy", "metadata": {}}])]
    (tmp_path / "hri_lab").mkdir()
    result = notebooks.grade_notebooks(uploaded, tmp_path / "hri_lab", shipped / COURSE, tmp_path / "work")
    assert result.unjudged == [("preparation/ex01_fsr_and_arduino.ipynb", why)]
    tests = result.tests["preparation/ex01_fsr_and_arduino.ipynb"]
    assert len(tests) == 3 and all(t["score"] == 0 and why in t["output"] for t in tests)
    assert any(n.startswith("ignored notes.ipynb: not notebooks of the course") for n in result.notes)
    assert "ex01_fsr_and_arduino.ipynb: in the upload more than once; graded the copy nearest its top" in result.notes
    assert (tmp_path / "work" / "course" / "submitted" / "student" / "preparation" / "ex01_fsr_and_arduino.ipynb"
            ).read_bytes() == uploaded[0].read_bytes()


def test_a_grader_crash_on_the_notebooks_is_one_not_judged_line(tmp_path, monkeypatch):
    from hri_teleop.grading.gradescope import container

    def crash(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(container, "grade_notebooks", crash)
    result = container.grade_upload_notebooks([tmp_path / "ex01_fsr_and_arduino.ipynb"], tmp_path, tmp_path, tmp_path, 60.0, 7, None)
    assert result.unjudged == [("ex01_fsr_and_arduino.ipynb", "the grader stopped with OSError")]
    assert container.grade_upload_notebooks([], tmp_path, tmp_path, tmp_path, 60.0, 7, None).unjudged == []
