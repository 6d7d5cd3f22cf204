"""`roslaunch --files` (the tool itself, no master needed) resolves both launch files."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
import yaml

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


def _params(args, ros_env):
    proc = subprocess.run(["roslaunch", "--dump-params", "hri_lab", "teleoperation.launch", *args],
                          env=ros_env, capture_output=True, text=True, timeout=60)
    return proc


@pytest.mark.parametrize("args, node, baud", [
    (["robot:=false"], "serial_node", 57600),                                  # the handout's rosserial sketch
    (["robot:=false", "board:=serial"], "serial_bridge", 115200),              # firmware/fsr_serial
    (["robot:=false", "board:=serial", "baud:=9600"], "serial_bridge", 9600),
])
def test_the_board_argument_picks_rosserial_or_the_serial_bridge_with_its_own_baud(args, node, baud, ros_env):
    proc = _params(args, ros_env)
    assert proc.returncode == 0, proc.stderr
    params = yaml.safe_load(proc.stdout)
    assert params[f"/{node}/baud"] == baud and params[f"/{node}/port"] == "/dev/ttyACM0"
    other = "serial_bridge" if node == "serial_node" else "serial_node"
    assert not any(key.startswith(f"/{other}/") for key in params)


def test_an_unknown_board_is_refused_naming_the_choices(ros_env):
    # (--dump-params exits 0 even when loading fails; roslaunch itself stops with this line)
    proc = _params(["robot:=false", "board:=usb"], ros_env)
    assert "Unable to load file" in proc.stdout + proc.stderr
    assert "board_argument_must_be_rosserial_or_serial" in proc.stdout + proc.stderr


def test_sim_true_replaces_robot_and_board_with_lab_sim_and_plays_the_default_scenario(ros_env):
    proc = _params(["sim:=true"], ros_env)
    assert proc.returncode == 0, proc.stderr
    params = yaml.safe_load(proc.stdout)
    assert params["/teleoperation/pad"] == "virtual"
    assert params["/teleoperation/pad_script"] == str(REPO / "hri_lab" / "scenarios" / "default.yaml")
    assert params["/lab_sim/scenario"] == params["/teleoperation/pad_script"]
    assert not any(k.startswith(("/serial_node/", "/serial_bridge/", "/FSR_sensor/")) for k in params)
    real_pad = yaml.safe_load(_params(["sim:=true", "pad:=pygame"], ros_env).stdout)
    assert real_pad["/teleoperation/pad"] == "pygame" and real_pad["/teleoperation/pad_script"] == ""
