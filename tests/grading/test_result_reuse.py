"""make grade's files job stores each check result; a notebook's check cell of the very same
package (same files, same seed) takes it instead of running the check again
(hri_teleop.grading.judge.reuse). Anything different runs the check."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from hri_teleop.grading.exercises.robot_params import grade_robot_params
from hri_teleop.grading.judge import reuse
from hri_teleop.grading.results import CheckResult, Part

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def package(tmp_path):
    root = tmp_path / "alice" / "preparation" / "hri_lab"
    (root / "config").mkdir(parents=True)
    shutil.copy(REPO / "solutions" / "hri_lab" / "config" / "robot_params.yaml", root / "config")
    (root / "scripts").mkdir()
    (root / "scripts" / "mapping_node.py").write_text("# mine\n")
    return root


def _forged(root: Path) -> CheckResult:
    return CheckResult("robot-params", str(root / "config" / "robot_params.yaml"),
                       [Part("stored part", 3.0, True)], None, 1.5)


def test_a_stored_result_comes_back_for_the_same_files_re_rooted_and_with_a_note(package, tmp_path):
    store = tmp_path / "results"
    reuse.store(store, "robot-params", 7, package, _forged(package))
    copy = tmp_path / "autograded" / "alice" / "preparation" / "hri_lab"
    shutil.copytree(package, copy)
    found = reuse.load(store, "robot-params", 7, copy)
    assert found is not None and [p.name for p in found.parts] == ["stored part"]
    assert found.target == str(copy / "config" / "robot_params.yaml")
    assert found.notes[-1] == reuse.REUSED_NOTE


@pytest.mark.parametrize("change", ["edit a deliverable", "edit another file", "add a file", "other seed",
                                    "other check"])
def test_anything_different_finds_nothing(package, tmp_path, change):
    store = tmp_path / "results"
    reuse.store(store, "robot-params", 7, package, _forged(package))
    seed, check = 7, "robot-params"
    if change == "edit a deliverable":
        (package / "config" / "robot_params.yaml").write_text("robot_name: FER\n")
    elif change == "edit another file":
        (package / "scripts" / "mapping_node.py").write_text("# mine, changed\n")
    elif change == "add a file":
        (package / "config" / "extra.yaml").write_text("a: 1\n")
    elif change == "other seed":
        seed = 8
    else:
        check = "mapping-node"
    assert reuse.load(store, check, seed, package) is None


def test_caches_and_hidden_folders_do_not_change_the_digest(package):
    before = reuse.package_digest(package)
    (package / "scripts" / "__pycache__").mkdir()
    (package / "scripts" / "__pycache__" / "x.pyc").write_bytes(b"\0")
    (package / ".ros").mkdir()
    (package / ".ros" / "log.txt").write_text("log")
    assert reuse.package_digest(package) == before


def test_a_notebook_takes_the_stored_result_and_the_files_job_never_does(package, tmp_path, monkeypatch):
    """The reader gets what is stored (here forged, to tell it apart); the writer runs the real check
    and overwrites it (a notebook kernel runs student code: the files job trusts nothing it finds)."""
    store = tmp_path / "results"
    from hri_teleop.grading.cases.inputs import seed_for

    reuse.store(store, "robot-params", seed_for(package), package, _forged(package))
    monkeypatch.setenv(reuse.READ_ENV, str(store))
    assert [p.name for p in grade_robot_params(package).parts] == ["stored part"]
    assert [p.name for p in grade_robot_params(package, seed=seed_for(package) + 1).parts] != ["stored part"]

    monkeypatch.delenv(reuse.READ_ENV)
    monkeypatch.setenv(reuse.WRITE_ENV, str(store))
    real = grade_robot_params(package)
    assert real.score == real.max_score == 10 and reuse.REUSED_NOTE not in real.notes
    assert reuse.load(store, "robot-params", seed_for(package), package).score == 10  # overwritten


def test_a_single_file_or_without_make_grade_always_runs_the_check(package, tmp_path, monkeypatch):
    store = tmp_path / "results"
    from hri_teleop.grading.cases.inputs import seed_for

    reuse.store(store, "robot-params", seed_for(package), package, _forged(package))
    assert grade_robot_params(package).score == 10  # no variable set: nothing read
    monkeypatch.setenv(reuse.READ_ENV, str(store))
    assert grade_robot_params(package / "config" / "robot_params.yaml").score == 10
