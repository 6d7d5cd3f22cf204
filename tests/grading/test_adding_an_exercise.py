"""docs/adding-an-exercise.md followed to the letter (issue 45, item 2): a made-up exercise, ``lab_notes``
(config/lab_notes.yaml: ``operator`` and ``trials``, two parts), added to a scratch copy of the checkout
through the guide's worked example only, then released, graded by ``make grade`` and by the Gradescope
layout, checked by the student bundle's ``make check``, and shown in the class report.

The guide's example blocks are the only edits: each ``<!-- example: new PATH -->`` block is written as that
file, each ``<!-- example: entry PATH NAME -->`` block goes in as the last entry of the table ``NAME`` there.
A path that needed anything else would need a change of the grader's shared code (the test fails then).

The copy is what git has (tracked files, and new ones not ignored: never a build's leftovers) with a
``.venv`` of its own that reuses the checkout's packages, so its ``hri_teleop`` is the one imported and the
kernels it registers are its own. Every make runs with ``-o setup`` (the suite runs after ``make setup``).
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import zipfile
from pathlib import Path
from typing import Dict, List, Tuple

import pytest
from grading_helpers import REPO, run_session

pytestmark = pytest.mark.ros

GUIDE = REPO / "docs" / "adding-an-exercise.md"
KEY, CHECK = "lab_notes", "lab-notes"
ASSIGNMENT, NOTEBOOK, FILE = "lab", "ex16_lab_notes", "config/lab_notes.yaml"
#: What a student who got the number of trials wrong hands in (the operator is right).
WRONG = "operator: bob\ntrials: '5'\n"
#: What make, nbgrader and the grader may take here at most (s): a hang fails the test, not the run.
TIMEOUT_S = 600
_EXAMPLE = re.compile(r"^<!-- example: (new|entry) (\S+)(?: (\w+))? -->\n```\w*\n(.*?)^```$", re.M | re.S)


# -- the guide's worked example, applied -------------------------------------------------------------

def guide_examples(text: str) -> List[Tuple[str, str, str, str]]:
    """(action, path, table, block) of every example block of the guide, in its order."""
    return [(m.group(1), m.group(2), m.group(3) or "", m.group(4)) for m in _EXAMPLE.finditer(text)]


def add_entry(text: str, table: str, lines: str, where: str) -> str:
    """``text`` with ``lines`` as the last entries of the table assigned to ``table`` (a dict or a tuple whose
    closing bracket is alone on its line)."""
    source = text.split("\n")
    start = next((i for i, line in enumerate(source) if re.match(rf"{table}\b.*=\s*[{{(]\s*$", line)), None)
    assert start is not None, f"{where}: no table {table} = {{ or ( (the guide names it)"
    end = next(i for i in range(start + 1, len(source)) if source[i] in ("}", ")"))
    return "\n".join(source[:end] + lines.rstrip("\n").split("\n") + source[end:])


def apply_guide(root: Path) -> List[str]:
    """The guide's example applied to the copy at ``root``; the paths it wrote."""
    touched = []
    for action, path, table, block in guide_examples(GUIDE.read_text(encoding="utf-8")):
        target = root / path
        if action == "new":
            assert not target.exists(), f"the guide's example writes {path}, which the checkout has already"
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(block, encoding="utf-8")
        else:
            target.write_text(add_entry(target.read_text(encoding="utf-8"), table, block, path), encoding="utf-8")
        touched.append(path)
    return touched


# -- a scratch copy of the checkout, and the environments to run it in ---------------------------------

def checkout_files(root: Path = REPO) -> List[str]:
    """What a clone of the checkout holds: git's tracked files and new files not ignored, as they are now."""
    listed = subprocess.run(["git", "-C", str(root), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                            capture_output=True, check=True).stdout.decode("utf-8", "surrogateescape")
    return sorted({n for n in listed.split("\0") if n and os.path.lexists(root / n)})


def copy_checkout(target: Path) -> Path:
    for name in checkout_files():
        source, dest = REPO / name, target / name
        dest.parent.mkdir(parents=True, exist_ok=True)
        if source.is_symlink():
            os.symlink(os.readlink(source), dest)
        elif source.is_file():
            shutil.copy2(source, dest)
    return target


def venv_reusing_the_checkouts(root: Path) -> Path:
    """``root/.venv``: a virtual environment of the checkout's .venv's Python whose packages are that .venv's
    (nothing downloaded) and whose ``hri_teleop`` is ``root``'s; its share/ holds the checkout's Jupyter files
    but a kernels folder of its own (the copy registers its own "hri-teleop" kernel there, never the checkout's)."""
    venv = root / ".venv"
    base = getattr(sys, "_base_executable", sys.executable)
    subprocess.run([base, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    purelib = Path(subprocess.run([str(venv / "bin" / "python"), "-c",
                                   "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                                  capture_output=True, text=True, check=True).stdout.strip())
    (purelib / "00-hri-teleop-copy.pth").write_text(f"{root}\n")
    (purelib / "hri-teleop-reuse.pth").write_text(f"import site; site.addsitedir({sysconfig.get_paths()['purelib']!r})\n")
    for script in Path(sys.prefix, "bin").iterdir():  # the console scripts (nbgrader runs alembic by name)
        if not (venv / "bin" / script.name).exists() and script.is_file() and not script.is_symlink():
            head, _, rest = script.read_bytes().partition(b"\n")
            if head.startswith(b"#!") and head[2:].strip() == str(Path(sys.prefix, "bin", "python")).encode():
                (venv / "bin" / script.name).write_bytes(b"#!" + str(venv / "bin" / "python").encode() + b"\n" + rest)
                (venv / "bin" / script.name).chmod(0o755)
    theirs = Path(sys.prefix) / "share"
    for entry in theirs.iterdir() if theirs.is_dir() else []:
        if entry.name != "jupyter":
            (venv / "share").mkdir(exist_ok=True)
            os.symlink(entry, venv / "share" / entry.name)
    for entry in (theirs / "jupyter").iterdir() if (theirs / "jupyter").is_dir() else []:
        (venv / "share" / "jupyter" / "kernels").mkdir(parents=True, exist_ok=True)
        if entry.name != "kernels":
            os.symlink(entry, venv / "share" / "jupyter" / entry.name)
    for kernel in (theirs / "jupyter" / "kernels").glob("*"):
        if kernel.name != "hri-teleop":
            os.symlink(kernel, venv / "share" / "jupyter" / "kernels" / kernel.name)
    return venv


def fresh_env(**extra: str) -> Dict[str, str]:
    """A new terminal: no ROS variables, nothing of the checkout's .venv (make sources the copy's env.sh)."""
    drop = ("ROS", "HRI_", "PYTHON", "VIRTUAL_ENV", "CMAKE_PREFIX_PATH", "CATKIN", "JUPYTER", "NBGRADER", "MAKE",
            "MFLAGS")
    env = {k: v for k, v in os.environ.items() if not k.startswith(drop)}
    env["PATH"] = ":".join(p for p in os.environ.get("PATH", "/usr/bin:/bin").split(":")
                           if p and not p.startswith(str(REPO)) and "/.venv" not in p)
    env.update(SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy", **extra)
    return env


def run(argv: List[str], cwd: Path, env: Dict[str, str]) -> subprocess.CompletedProcess:
    """``argv`` in a session of its own (everything it starts is killed if it hangs); output printed."""
    return run_session(argv, cwd, env, TIMEOUT_S)


def make(folder: Path, *args: str, env: Dict[str, str]) -> str:
    done = run(["make", "-s", "-o", "setup", *args], folder, env)
    assert done.returncode == 0, done.stdout[-4000:]
    return done.stdout


@pytest.fixture(scope="module")
def scratch():
    """A folder every uid may enter (the grader's student uid reads the copies), removed afterwards."""
    folder = Path(tempfile.mkdtemp(prefix="hri-adding-an-exercise-"))
    folder.chmod(0o755)
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def repo(scratch):
    """The copy with the guide's example added and ``make release`` run: (its root, the paths the guide wrote)."""
    root = copy_checkout(scratch / "repo")
    touched = apply_guide(root)
    venv_reusing_the_checkouts(root)
    make(root, "release", env=fresh_env())
    return root, touched


def _answer(root: Path) -> str:
    from hri_teleop.grading.cases.templates import make_answer

    return make_answer((root / "solutions" / "hri_lab" / FILE).read_text(encoding="utf-8"))


# -- the guide's steps ---------------------------------------------------------------------------------

def test_the_guide_adds_an_exercise_in_its_module_the_registry_line_the_answer_key_the_notebook_and_check_cells(repo):
    root, touched = repo
    assert sorted(touched) == sorted([
        f"hri_teleop/grading/exercises/{KEY}.py",  # the exercise
        "hri_teleop/grading/deliverables.py",  # its registry line
        f"solutions/hri_lab/{FILE}",  # the reference answer (the template is made from it)
        f"notebooks/source/{ASSIGNMENT}/{NOTEBOOK}.ipynb",  # the notebook with its read-only check cell
        "hri_teleop/grading/points.py",  # the course's map of check cells
    ]), touched
    # the exercise is known to every way of grading in the copy, and counted in its assignment
    probe = run([str(root / ".venv" / "bin" / "python"), "-c",
                 "from hri_teleop.grading.exercises.registry import checks\n"
                 "from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS\n"
                 "from hri_teleop.grading.points import check_points, check_cell_problems\n"
                 "from hri_teleop.course.check import calls\n"
                 "from hri_teleop.core.paths import REPO\n"
                 f"print(REPO, checks()[-1], ASSIGNMENT_CHECKS[{ASSIGNMENT!r}][-1], check_points({CHECK!r}), "
                 f"{KEY!r} in calls(), check_cell_problems(REPO / 'notebooks' / 'source'))"], root, fresh_env())
    assert probe.returncode == 0 and probe.stdout.split() == [str(root), CHECK, CHECK, "3.0", "True", "[]"], probe.stdout


def test_make_release_ships_the_template_and_the_check_cell_and_no_answer(repo):
    root, _ = repo
    answer = _answer(root)
    with tarfile.open(root / "out" / "task4-student-bundle.tar.gz") as tar:
        names = tar.getnames()
        template = tar.extractfile(f"task4/{ASSIGNMENT}/hri_lab/{FILE}").read().decode()
        notebook = json.loads(tar.extractfile(f"task4/{ASSIGNMENT}/{NOTEBOOK}.ipynb").read())
        texts = {m.name: tar.extractfile(m).read().decode("utf-8", "replace") for m in tar.getmembers() if m.isfile()}
    assert "# YOUR CODE HERE" in template and "SOLUTION" not in template, template
    cells = [c for c in notebook["cells"] if c["metadata"].get("nbgrader", {}).get("grade_id") == "ex16_notes"]
    assert len(cells) == 1 and "".join(cells[0]["source"]).strip() == f"check.{KEY}(PACKAGE)", cells
    assert (cells[0]["metadata"]["nbgrader"]["grade"], cells[0]["metadata"]["nbgrader"]["locked"]) == (False, True)
    assert f"task4/toolkit/hri_teleop/grading/exercises/{KEY}.py" in names
    assert not any(n.startswith(("task4/toolkit/solutions", f"task4/toolkit/hri_lab/{FILE}")) for n in names)
    answer_lines = [line.strip() for line in answer.splitlines() if line.strip() and not line.startswith("#")]
    assert answer_lines, answer
    leaks = [(name, line) for name, text in texts.items() for line in answer_lines
             if line in [t.strip() for t in text.splitlines()]]
    assert leaks == [], leaks


def _nbgrader_course(root: Path, course: Path) -> Path:
    """A course of the copy's new notebook alone (as tests/grading/grading_helpers.nbgrader_course), released."""
    source = course / "source" / ASSIGNMENT
    source.mkdir(parents=True)
    shutil.copy(root / "notebooks" / "nbgrader_config.py", course / "nbgrader_config.py")
    shutil.copy(root / "notebooks" / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb", source)
    (source / "hri_lab").symlink_to(root / "solutions" / "hri_lab", target_is_directory=True)
    make(root, "nbgrader", f"DIR={course}", f"ARGS=generate_assignment {ASSIGNMENT} --create --force", env=fresh_env())
    return course


def _hand_in(root: Path, course: Path) -> Path:
    """alice hands in the answer key, bob the release with the number of trials in quotes."""
    from hri_teleop.grading.cases.templates import generate_answers

    submitted = course / "submitted"
    alice = submitted / "alice" / ASSIGNMENT
    alice.mkdir(parents=True)
    shutil.copy(course / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb", alice)
    generate_answers(root / "solutions" / "hri_lab", alice / "hri_lab")
    bob = submitted / "bob" / ASSIGNMENT  # the release as make release made it, one line written wrong
    shutil.copytree(root / "notebooks" / "release" / ASSIGNMENT / "hri_lab", bob / "hri_lab")
    shutil.copy(course / "release" / ASSIGNMENT / f"{NOTEBOOK}.ipynb", bob)
    (bob / "hri_lab" / FILE).write_text(WRONG)
    return submitted


def test_make_grade_gives_the_new_checks_points_in_the_grades_the_feedback_and_the_class_report(repo, scratch):
    root, _ = repo
    course = _nbgrader_course(root, scratch / "course")
    submitted = _hand_in(root, course)
    out = scratch / "grades"
    make(root, "grade", f"DIR={submitted}", f"OUT={out}", f"CHECKS={CHECK}", "JOBS=2", env=fresh_env())
    with open(out / "grades.csv") as fh:
        rows = {row["student"]: row for row in csv.DictReader(fh)}
    assert {s: (r["status"], float(r["files_score"])) for s, r in rows.items()} == \
        {"alice": ("graded", 3.0), "bob": ("graded", 1.0)}, rows
    report = (out / "report.html").read_text(encoding="utf-8")
    assert CHECK in report and "trials: how many trials you ran" in report, report[:3000]
    bob_feedback = "\n".join(p.read_text(encoding="utf-8", errors="replace") for p in (out / "bob").rglob("*")
                             if p.is_file() and p.suffix in (".txt", ".html", ".json"))
    assert "trials is the string '5'" in bob_feedback, bob_feedback[:3000]


def test_the_gradescope_layout_grades_the_new_check_a_test_per_part(repo, scratch):
    root, _ = repo
    zipped = scratch / "gradescope"
    make(root, "gradescope", f"OUT={zipped}", f"CHECKS={CHECK}", env=fresh_env())
    box = scratch / "autograder"
    source = box / "source"
    with zipfile.ZipFile(zipped / "autograder.zip") as zf:
        zf.extractall(source)
        for info in zf.infolist():
            (source / info.filename).chmod((info.external_attr >> 16) & 0o777)
    venv_reusing_the_checkouts(source)  # what setup.sh installs there
    (box / "submission" / "hri_lab" / "config").mkdir(parents=True)
    (box / "submission" / "hri_lab" / FILE).write_text(WRONG)
    # run_autograder's own steps, with /autograder at ``box``
    done = run(["bash", "-c", f"cd {source} && . tools/env.sh && export PYTHONPATH={source} && "
                              f".venv/bin/python -m hri_teleop.grading.gradescope.container --root {box}"],
               source, fresh_env())
    assert done.returncode == 0, done.stdout[-3000:]
    results = json.loads((box / "results" / "results.json").read_text())
    tests = {t["name"]: t for t in results["tests"]}
    assert len(tests) == 2 and all(CHECK in name for name in tests), tests
    assert results["score"] == 1.0 and sum(t["max_score"] for t in tests.values()) == 3.0, results
    failed = [t for t in tests.values() if t["score"] < t["max_score"]]
    assert len(failed) == 1 and "trials is the string '5'" in failed[0]["output"], failed


def test_make_check_in_the_bundle_shows_the_new_check_cell_and_the_files_points_with_their_feedback(repo, scratch):
    root, _ = repo
    home = scratch / "home"
    home.mkdir()
    home.chmod(0o755)
    with tarfile.open(root / "out" / "task4-student-bundle.tar.gz") as tar:
        tar.extractall(home)
    bundle = home / "task4"
    venv_reusing_the_checkouts(bundle / "toolkit")  # what the bundle's make setup installs
    (bundle / ASSIGNMENT / "hri_lab" / FILE).write_text(WRONG)
    output = make(bundle, "check", "ONLY=ex16", env=fresh_env())
    assert f"{ASSIGNMENT}/{NOTEBOOK}.ipynb ... 0/0 points" in output, output
    assert f"{ASSIGNMENT}/hri_lab: {CHECK} 1/3: 1/3 points" in output, output
    assert "[FAIL] trials: how many trials you ran, an integer of at least 3 (0/2)" in output, output
    assert "trials is the string '5'" in output, output
    assert "check: 1/3 points for your files" in output, output
