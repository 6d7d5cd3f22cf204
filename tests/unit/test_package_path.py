"""hri_lab on ROS_PACKAGE_PATH as the package folder itself: a copy elsewhere in the repository
(make grade's and make bench's courses under out/) never shadows the lab's."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from hri_teleop.ros.master import finds_hri_lab, lab_shell_env

REPO = Path(__file__).resolve().parents[2]
PACKAGE_XML = (REPO / "hri_lab" / "package.xml").read_text()


def _package(folder: Path) -> Path:
    folder.mkdir(parents=True)
    (folder / "package.xml").write_text(PACKAGE_XML)
    return folder


@pytest.mark.skipif(shutil.which("rospack") is None, reason="needs rospack (make setup)")
def test_a_copy_of_hri_lab_under_out_does_not_shadow_the_labs(tmp_path):
    lab = _package(tmp_path / "repo" / "hri_lab")
    for i in range(5):  # rospack's search order among subfolders is the file system's
        _package(tmp_path / "repo" / "out" / f"course{i}" / "hri_lab")
    env = lab_shell_env(base={"PATH": "/usr/bin:/bin", "ROS_HOME": str(tmp_path / "ros")},
                        package_root=tmp_path / "repo")
    assert env["ROS_PACKAGE_PATH"].split(":")[0] == str(lab)
    found = subprocess.run(["rospack", "find", "hri_lab"], env=env, capture_output=True, text=True, timeout=30)
    assert found.stdout.strip() == str(lab), found.stderr


def test_an_older_shells_repository_entry_is_replaced_by_the_package_folder(tmp_path):
    lab = _package(tmp_path / "repo" / "hri_lab")
    env = lab_shell_env(base={"ROS_PACKAGE_PATH": f"{tmp_path / 'repo'}:/opt/other"}, package_root=tmp_path / "repo")
    assert env["ROS_PACKAGE_PATH"].split(":")[:2] == [str(lab), "/opt/other"]


def test_entries_that_find_hri_lab_directly_are_recognised(tmp_path):
    lab = _package(tmp_path / "a" / "hri_lab")
    other = _package(tmp_path / "b" / "other_pkg")
    assert finds_hri_lab(str(lab)) and finds_hri_lab(str(lab.parent))
    assert not finds_hri_lab(str(other)) and not finds_hri_lab(str(tmp_path))
