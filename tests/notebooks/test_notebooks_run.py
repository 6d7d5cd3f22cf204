"""Every source notebook runs top to bottom and gets full marks; every student version fails.

The whole course is checked once, in a temporary copy: ``nbgrader generate_assignment``
writes the student versions (and the hri_lab templates next to them), then each source
notebook is executed headless with nbclient (the kernel of this .venv, no gamepad: the
virtual pad and the simulation, a private roscore per notebook) and graded as nbgrader
grades, and each student version goes through nbgrader's ``validate --invert`` -- two
notebooks at a time. Real-time cells run short (HRI_NOTEBOOK_FAST).
"""

from __future__ import annotations

import hashlib
import shutil
import time
from pathlib import Path

import pytest

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.course.release import (
    bundle_leaks,
    prepare_course_copy,
    run_course,
    solution_texts,
    source_notebooks,
)

NAMES = [p.stem for p in source_notebooks()]
pytestmark = pytest.mark.ros


def _tree_digest(root: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(p for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
        digest.update(str(path.relative_to(root)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    if shutil.which("roscore") is None:
        pytest.fail("roscore not found: run 'make setup' (installs ROS 1) or source tools/env.sh")
    work = tmp_path_factory.mktemp("course")
    key_before = _tree_digest(SOLUTIONS)
    started = time.monotonic()
    course_dir = prepare_course_copy(work)
    bundle = work / "bundle"  # the release as generated, before the student versions run in place
    shutil.copytree(course_dir / "release", bundle)
    results = run_course(course_dir)
    elapsed = time.monotonic() - started
    print(f"\nnotebooks: generate + {2 * len(results)} executions in {elapsed:.0f} s")
    return {"dir": course_dir, "bundle": bundle, "results": results, "key_before": key_before, "seconds": elapsed}


@pytest.mark.parametrize("name", NAMES)
def test_source_notebook_runs_without_error_and_gets_full_marks(course, name):
    source = course["results"][name]["source"]
    assert source["errors"] == [], f"{name}: " + "\n".join(source["errors"])
    short = {gid: got for gid, (got, most) in source["grades"].items() if got != most}
    assert short == {}, f"{name}: the answer key loses points in {short}"


@pytest.mark.parametrize("name", NAMES)
def test_student_version_fails_every_autograded_cell(course, name):
    release = course["results"][name]["release"]
    assert not release.get("changed") and not release.get("type_changed"), release
    passed = [cell["source"] for cell in release.get("passed", [])]
    assert passed == [], f"{name}: these autograded cells pass without the student's work: {passed}"


def test_running_the_notebooks_leaves_the_answer_key_unchanged(course):
    assert _tree_digest(SOLUTIONS) == course["key_before"]


def test_student_bundle_has_every_notebook_and_the_generated_templates(course):
    from hri_teleop.grading.cases.templates import generate_templates

    release = course["bundle"]
    assert sorted(p.stem for p in release.glob("*/*.ipynb")) == sorted(NAMES)
    others = [p for p in release.rglob("*") if p.is_file() and p.suffix != ".ipynb" and STUDENT_PACKAGE not in p.parts]
    assert others == [], "the bundle holds only the notebooks and the student's package"
    expected = course["dir"] / "expected-templates"
    generate_templates(SOLUTIONS, expected)
    for assignment in ("preparation", "lab"):
        package = release / assignment / STUDENT_PACKAGE
        assert not package.is_symlink()
        files = sorted(p.relative_to(package) for p in package.rglob("*") if p.is_file())
        assert files == sorted(p.relative_to(expected) for p in expected.rglob("*") if p.is_file())
        for relative in files:
            assert (package / relative).read_bytes() == (expected / relative).read_bytes(), relative


def test_student_bundle_holds_no_solution_text(course):
    assert bundle_leaks(course["bundle"], solution_texts(SOLUTIONS, course["dir"])) == []


def test_leak_check_finds_a_solution_line_in_a_template_and_in_a_notebook(course, tmp_path):
    bundle = tmp_path / "bundle"
    shutil.copytree(course["bundle"], bundle)
    texts = solution_texts(SOLUTIONS, course["dir"])
    script = bundle / "preparation" / STUDENT_PACKAGE / "scripts" / "mapping_node.py"
    script.write_text(script.read_text() + "\n        self.publisher = rospy.Publisher(\"/force_mapped\", Float32, queue_size=10)\n")
    leaks = bundle_leaks(bundle, texts)
    assert any("mapping_node.py" in leak and "Publisher" in leak for leak in leaks)
    notebook = bundle / "lab" / "ex11_calibration.ipynb"
    notebook.write_text(notebook.read_text().replace("# YOUR CODE HERE", "max_sensor_force = int(max(count for _time, count in record.count))"))
    assert any("ex11_calibration" in leak for leak in bundle_leaks(bundle, texts))


def test_a_check_cell_shows_full_points_on_a_machine_without_bubblewrap(course, monkeypatch):
    """The grader's "no bubblewrap" note must not reach a check cell's stderr (the student would see an
    error); the cell shows the check's points (the files': the cell itself is read-only)."""
    import nbformat
    from nbclient import NotebookClient

    from hri_teleop.course.check import POINTS_NOTE
    from hri_teleop.grading.exercises.teleoperation_launch.judge import PARTS as TELEOP_LAUNCH
    from hri_teleop.ros.kernel import ipc_kernel_config

    monkeypatch.setenv("HRI_GRADE_SANDBOX", "none")
    path = course["dir"] / "source" / "lab" / "ex12_13_teleoperation_launch.ipynb"
    nb = nbformat.read(str(path), as_version=4)
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=300, startup_timeout=120, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()
    full = sum(points for _name, points in TELEOP_LAUNCH.values())
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert [o for o in outputs if o.output_type == "error" or o.get("name") == "stderr"] == []
    cell = next(c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "ex12_launch")
    printed = "".join(o.text for o in cell.outputs if o.output_type == "stream")
    assert f"total: {full:g}/{full:g}" in printed and POINTS_NOTE in printed, printed
    assert [o.data["text/plain"] for o in cell.outputs if o.output_type == "execute_result"] == [f"{float(full)!r}"]
