"""The grader trusts nothing it is handed: hostile files graded by make grade's files-only mode.

Each submission below attacks how the grader reads what it is handed, not the code it runs: a
deliverable that is a link (to the answer key, to another student's file, to a secret of the
machine), ``hri_lab`` itself a link to another student's package, a FIFO, a link to an endless
/proc file, a YAML alias bomb, rosparam's eval-based ``!radians`` tag, and a module in the
submission that stands in for the grader's probe. All are graded in one ``hri-grade batch`` (what
``make grade DIR=...`` runs on a folder of packages) beside an honest submission that writes
rosparam's honest ``!radians`` too. Each attack gains no point, nothing of a target or secret
reaches any output file, the batch ends with every student graded, and the honest one keeps
full marks. ``hri-grade CHECK FILE`` (the single-file form) refuses the same links.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Dict, Iterator, List, NamedTuple

import pytest
from grading_helpers import SOLUTIONS, answer_text, grader_env, hri_grade, open_folder, write_package

pytestmark = pytest.mark.ros

CHECKS = "robot-params,graph,catkin-package"
FULL = {"robot-params": 10.0, "graph": 9.0, "catkin-package": 4.0}
SECRET = "SECRET-hostile-inputs-91c4e7"
#: Every deliverable these checks read, at its handout place.
DELIVERABLES = ["config/robot_params.yaml", "graph.yaml", "scripts/teleoperation.py", "scripts/gripper_manager.py",
                "CMakeLists.txt"]
#: What each check's result would be if a forged probe result were believed: Table 1, exactly.
FORGED_PARAMS = json.dumps({"ok": True, "error": "", "params": {
    "robot_name": "FER", "robot_number": 1, "robot_mass": 18.0, "load_gripper": True,
    "mixed_list": ["text", 1.0, 1], "gains": {"p": 10.0, "i": 1.0, "d": 5.0}}})

ALIAS_BOMB = "a: &a [" + ", ".join(["lol"] * 9) + "]\n" + "".join(
    f"{c}: &{c} [" + ", ".join([f"*{p}"] * 9) + "]\n" for p, c in zip("abcdefgh", "bcdefghi"))

# rosparam evaluates !radians with eval after replacing "pi" by "math.pi": this payload has no "pi".
# At the probe's exit it writes Table 1 over the probe's result (argv's last word is the result's path).
RADIANS_EVAL = ("robot_name: 1\n"
                "angle: !radians |-\n"
                "  __import__('atexit').register(lambda: open(__import__('sys').argv[-1], 'w').write("
                + repr(FORGED_PARAMS) + "))\n")

SHADOW_PROBE = ("import sys\n"
                f"open(sys.argv[-1], 'w').write({FORGED_PARAMS!r})\n")


def _honest() -> Dict[str, str]:
    files = {relative: answer_text(relative) for relative in DELIVERABLES}
    files["config/robot_params.yaml"] += "angle: !radians pi/2   # rosparam's honest tag\nturn: deg(180)\n"
    return files


def _link(path: Path, target: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.exists() or path.is_symlink():
        path.unlink()
    path.symlink_to(target)


def _submissions(root: Path, secret: Path) -> Dict[str, str]:
    """The batch's submissions; name -> a word each one's feedback must hold."""
    write_package(root / "good" / "hri_lab", _honest())
    words: Dict[str, str] = {}
    wrong = {"config/robot_params.yaml": "robot_name: [\n", "graph.yaml": "nodes: [\n",
             "CMakeLists.txt": "project(hri_lab)\n"}

    # the answer key's files, linked
    write_package(root / "link_to_key" / "hri_lab", {})
    for relative in DELIVERABLES:
        _link(root / "link_to_key" / "hri_lab" / relative, str(SOLUTIONS / relative))
    words["link_to_key"] = "is a link; hand in the file itself"

    # another student's files, linked (relative links, as a zip would carry them)
    write_package(root / "link_to_other" / "hri_lab", {})
    for relative in DELIVERABLES:
        depth = len(Path(relative).parts) + 1
        _link(root / "link_to_other" / "hri_lab" / relative, "../" * depth + f"good/hri_lab/{relative}")
    words["link_to_other"] = "is a link; hand in the file itself"

    # a secret of the machine (mode 0600, the grader runs as root) and /etc/shadow
    write_package(root / "link_to_secret" / "hri_lab", {})
    _link(root / "link_to_secret" / "hri_lab" / "config" / "robot_params.yaml", str(secret))
    _link(root / "link_to_secret" / "hri_lab" / "graph.yaml", "/etc/shadow")
    _link(root / "link_to_secret" / "hri_lab" / "CMakeLists.txt", str(secret))
    words["link_to_secret"] = "is a link; hand in the file itself"

    # hri_lab itself a link to another student's package
    (root / "package_link").mkdir()
    _link(root / "package_link" / "hri_lab", str(root / "good" / "hri_lab"))
    words["package_link"] = "hri_lab is a link; hand in the folder itself"

    # FIFOs: a reader blocks until someone writes, for ever here
    write_package(root / "fifo" / "hri_lab", {})
    for relative in ("config/robot_params.yaml", "graph.yaml", "CMakeLists.txt"):
        (root / "fifo" / "hri_lab" / relative).parent.mkdir(parents=True, exist_ok=True)
        os.mkfifo(root / "fifo" / "hri_lab" / relative)
    words["fifo"] = "is a FIFO, not a regular file"

    # /proc/self/pagemap: endless (the root grader copied 1.1 GB of it in 2.6 s and went on)
    write_package(root / "pagemap" / "hri_lab", {})
    for relative in ("config/robot_params.yaml", "graph.yaml", "CMakeLists.txt"):
        _link(root / "pagemap" / "hri_lab" / relative, "/proc/self/pagemap")
    words["pagemap"] = "is a link; hand in the file itself"

    # a YAML alias bomb as graph.yaml and as robot_params.yaml
    write_package(root / "alias_bomb" / "hri_lab", dict(wrong, **{"config/robot_params.yaml": ALIAS_BOMB,
                                                               "graph.yaml": ALIAS_BOMB}))
    words["alias_bomb"] = "expands to more than"

    # rosparam's !radians runs eval: the payload rewrites the probe's result at exit
    write_package(root / "radians_eval" / "hri_lab", dict(wrong, **{"config/robot_params.yaml": RADIANS_EVAL}))
    words["radians_eval"] = "invalid radian expression"

    # a module of the submission in place of the grader's probe (started with -m from the student's folder)
    shadow = dict(wrong)
    for package in ("hri_teleop", "hri_teleop/grading", "hri_teleop/grading/run"):
        shadow[f"{package}/__init__.py"] = ""
    shadow["hri_teleop/grading/run/probe.py"] = SHADOW_PROBE
    write_package(root / "shadow_probe" / "hri_lab", shadow)
    words["shadow_probe"] = "robot_params.yaml"
    return words


@pytest.fixture(scope="module")
def secret() -> Iterator[Path]:
    """A file only root may read, outside every submission."""
    for folder in open_folder("hri-hostile-inputs-secret-"):
        path = folder / "secret.txt"
        path.write_text(f"{SECRET}\n")
        path.chmod(0o600)
        yield path


def _grades(out: Path) -> Dict[str, Dict[str, str]]:
    with open(out / "grades.csv") as fh:
        return {row["student"]: row for row in csv.DictReader(fh)}


def _leaks(out: Path, needles: List[str]) -> List[str]:
    """Output files holding any of ``needles`` (read as bytes, links not followed)."""
    found = []
    for folder, _dirs, files in os.walk(out):
        for name in files:
            path = Path(folder) / name
            if path.is_symlink() or not path.is_file():
                continue
            data = path.read_bytes()
            found += [f"{path}: {needle}" for needle in needles if needle.encode() in data]
    return found


def _shadow_line() -> List[str]:
    """/etc/shadow's first line, when this test can read it (it is root's), to look for in the outputs."""
    try:
        first = Path("/etc/shadow").read_text().splitlines()[0]
    except (OSError, IndexError):
        return []
    return [first] if len(first) > 8 else []


class Batch(NamedTuple):
    out: Path
    words: Dict[str, str]
    grades: Dict[str, Dict[str, str]]
    output: str


@pytest.fixture(scope="module")
def batch(tmp_path_factory, secret) -> Batch:
    """Every submission graded once, two at a time, by ``hri-grade batch`` (make grade's files-only mode)."""
    root = tmp_path_factory.mktemp("hostile-inputs")
    words = _submissions(root / "submitted", secret)
    out = root / "grades"
    proc = hri_grade("batch", str(root / "submitted"), "--out", str(out), "--jobs", "2", "--checks", CHECKS,
                     "--timeout", "240", timeout=900)
    grades = _grades(out) if (out / "grades.csv").is_file() else {}
    return Batch(out, words, grades, proc.stdout[-3000:] + proc.stderr[-3000:])


ATTACKS = ["link_to_key", "link_to_other", "link_to_secret", "package_link", "fifo", "pagemap", "alias_bomb",
           "radians_eval", "shadow_probe"]


@pytest.mark.parametrize("name", ATTACKS)
def test_a_hostile_submission_is_graded_gains_no_point_and_is_told_why(batch: Batch, name: str) -> None:
    assert set(batch.words) == set(ATTACKS)
    row = batch.grades.get(name)
    assert row is not None and row["status"] == "graded", f"{name}: {row}\n{batch.output}"
    feedback = (batch.out / name / "feedback.txt").read_text()
    assert float(row["score"]) == 0, f"{name} gained points:\n{feedback}"
    assert batch.words[name] in feedback, f"{name}: {batch.words[name]!r} not in\n{feedback}"
    assert _leaks(batch.out / name, [SECRET, *_shadow_line()]) == []
    sizes = {str(p): p.stat().st_size for p in (batch.out / name).rglob("*") if p.is_file() and not p.is_symlink()}
    assert max(sizes.values()) < 5_000_000, sorted(sizes.items(), key=lambda kv: -kv[1])[:3]


def test_the_honest_submission_beside_them_keeps_full_marks_and_nothing_leaks_anywhere(batch: Batch) -> None:
    assert batch.grades, batch.output
    good = batch.grades["good"]
    assert good["status"] == "graded", batch.output
    assert float(good["score"]) == float(good["max_score"]) == sum(FULL.values()), \
        (batch.out / "good" / "feedback.txt").read_text()
    assert _leaks(batch.out, [SECRET, *_shadow_line()]) == []


@pytest.mark.parametrize("check,relative", [("robot-params", "config/robot_params.yaml"), ("graph", "graph.yaml"),
                                            ("catkin-package", "CMakeLists.txt")])
def test_the_single_file_form_refuses_a_link_to_the_answer_key_or_a_secret(tmp_path, secret, check, relative):
    for target in (str(SOLUTIONS / relative), str(secret)):
        link = tmp_path / target.replace("/", "_") / "hri_lab" / relative
        _link(link, target)
        proc = hri_grade(check, str(link), "--json", timeout=300)
        assert proc.returncode in (0, 1), proc.stdout + proc.stderr
        result = json.loads(proc.stdout)
        assert result["score"] == 0, proc.stdout
        assert "is a link" in proc.stdout, proc.stdout
        assert SECRET not in proc.stdout + proc.stderr


def test_the_single_file_form_refuses_a_fifo_without_waiting_for_a_writer(tmp_path):
    fifo = tmp_path / "hri_lab" / "config" / "robot_params.yaml"
    fifo.parent.mkdir(parents=True)
    os.mkfifo(fifo)
    proc = hri_grade("robot-params", str(fifo), "--json", timeout=300, env=grader_env())
    assert json.loads(proc.stdout)["score"] == 0
    assert "is a FIFO, not a regular file" in proc.stdout
