"""`roslaunch --files` (the tool itself, no master needed) resolves both launch files."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("launch_file, args", [
    ("sensor.launch", []),
    ("sensor.launch", ["load_robot_params:=true"]),
    ("teleoperation.launch", ["robot:=false", "arduino:=false", "pad:=virtual"]),
    ("teleoperation.launch", ["robot:=false"]),
])
def test_roslaunch_files_resolves_the_launch_file_and_its_includes(launch_file, args, ros_env):
    proc = subprocess.run(["roslaunch", "--files", "hri_lab", launch_file, *args], env=ros_env,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    files = {Path(line.strip()) for line in proc.stdout.splitlines() if line.strip()}
    assert REPO / "hri_lab" / "launch" / launch_file in files
