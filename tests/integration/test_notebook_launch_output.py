"""What a notebook cell prints of a launch it started: roslaunch's own lines, without terminal escapes."""

from __future__ import annotations

from pathlib import Path

import pytest

from hri_teleop.course import lab

REPO = Path(__file__).resolve().parents[2]
ANSWER_KEY = REPO / "solutions" / "hri_lab"

pytestmark = pytest.mark.ros


def test_a_launchs_output_in_a_notebook_has_no_terminal_title_escapes(ros_master, monkeypatch):
    for key, value in ros_master.env.items():
        monkeypatch.setenv(key, value)
    for key in ("HRI_MODE", "NBGRADER_EXECUTION"):
        monkeypatch.delenv(key, raising=False)
    try:
        launch = lab.launch_student("sensor.launch", package=ANSWER_KEY)
        assert lab.wait_for_publisher("/force_mapped", launch, timeout_s=60), launch.output()
        output = launch.output()
        assert "started roslaunch server" in output or "process[" in output, output
        assert "\x1b]" not in output and "\x07" not in output, repr(output[:300])
    finally:
        lab.stop()
