"""The student bundle as a student receives it: unpacked on its own, set up with its Makefile, checked
with `make check`. It holds no answer; the answer key copied into its files gets full marks, untouched zero."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tarfile
import tempfile
from pathlib import Path

import pytest

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.bundle import (
    LAB_DELIVERABLES,
    answer_files,
    assemble_bundle,
    pack_bundle,
    toolkit_leaks,
)
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.course.release import prepare_course_copy, solution_texts
from hri_teleop.grading.batch.assignments import ASSIGNMENTS
from hri_teleop.grading.cases.templates import make_answer
from hri_teleop.ros.master import free_port

pytestmark = pytest.mark.ros

#: the notebooks `make check` runs here: a node check, a launch check and the pipeline's graph
CHECKED = "ex05,ex06,ex15"


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    return prepare_course_copy(tmp_path_factory.mktemp("bundle-course"))


@pytest.fixture(scope="module")
def home():
    """A student's home: readable by the unprivileged user the grader runs student code as (when
    the tests run as root), which pytest's own 0700 temporary folders are not."""
    folder = Path(tempfile.mkdtemp(prefix="hri-student-home-"))
    folder.chmod(0o755)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def unpacked(course, home, tmp_path_factory):
    """The bundle packed as `make release` packs it, then unpacked where no checkout is."""
    work = tmp_path_factory.mktemp("bundle")
    archive = pack_bundle(assemble_bundle(course / "release", work / "assembled", ASSIGNMENTS), work / "b.tar.gz")
    with tarfile.open(archive) as tar:
        tar.extractall(home)
    return home / "task4"


def _copy(installed: Path, home: Path, name: str) -> Path:
    """A second student's folder sharing the installed toolkit's .venv (set up once)."""
    bundle = home / name / "task4"
    shutil.copytree(installed, bundle, symlinks=True, ignore=shutil.ignore_patterns(".venv"))
    os.symlink(installed / "toolkit" / ".venv", bundle / "toolkit" / ".venv")
    (home / name).chmod(0o755)
    return bundle


def test_the_bundle_has_its_three_commands_and_the_provided_nodes(unpacked):
    make = (unpacked / "Makefile").read_text()
    for target in ("setup:", "lab:", "check:"):
        assert target in make
    assert "make check" in (unpacked / "README.md").read_text()
    scripts = unpacked / "toolkit" / "hri_lab" / "scripts"
    for provided in ("FSR_sensor.py", "gripper_manager.py", "teleoperation_subscriber_publisher.py", "lab_sim.py"):
        assert (scripts / provided).is_file(), provided
    for assignment in ASSIGNMENTS:
        assert (unpacked / assignment / STUDENT_PACKAGE / "package.xml").is_file()


def test_the_pages_the_provided_nodes_point_to_are_in_the_bundle_and_the_rubric_is_not(unpacked):
    toolkit = unpacked / "toolkit"
    pointed = {m for path in (toolkit / "hri_lab").rglob("*") if path.is_file() and path.suffix in (".py", ".md")
               for m in re.findall(r"docs/[\w-]+\.md", path.read_text(encoding="utf-8"))}
    assert "docs/ros-nodes.md" in pointed
    assert [page for page in sorted(pointed) if not (toolkit / page).is_file()] == []
    assert not (toolkit / "docs" / "instructors.md").exists()


def test_the_bundle_holds_no_solution_line_and_no_completed_deliverable(unpacked, course):
    assert toolkit_leaks(unpacked, solution_texts(SOLUTIONS, course), answer_files()) == []
    assert not (unpacked / "toolkit" / "tests").exists() and not (unpacked / "toolkit" / "solutions").exists()


def test_the_leak_check_finds_a_deliverable_copied_into_the_toolkit(unpacked, course, tmp_path):
    bundle = tmp_path / "task4"
    shutil.copytree(unpacked, bundle, symlinks=True)
    hidden = bundle / "toolkit" / "hri_teleop" / "hardware" / "sim" / "answer.launch"
    hidden.write_text(make_answer((SOLUTIONS / "launch" / "sensor.launch").read_text()))
    (bundle / "toolkit" / LAB_DELIVERABLES[0]).write_text("#!/usr/bin/env python3\n")
    leaks = toolkit_leaks(bundle, solution_texts(SOLUTIONS, course), answer_files())
    assert any("answer.launch" in leak and "completed" in leak for leak in leaks)
    assert any(LAB_DELIVERABLES[0] in leak for leak in leaks)


def _copy_answer_key(bundle: Path, course: Path) -> None:
    """What a student who knows every answer hands in: the answer key's files and solution cells."""
    for assignment in ASSIGNMENTS:
        package = bundle / assignment / STUDENT_PACKAGE
        for where, text in answer_files().items():
            relative = Path(where).relative_to(SOLUTIONS)
            if (package / relative).is_file():
                (package / relative).write_text(text)
                if relative.suffix == ".py":
                    (package / relative).chmod(0o755)
        for notebook in (bundle / assignment).glob("ex*.ipynb"):
            source = json.loads((course / "source" / assignment / notebook.name).read_text())
            answers = {c["metadata"]["nbgrader"]["grade_id"]: c["source"] for c in source["cells"]
                       if c.get("metadata", {}).get("nbgrader", {}).get("solution")}
            student = json.loads(notebook.read_text())
            for cell in student["cells"]:
                grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
                if grade_id in answers:
                    cell["source"] = answers[grade_id]
            notebook.write_text(json.dumps(student))


def _student_env() -> dict:
    """Only the machine's own PATH: no project .venv, no ROS_PACKAGE_PATH pointing at this checkout."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "VIRTUAL_ENV", "PYTHON", "HRI_"))}
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if ".venv" not in p)
    env["SDL_VIDEODRIVER"] = env["SDL_AUDIODRIVER"] = "dummy"
    return env


def _make(bundle: Path, *args: str, timeout: float) -> subprocess.CompletedProcess:
    env = _student_env()
    return subprocess.run(["make", "-C", str(bundle), *args], capture_output=True, text=True, timeout=timeout,
                          env=env, stdin=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def installed(unpacked):
    """`make setup` of the bundle: its own venv with the toolkit, as on a student's machine."""
    done = _make(unpacked, "setup", timeout=1200)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    return unpacked


def test_the_installed_toolkit_holds_no_answer(installed, course):
    site = next((installed / "toolkit" / ".venv" / "lib").glob("python3*/site-packages"))
    probe = subprocess.run([str(installed / "toolkit" / ".venv" / "bin" / "python"), "-c",
                            "import hri_teleop, pathlib; print(pathlib.Path(hri_teleop.__file__).parent)"],
                           capture_output=True, text=True, check=True, cwd=installed, env=_student_env())
    assert Path(probe.stdout.strip()) == installed / "toolkit" / "hri_teleop"  # no checkout is imported
    # the toolkit is installed in place: site-packages holds only its metadata and import hook
    owned = [p.name for p in site.iterdir() if "hri_teleop" in p.name]
    assert owned and all(n.endswith(".dist-info") or n.startswith("__editable__") for n in owned), owned
    assert toolkit_leaks(installed / "toolkit", solution_texts(SOLUTIONS, course), answer_files()) == []


def _points(output: str) -> dict:
    scores = {}
    for line in output.splitlines():
        if line.strip().endswith(")") and "points (" in line:
            name = line.split("/")[1].split(".ipynb")[0] if "/" in line else line
            got, most = line.split(" ... ")[1].split(" points")[0].split("/")
            scores[name.strip()] = (float(got), float(most))
    return scores


def test_untouched_the_bundle_scores_zero(installed, home):
    bundle = _copy(installed, home, "untouched")
    done = _make(bundle, "check", f"ONLY={CHECKED}", timeout=1200)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    scores = _points(done.stdout)
    assert len(scores) == 3 and all(got == 0 for got, _most in scores.values()), done.stdout


def test_with_the_answer_key_copied_in_the_bundle_gets_full_marks(installed, course, home):
    bundle = _copy(installed, home, "answers")
    _copy_answer_key(bundle, course)
    done = _make(bundle, "check", f"ONLY={CHECKED}", timeout=1200)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    scores = _points(done.stdout)
    assert len(scores) == 3 and all(got == most > 0 for got, most in scores.values()), done.stdout


def test_make_lab_serves_the_bundle_with_the_toolkits_kernel(installed):
    done = _make(installed, "lab", "LAB_ARGS=--version", timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    kernel = json.loads(next((installed / "toolkit" / ".venv" / "share" / "jupyter" / "kernels").glob(
        "hri-teleop/kernel.json")).read_text())
    assert kernel["argv"][1] == str(installed / "toolkit" / "tools" / "kernel.sh")
    assert done.stderr.strip() == ""


def test_make_doctor_checks_the_simulated_lab_from_the_bundle_alone(installed):
    env = _student_env()
    env.update({"HRI_MODE": "home", "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}/"})  # nobody there
    done = subprocess.run(["make", "-C", str(installed), "doctor"], capture_output=True, text=True, timeout=300,
                          env=env, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert re.search(r"^ok\s+robot\s+the simulation \(lab_sim\)", done.stdout, re.M), done.stdout
    assert re.search(r"^ok\s+board\s+the simulated board", done.stdout, re.M), done.stdout
