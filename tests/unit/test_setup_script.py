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
