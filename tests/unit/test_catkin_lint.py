"""catkin_lint finds nothing wrong with hri_lab (issue 2: "catkin_lint is clean").

The command is the one `make lint` runs: ``catkin_lint --offline -W2 --strict hri_lab``
from the repository root. ``--offline``: never download rosdistro data (tests must not need
the network). Without a rosdep cache (``rosdep update`` never ran, as here) catkin_lint says
so on stderr and cannot check that dependency names exist; everything else -- package.xml
format, CMakeLists order, scripts installed with catkin_install_python, launch/config
installed -- is checked, and -W2 --strict turns even notices into failures.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
COMMAND = ["catkin_lint", "--offline", "-W2", "--strict"]

def lint(path: Path) -> subprocess.CompletedProcess:
    if shutil.which("catkin_lint") is None:
        pytest.fail("catkin_lint is not installed: run 'make setup' (Debian: apt package catkin-lint; "
                    "ROS Noetic: setup pip-installs it into .venv)")
    return subprocess.run([*COMMAND, str(path)], cwd=str(path.parent), capture_output=True, text=True,
                          timeout=120)


def test_hri_lab_is_clean_even_of_notices():
    result = lint(REPO / "hri_lab")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "found 0 problems" in result.stderr, result.stderr


def test_catkin_lint_would_catch_a_script_left_out_of_catkin_install_python(tmp_path):
    # Guards the guard: a new node script not added to CMakeLists.txt is an error.
    copy = tmp_path / "hri_lab"
    shutil.copytree(REPO / "hri_lab", copy)
    extra = copy / "scripts" / "new_node.py"
    extra.write_text("#!/usr/bin/env python3\n")
    extra.chmod(0o755)
    result = lint(copy)
    assert result.returncode != 0
    assert "new_node.py" in result.stdout + result.stderr
