"""tools/setup.sh, which `make setup` (and so `make demo` and `make test`) runs first."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SETUP = REPO / "tools" / "setup.sh"


def _run(**env_extra):
    env = dict(os.environ, **env_extra)
    return subprocess.run(["bash", str(SETUP)], cwd=REPO, env=env, capture_output=True, text=True, timeout=600)


@pytest.mark.skipif(Path("/opt/ros/noetic/setup.sh").exists(), reason="with ROS Noetic, setup installs nothing from apt")
def test_without_root_it_prints_the_exact_apt_command_and_fails():
    proc = _run(HRI_SETUP_APT_PACKAGES="ros-core hri-teleop-no-such-package", HRI_SETUP_PRETEND_UID="1000")
    assert proc.returncode != 0
    assert "sudo apt-get update && sudo apt-get install -y hri-teleop-no-such-package" in proc.stderr
    assert "ros-core" not in proc.stderr.split("install -y", 1)[1], "an installed package was listed as missing"


def test_a_second_run_only_checks():
    """Nothing installed, nothing built the second time: only checks (their time: make bench, "make setup,
    nothing missing")."""
    first = _run()
    assert first.returncode == 0, first.stderr
    second = _run()
    assert second.returncode == 0, second.stderr
    said = second.stdout + second.stderr
    assert "installing" not in said and "creating" not in said, said


def test_in_an_active_conda_environment_with_rospy_it_uses_its_python_and_installs_nothing_from_apt(tmp_path):
    """environment.yml's route: no apt; a package missing from apt would fail the apt path."""
    (tmp_path / "bin").mkdir()
    (tmp_path / "bin" / "python").symlink_to("/usr/bin/python3")  # Debian's, which has rospy
    proc = _run(CONDA_PREFIX=str(tmp_path), HRI_SETUP_APT_PACKAGES="hri-teleop-no-such-package",
                HRI_SETUP_PRETEND_UID="1000")
    assert proc.returncode == 0, proc.stderr
    assert f"using ROS from the conda environment {tmp_path}" in proc.stdout
    assert "apt-get" not in proc.stdout + proc.stderr


def test_a_conda_environment_without_rospy_is_not_taken_for_ros(tmp_path):
    (tmp_path / "bin").mkdir()
    fake = tmp_path / "bin" / "python"
    fake.write_text("#!/bin/sh\nexit 1\n")
    fake.chmod(0o755)
    proc = _run(CONDA_PREFIX=str(tmp_path), HRI_SETUP_APT_PACKAGES="hri-teleop-no-such-package",
                HRI_SETUP_PRETEND_UID="1000")
    assert "conda environment" not in proc.stdout
    if not Path("/opt/ros/noetic/setup.sh").exists():
        assert proc.returncode != 0 and "install -y hri-teleop-no-such-package" in proc.stderr
