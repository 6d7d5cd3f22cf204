"""Everything that runs in the lab must run on the lab PCs' Python 3.8 (ROS Noetic, Ubuntu 20.04)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
LAB_CODE = [REPO / "hri_teleop", REPO / "hri_lab" / "scripts", REPO / "solutions" / "hri_lab" / "scripts"]


def _vermin() -> str:
    exe = Path(sys.executable).with_name("vermin")
    if exe.exists():
        return str(exe)
    found = shutil.which("vermin")
    if not found:
        pytest.fail("vermin not installed: run 'make setup' (it installs the test extras)")
    return found


def test_lab_code_needs_at_most_python_3_8():
    targets = [str(p) for p in LAB_CODE if p.exists()]
    proc = subprocess.run(
        [_vermin(), "--target=3.8-", "--violations", "--no-tips", "--no-parse-comments", *targets],
        capture_output=True, text=True,
    )
    assert proc.returncode == 0, "code that Python 3.8 cannot run:\n" + proc.stdout + proc.stderr


def test_vermin_catches_a_python_3_10_construct(tmp_path):
    """Guard against a vermin invocation that passes everything."""
    bad = tmp_path / "bad.py"
    bad.write_text("def f(x):\n    match x:\n        case 1:\n            return 2\n")
    proc = subprocess.run([_vermin(), "--target=3.8-", "--violations", "--no-tips", str(bad)],
                          capture_output=True, text=True)
    assert proc.returncode != 0


# The ROS-free core's own tests; the rest need rospy, roslaunch or catkin_lint from the system.
CORE_TESTS = ["test_fsr.py", "test_mapping.py", "test_limits.py", "test_teleop.py", "test_config.py",
              "test_sensor_profile.py", "test_gripper.py", "test_traces.py", "test_gamepad_deadzone.py",
              "test_gamepad_layout.py", "test_gamepad_state.py", "test_gamepad_virtual.py",
              "test_gamepad_pygame.py", "test_gamepad_rumble.py", "test_sim_arm.py", "test_sim_hand_physics.py",
              "test_sim_hand_goals.py",
              "test_sim_config.py", "test_sim_board.py", "test_sim_world.py", "test_sim_lab.py",
              "test_serial_protocol.py", "test_calibrate.py", "test_simavr_board.py",
              "test_gamepad_events.py", "test_grading_templates.py", "test_grading_cases.py",
              "test_grading_results.py", "test_grading_compare.py",
              "test_experiment.py", "test_experiment_stats.py", "test_paramfile.py",
              "test_experiment_tlx.py", "test_experiment_analysis.py", "test_bench_stats.py",
              "test_checks_counts.py", "test_gamepad_browser.py", "test_gamepad_identify.py", "test_gamepad_stale.py",
              "test_teleop_precision_motors.py", "test_rosserial_frames.py", "test_rosserial_board.py",
              "test_student_old_paths.py"]


@pytest.mark.skipif(not (REPO / ".venv38" / "bin" / "python").exists(),
                    reason="no Python 3.8 on this machine (tools/setup.sh builds .venv38 where it finds one)")
def test_core_unit_tests_pass_on_python_3_8():
    py38 = REPO / ".venv38" / "bin" / "python"
    version = subprocess.run([str(py38), "-c", "import sys; print(sys.version_info[:2])"],
                             capture_output=True, text=True).stdout.strip()
    assert version == "(3, 8)", version
    here = Path(__file__).parent
    proc = subprocess.run([str(py38), "-m", "pytest", "-q", "-p", "no:cacheprovider", "-x",
                           *[str(here / name) for name in CORE_TESTS]],
                          cwd=str(REPO), capture_output=True, text=True,
                          env=dict(os.environ, HRI_TEST_COMPAT="1"),  # 10 examples per property (conftest)
                          timeout=1800)  # a hang guard: ~2 min of CPU, 6 min of wall on a busy 2-core machine
    assert proc.returncode == 0, "on Python 3.8:\n" + proc.stdout[-3000:] + proc.stderr[-2000:]
