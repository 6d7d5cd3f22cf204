"""The Gradescope autograder in Gradescope's own layout: the zip unpacked into /autograder/source, setup.sh,
an upload in /autograder/submission, run_autograder, /autograder/results/results.json.

/autograder is a folder of the test's, mounted there by bubblewrap over an otherwise read-only view
of the machine (the host's / is never written). setup.sh is the zip's own; it reuses the checkout's
.venv packages (HRI_GRADESCOPE_REUSE_VENV) instead of downloading them. The uploads are graded two at
a time, each in a box of its own sharing the one source folder, as Gradescope shares its image.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Dict, List

import pytest
from grading_helpers import (
    REPO,
    SOLUTIONS,
    answer_text,
    corpus_files,
    expectation,
    grader_env,
    open_folder,
    part_keys,
)

from hri_teleop.course.release import COURSE_DIR, STUDENT_MAKES_EXECUTABLE
from hri_teleop.grading.cases.templates import generate_templates
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.gradescope.build import build_zip
from hri_teleop.grading.points import check_points

pytestmark = pytest.mark.ros
#: The course notebook the uploads hold: Ex. 1 runs no ROS, so it autogrades in seconds.
NOTEBOOK = "ex01_fsr_and_arduino.ipynb"
#: The answer key's upload also holds Ex. 4, whose check cell shows robot-params (its points are the files').
CHECK_NOTEBOOK = "ex04_robot_params.ipynb"
_ENV = {"PATH": "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin", "HOME": "/tmp/home", "LANG": "C.UTF-8"}


def _box(root: Path, source: Path, argv: List[str], env: Dict[str, str], timeout_s: float) -> subprocess.CompletedProcess:
    """``argv`` with ``root`` at /autograder, ``source`` at /autograder/source and a /tmp of its own."""
    args = ["bwrap", "--die-with-parent", "--tmpfs", "/", "--dev", "/dev", "--proc", "/proc"]
    for entry in sorted(Path("/").iterdir()):
        if entry.name in ("dev", "proc", "tmp", "autograder"):
            continue
        args += ["--symlink", str(entry.readlink()), str(entry)] if entry.is_symlink() else ["--bind", str(entry), str(entry)]
    (root / "tmp" / "home").mkdir(parents=True, exist_ok=True)
    (root / "ag" / "source").mkdir(parents=True, exist_ok=True)
    args += ["--bind", str(root / "tmp"), "/tmp", "--bind", str(root / "ag"), "/autograder",
             "--bind", str(source), "/autograder/source", "--chdir", "/autograder"]
    # The checkout's .venv (HRI_GRADESCOPE_REUSE_VENV) stays visible where a checkout lives under /tmp (CI),
    # its folders traversable by the students' uid (bwrap would make them 0700).
    venv = REPO / ".venv"
    if str(venv).startswith("/tmp/"):
        mount_point = root / "tmp" / venv.relative_to("/tmp")
        mount_point.mkdir(parents=True, exist_ok=True)
        for folder in [mount_point, *mount_point.parents][: len(venv.relative_to("/tmp").parts)]:
            folder.chmod(0o755)
        args += ["--ro-bind", str(venv), str(venv)]
    return subprocess.run(args + argv, env=dict(_ENV, **env), capture_output=True, text=True, timeout=timeout_s,
                          stdin=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def autograder():
    """(folder of the boxes, the source folder after setup.sh, setup.sh's seconds)."""
    if shutil.which("bwrap") is None or subprocess.run(["bwrap", "--dev-bind", "/", "/", "true"]).returncode:
        pytest.skip("bubblewrap cannot run here: the Gradescope layout needs it to mount /autograder")
    for folder in open_folder("hri-gradescope-"):
        zip_path = build_zip(folder / "zip")
        source = folder / "source"
        with zipfile.ZipFile(zip_path) as zf:
            zf.extractall(source)
            for info in zf.infolist():
                (source / info.filename).chmod((info.external_attr >> 16) & 0o777)
        started = time.monotonic()
        setup = _box(folder / "setup", source, ["bash", "/autograder/source/setup.sh"],
                     {"HRI_GRADESCOPE_REUSE_VENV": str(REPO / ".venv")}, timeout_s=300)
        assert setup.returncode == 0, f"setup.sh failed:\n{setup.stdout}\n{setup.stderr}"
        yield folder, source, time.monotonic() - started


def _answer_key(root: Path) -> Path:
    for path in SOLUTIONS.rglob("*"):
        if path.is_file() and path.name != "README.md":
            target = root / path.relative_to(SOLUTIONS)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(answer_text(str(path.relative_to(SOLUTIONS))))
            shutil.copymode(path, target)
    return root


def _corpus(name: str, root: Path) -> Path:
    """Corpus entry ``name`` on top of the answer key (the student got one thing wrong)."""
    _answer_key(root)
    for relative, text in corpus_files(name).items():
        (root / relative).write_text(text)
    return root


def _messy_zip(package: Path, upload: Path) -> None:
    """A Finder-made zip of a zip: the package two folders down, __MACOSX and ._ copies beside it."""
    inner = upload / "inner.zip"
    upload.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(inner, "w", zipfile.ZIP_DEFLATED) as zf:
        for path in sorted(package.rglob("*")):
            if path.is_file():
                name = f"Lab 4/my work/hri_lab/{path.relative_to(package).as_posix()}"
                zf.write(path, name)
                zf.writestr(f"__MACOSX/{Path(name).parent.as_posix()}/._{path.name}", "\0\5\26\7 junk")
    with zipfile.ZipFile(upload / "submission.zip", "w") as zf:
        zf.write(inner, "Archive/inner.zip")
        zf.writestr("__MACOSX/Archive/._inner.zip", "junk")
    inner.unlink()


def _loose(package: Path, upload: Path) -> None:
    """Every file dropped at the upload's top level, as Gradescope's drag and drop does."""
    upload.mkdir(parents=True, exist_ok=True)
    for path in package.rglob("*"):
        if path.is_file():
            shutil.copy2(path, upload / path.name)


def _released_notebook(work: Path) -> Path:
    """NOTEBOOK as students get it (nbgrader generate_assignment in a course of its own)."""
    course = work / "course"
    (course / "source" / "preparation").mkdir(parents=True)
    shutil.copy(COURSE_DIR / "nbgrader_config.py", course)
    shutil.copy(COURSE_DIR / "source" / "preparation" / NOTEBOOK, course / "source" / "preparation")
    proc = subprocess.run([sys.executable, "-m", "nbgrader", "generate_assignment", "preparation", "--create"],
                          cwd=course, capture_output=True, text=True, env=grader_env(PYTHONWARNINGS="ignore"),
                          timeout=120)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    return course / "release" / "preparation" / NOTEBOOK


def _cases(work: Path) -> Dict[str, dict]:
    """name -> the upload folder and the checks graded (None: the zip's, i.e. all).

    The answer key's upload also holds the instructor's NOTEBOOK and CHECK_NOTEBOOK (every answer in them); the
    template's the released NOTEBOOK, untouched, and a notebook that is not the course's;
    params_robot_mass_int's the instructor's NOTEBOOK with a cell reaching for the autograder's files.
    """
    generate_templates(SOLUTIONS, work / "template" / "hri_lab", not_executable=STUDENT_MAKES_EXECUTABLE)
    cases = {
        "answer key": {"upload": _answer_key(work / "key" / "upload" / "hri_lab").parent, "checks": None},
        "template": {"upload": work / "template", "checks": None},
    }
    shutil.copy(COURSE_DIR / "source" / "preparation" / NOTEBOOK, work / "key" / "upload")
    shutil.copy(COURSE_DIR / "source" / "preparation" / CHECK_NOTEBOOK, work / "key" / "upload")
    shutil.copy(_released_notebook(work / "release"), work / "template")
    (work / "template" / "Untitled.ipynb").write_text(json.dumps({"cells": [], "metadata": {}, "nbformat": 4,
                                                                  "nbformat_minor": 5}))
    for name, layout in (("mapping_no_clipping", _messy_zip), ("teleop_no_deadzone", _loose),
                         ("params_robot_mass_int", None)):
        package = _corpus(name, work / name / "package" / "hri_lab")
        upload = work / name / "upload"
        if layout is None:
            shutil.copytree(package, upload / "hri_lab")
        else:
            layout(package, upload)
        checks = sorted({expectation(name)["check"], "robot-params", "graph"})
        cases[name] = {"upload": upload, "checks": ",".join(checks)}
    _hostile_notebook(work / "params_robot_mass_int" / "upload" / NOTEBOOK)
    return cases


#: What the hostile notebook's extra cell reaches for: the course (its hidden tests), the upload, the results.
_REACHED_FOR = ("/autograder/source/course", "/autograder/submission", "/autograder/results/results.json")


def _hostile_notebook(target: Path) -> None:
    """The instructor's NOTEBOOK plus a cell that reads the autograder's course and upload and writes its results."""
    nb = json.loads((COURSE_DIR / "source" / "preparation" / NOTEBOOK).read_text())
    code = ("import os\n"
            f"for path in {_REACHED_FOR[:2]!r}:\n"
            "    try:\n        print(path, 'holds', sorted(os.listdir(path)))\n"
            "    except OSError as exc:\n        print(path, 'refused:', exc)\n"
            "try:\n"
            f"    open({_REACHED_FOR[2]!r}, 'w').write('{{\"score\": 1000, \"tests\": []}}')\n"
            "    print('results written')\n"
            "except OSError as exc:\n    print('results refused:', exc)\n")
    nb["cells"].append({"cell_type": "code", "execution_count": None, "metadata": {}, "outputs": [],
                        "source": "# reaches for the autograder\n" + code})
    target.write_text(json.dumps(nb))


@pytest.fixture(scope="module")
def graded(autograder):
    """case -> (results.json, run_autograder's seconds)."""
    folder, source, setup_s = autograder
    cases = _cases(folder / "uploads")

    def run(item):
        name, case = item
        box = folder / "boxes" / name.replace(" ", "_")
        shutil.copytree(case["upload"], box / "ag" / "submission")
        (box / "ag" / "submission_metadata.json").write_text(json.dumps({"users": [{"id": name}],
                                                                          "assignment": {"id": 1}}))
        env = {"HRI_GRADESCOPE_CHECKS": case["checks"]} if case["checks"] else {}
        started = time.monotonic()
        proc = _box(box, source, ["/autograder/source/run_autograder"], env, timeout_s=400)
        results = box / "ag" / "results" / "results.json"
        assert proc.returncode == 0 and results.is_file(), f"{name}: run_autograder failed:\n{proc.stdout}\n{proc.stderr}"
        return name, (json.loads(results.read_text()), time.monotonic() - started)

    with ThreadPoolExecutor(max_workers=2) as pool:  # the answer key and the template first: the longest
        done = dict(pool.map(run, cases.items()))
    print(f"setup.sh {setup_s:.1f} s; " + ", ".join(f"{n} {s:.1f} s" for n, (_, s) in done.items()))
    return done


#: Parts a corpus entry graded with ``node: false`` also fails here, where the node runs: the node
#: publishes the same raw sticks (a hidden-input part, so the student sees it after publishing).
_NODE_ALSO_FAILS = {"teleop_no_deadzone": {"node_twist"}}


def _failed(payload: dict) -> Dict[str, dict]:
    return {t["name"]: t for t in payload["tests"] if t["score"] < t["max_score"]}


def test_the_answer_key_gets_full_marks_with_hidden_parts_after_published(graded):
    payload, _ = graded["answer key"]
    assert not _failed(payload), json.dumps(_failed(payload), indent=1)
    # each part once: every check's parts (the files') and the uploaded notebooks' autograded cells, of
    # which Ex. 4's check cell is none
    assert payload["score"] == sum(t["max_score"] for t in payload["tests"]) == \
        sum(check_points(c) for c in CHECKS) + sum(_autograded_points()) + sum(_autograded_points(CHECK_NOTEBOOK))
    ex04 = [t["name"] for t in payload["tests"] if t["name"].startswith(f"preparation/{CHECK_NOTEBOOK}: ")]
    assert ex04 == [f"preparation/{CHECK_NOTEBOOK}: ex4_loaded", f"preparation/{CHECK_NOTEBOOK}: ex4_dumped"], ex04
    hidden = [t["name"] for t in payload["tests"] if t["visibility"] == "after_published"]
    assert any(n.startswith("mapping-node: takes the range") for n in hidden), hidden
    assert "Not judged" not in payload.get("output", "") and "found your package in hri_lab/" in payload["output"]


def test_the_template_scores_zero_and_every_part_says_what_to_do(graded):
    payload, _ = graded["template"]
    assert [t["name"] for t in payload["tests"] if t["score"]] == []
    assert payload["score"] == 0
    assert all(t["output"].strip() for t in payload["tests"] if t["max_score"] > t["score"])
    assert "Not judged" not in payload.get("output", "")


@pytest.mark.parametrize("name", ["mapping_no_clipping", "teleop_no_deadzone", "params_robot_mass_int"])
def test_a_typical_mistake_is_partial_and_fails_exactly_its_parts(graded, name):
    payload, _ = graded[name]
    exp = expectation(name)
    names = {key: f"{exp['check']}: {part}" for part, key in part_keys(exp["check"]).items()}
    failed = _failed(payload)
    wanted = {names[key] for key in set(exp["fails"]) | _NODE_ALSO_FAILS.get(name, set())}
    assert set(failed) == wanted, f"{name}: failed {sorted(failed)}, expected {sorted(wanted)}"
    for key, words in exp["fails"].items():
        assert words in failed[names[key]]["output"], f"{name}: {key} should say {words!r}"
    for key in _NODE_ALSO_FAILS.get(name, ()):
        assert failed[names[key]]["visibility"] == "after_published"
    assert 0 < payload["score"] < sum(t["max_score"] for t in payload["tests"])
    assert {t["name"].split(":")[0] for t in payload["tests"] if not t["name"].startswith("preparation/")} \
        == {exp["check"], "robot-params", "graph"}


def test_messy_uploads_are_found_and_the_student_is_told_where(graded):
    zipped, _ = graded["mapping_no_clipping"]
    assert "found your package in submission.zip/Archive/inner.zip/Lab 4/my work/hri_lab/" in zipped["output"]
    loose, _ = graded["teleop_no_deadzone"]
    assert "took scripts/teleoperation.py from teleoperation.py" in loose["output"]
    every = {t["name"]: t for t in zipped["tests"]}  # no clamp costs the clip part alone (issue 43): hidden passes
    hidden = every["mapping-node: takes the range from /max_sensor_force (hidden inputs, other values)"]
    assert hidden["visibility"] == "after_published"
    assert _failed(zipped)["mapping-node: clips counts above /max_sensor_force to 1.0 (public trace)"]["visibility"] == "visible"


def _notebook_tests(payload: dict) -> List[dict]:
    return [t for t in payload["tests"] if t["name"].startswith(f"preparation/{NOTEBOOK}: ")]


def _autograded_points(notebook: str = NOTEBOOK) -> List[float]:
    cells = json.loads((COURSE_DIR / "source" / "preparation" / notebook).read_text())["cells"]
    return [c["metadata"]["nbgrader"]["points"] for c in cells if c.get("metadata", {}).get("nbgrader", {}).get("grade")
            and not c["metadata"]["nbgrader"].get("solution")]


def test_an_answered_course_notebook_gets_full_marks_for_each_autograded_cell(graded):
    payload, _ = graded["answer key"]
    tests = _notebook_tests(payload)
    assert [t["max_score"] for t in tests] == _autograded_points() and len(tests) >= 3
    assert all(t["score"] == t["max_score"] and t["visibility"] == "visible" for t in tests), payload.get("output")
    assert f"preparation/{NOTEBOOK}: 2 more points of written answers are graded by course staff" in payload["output"]


def test_an_untouched_released_notebook_gets_zero_and_other_notebooks_are_named_and_ignored(graded):
    payload, _ = graded["template"]
    tests = _notebook_tests(payload)
    assert [t["max_score"] for t in tests] == _autograded_points()
    assert all(t["score"] == 0 and "fill them in" in t["output"] and "Error" in t["output"] for t in tests), payload.get("output")
    assert "ignored Untitled.ipynb: not notebooks of the course" in payload["output"]
    assert not [t for t in payload["tests"] if "Untitled" in t["name"]]


def test_an_uploaded_notebook_runs_in_the_sandbox_and_keeps_its_points(graded, autograder):
    """The kernel sees neither the autograder's course (hidden tests) nor the upload or results folder, and
    the notebook's answers still get full marks."""
    payload, _ = graded["params_robot_mass_int"]
    tests = _notebook_tests(payload)
    assert [t["max_score"] for t in tests] == _autograded_points()
    assert all(t["score"] == t["max_score"] for t in tests), payload.get("output")
    assert "without the sandbox" not in payload["output"]
    box_tmp = autograder[0] / "boxes" / "params_robot_mass_int" / "tmp"
    autograded = sorted(box_tmp.glob(f"hri-gradescope-*/notebooks/course/autograded/*/preparation/{NOTEBOOK}"))
    assert len(autograded) == 1, autograded
    cell = [c for c in json.loads(autograded[0].read_text())["cells"]
            if "".join(c["source"]).startswith("# reaches for the autograder")]
    printed = "".join("".join(o.get("text", "")) for o in cell[0]["outputs"])
    course, upload, results = _REACHED_FOR
    assert f"{course} refused: [Errno 2] No such file or directory" in printed, printed  # not there at all
    assert f"{upload} refused: [Errno 2] No such file or directory" in printed, printed
    assert "results refused: [Errno 2] No such file or directory" in printed, printed
