"""hri_lab's launch files, parsed in-process by roslaunch's own loader (no master needed).

What a student (and the lab PC) gets from each combination of arguments: which nodes,
which parameters, and that the robot's launch file is included only with robot:=true.
"""

from __future__ import annotations

from pathlib import Path
from typing import Dict, List, Sequence

import pytest

pytest.importorskip("roslaunch", reason="needs ROS 1's roslaunch (run 'make setup')")
import roslaunch.config
import roslaunch.core
import roslaunch.substitution_args
import roslaunch.xmlloader
import yaml

REPO = Path(__file__).resolve().parents[2]
LAUNCH = REPO / "hri_lab" / "launch"
SCRIPTS = REPO / "hri_lab" / "scripts"
CONFIG = REPO / "hri_lab" / "config"


@pytest.fixture(autouse=True)
def _package_path(monkeypatch, tmp_path):
    """hri_lab (and a stand-in franka_control, see below) findable with $(find ...)."""
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"{REPO / 'hri_lab'}:/usr/share")
    monkeypatch.setenv("ROS_HOME", str(tmp_path / "ros_home"))


def load(name: str, args: Sequence[str] = ()) -> roslaunch.config.ROSLaunchConfig:
    # $(find) keeps one module-level RosPack: drop it so this test's ROS_PACKAGE_PATH counts.
    roslaunch.substitution_args._rospack = None
    config = roslaunch.config.ROSLaunchConfig()
    loader = roslaunch.xmlloader.XmlLoader(resolve_anon=False)
    loader.load(str(LAUNCH / name), config, argv=["roslaunch", *args], verbose=False)
    return config


def nodes(config) -> Dict[str, roslaunch.core.Node]:
    return {n.namespace + n.name: n for n in config.nodes}


def params(config) -> Dict[str, object]:
    return {k: p.value for k, p in config.params.items()}


def no_hardware(*extra: str) -> List[str]:
    return ["robot:=false", "arduino:=false", *extra]


# -- sensor.launch (Ex. 6, 7) -------------------------------------------------------


def test_sensor_launch_starts_the_simulated_sensor_and_the_mapping_node():
    config = load("sensor.launch")
    found = nodes(config)
    assert set(found) == {"/FSR_sensor", "/mapping_node"}
    assert (found["/FSR_sensor"].package, found["/FSR_sensor"].type) == ("hri_lab", "FSR_sensor.py")
    assert (found["/mapping_node"].package, found["/mapping_node"].type) == ("hri_lab", "mapping_node.py")


def test_sensor_launch_sets_max_sensor_force_as_an_int_of_700_by_default():
    values = params(load("sensor.launch"))
    assert values["/max_sensor_force"] == 700 and type(values["/max_sensor_force"]) is int
    assert values["/FSR_sensor/rate_hz"] == 10


def test_sensor_launch_arguments_reach_the_parameters():
    values = params(load("sensor.launch", ["max_sensor_force:=650", "rate_hz:=50", "max_value:=700"]))
    assert values["/max_sensor_force"] == 650
    assert values["/FSR_sensor/rate_hz"] == 50
    assert values["/FSR_sensor/max_value"] == 700


def test_sensor_launch_hands_a_bad_max_sensor_force_to_the_node_unparsed():
    # roslaunch must not choke on it: mapping_node names the parameter and the fix.
    assert params(load("sensor.launch", ["max_sensor_force:=abc"]))["/max_sensor_force"] == "abc"


def test_robot_params_of_ex_7_are_loaded_only_on_request():
    assert "/robot_name" not in params(load("sensor.launch"))
    values = params(load("sensor.launch", ["load_robot_params:=true"]))
    expected = yaml.safe_load((CONFIG / "robot_params.yaml").read_text())
    assert values["/robot_name"] == "FER"
    assert values["/robot_number"] == 1 and type(values["/robot_number"]) is int
    assert values["/robot_mass"] == 18.0 and type(values["/robot_mass"]) is float
    assert values["/load_gripper"] is True
    assert values["/mixed_list"] == ["text", 1.0, 1]
    assert [type(v) for v in values["/mixed_list"]] == [str, float, int]
    assert (values["/gains/p"], values["/gains/i"], values["/gains/d"]) == (10.0, 1.0, 5.0)
    assert set(expected) == {"robot_name", "robot_number", "robot_mass", "load_gripper", "mixed_list", "gains"}


# -- teleoperation.launch (Ex. 12, 13) ------------------------------------------------


def test_no_hardware_runs_the_simulated_sensor_and_no_serial_node():
    found = nodes(load("teleoperation.launch", no_hardware()))
    assert set(found) == {"/FSR_sensor", "/mapping_node", "/gripper_manager", "/teleoperation"}
    assert found["/teleoperation"].required, "quitting teleoperation (square) must end the launch"


def test_with_the_arduino_rosserial_reads_the_given_port():
    config = load("teleoperation.launch", ["robot:=false", "port:=/dev/ttyACM1"])
    found = nodes(config)
    assert set(found) == {"/serial_node", "/mapping_node", "/gripper_manager", "/teleoperation"}
    assert (found["/serial_node"].package, found["/serial_node"].type) == ("rosserial_python", "serial_node.py")
    values = params(config)
    assert values["/serial_node/port"] == "/dev/ttyACM1"
    assert values["/serial_node/baud"] == 57600
    assert params(load("teleoperation.launch", ["robot:=false"]))["/serial_node/port"] == "/dev/ttyACM0"


def test_teleoperation_launch_sets_max_sensor_force():
    assert params(load("teleoperation.launch", no_hardware()))["/max_sensor_force"] == 700
    assert params(load("teleoperation.launch", no_hardware("max_sensor_force:=690")))["/max_sensor_force"] == 690


def test_teleoperation_reads_teleop_yaml_and_only_given_arguments_override_it():
    values = params(load("teleoperation.launch", no_hardware()))
    assert values["/teleoperation/config"] == str(CONFIG / "teleop.yaml")
    assert values["/teleoperation/pad_script"] == ""
    for key in ("pad", "layout", "twist_topic"):  # empty argument: teleop.yaml decides
        assert f"/teleoperation/{key}" not in values
    values = params(load("teleoperation.launch", no_hardware(
        "pad:=virtual", "layout:=xbox", "twist_topic:=/my_controller/cmd_vel", "pad_script:=/tmp/s.yaml")))
    assert values["/teleoperation/pad"] == "virtual"
    assert values["/teleoperation/layout"] == "xbox"
    assert values["/teleoperation/twist_topic"] == "/my_controller/cmd_vel"
    assert values["/teleoperation/pad_script"] == "/tmp/s.yaml"


def test_teleop_yaml_the_launch_points_to_is_a_valid_config():
    from hri_teleop.core.config import load_teleop_config

    config = load_teleop_config(CONFIG / "teleop.yaml")
    assert config.twist_topic == "/cartesian_velocity_controller/cmd_vel"
    assert config.pad == "pygame"


def test_nodes_start_with_a_clean_private_namespace():
    config = load("teleoperation.launch", no_hardware())
    assert set(config.clear_params) >= {"/teleoperation/", "/gripper_manager/", "/mapping_node/", "/FSR_sensor/"}


def _fake_franka_control(root: Path, with_robot_ip_arg: bool) -> None:
    """A stand-in for franka_control: the include must pass robot_ip only when given."""
    pkg = root / "franka_control"
    (pkg / "launch").mkdir(parents=True)
    (pkg / "package.xml").write_text(
        '<?xml version="1.0"?><package format="2"><name>franka_control</name><version>0.0.0</version>'
        "<description>stand-in</description><maintainer email='a@b.c'>x</maintainer>"
        "<license>BSD</license></package>")
    arg = '<arg name="robot_ip" default="172.16.0.2"/>' if with_robot_ip_arg else ""
    param = '<param name="robot_ip" value="$(arg robot_ip)"/>' if with_robot_ip_arg else ""
    (pkg / "launch" / "franka_control_cartesian_velocity.launch").write_text(
        f'<launch>{arg}<node name="franka_control" pkg="franka_control" type="franka_control_node">'
        f"{param}</node></launch>")


def test_robot_true_includes_franka_control_cartesian_velocity(monkeypatch, tmp_path):
    _fake_franka_control(tmp_path, with_robot_ip_arg=True)
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"{REPO / 'hri_lab'}:{tmp_path}:/usr/share")
    config = load("teleoperation.launch", ["arduino:=false"])
    assert "/franka_control" in nodes(config)
    assert params(config)["/franka_control/robot_ip"] == "172.16.0.2"  # that file's own default
    config = load("teleoperation.launch", ["arduino:=false", "robot_ip:=10.0.0.7"])
    assert params(config)["/franka_control/robot_ip"] == "10.0.0.7"


def test_robot_ip_is_not_forced_on_a_file_that_does_not_declare_it(monkeypatch, tmp_path):
    _fake_franka_control(tmp_path, with_robot_ip_arg=False)
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"{REPO / 'hri_lab'}:{tmp_path}:/usr/share")
    assert "/franka_control" in nodes(load("teleoperation.launch", ["arduino:=false"]))


def test_robot_false_does_not_even_look_for_franka_control():
    # franka_control is not installed here: resolving the include would fail.
    load("teleoperation.launch", no_hardware())
    with pytest.raises(Exception, match="franka_control"):
        load("teleoperation.launch", ["arduino:=false"])


# -- the package around them ----------------------------------------------------------


@pytest.mark.parametrize("launch_file", ["sensor.launch", "teleoperation.launch"])
def test_every_hri_lab_node_is_an_executable_script_installed_by_cmake(launch_file):
    cmake = (REPO / "hri_lab" / "CMakeLists.txt").read_text()
    args = no_hardware() if launch_file == "teleoperation.launch" else []
    for node in load(launch_file, args).nodes:
        if node.package != "hri_lab":
            continue
        script = SCRIPTS / node.type
        assert script.is_file(), f"{launch_file}: no script {script}"
        assert script.stat().st_mode & 0o111, f"{script} is not executable (chmod +x)"
        assert script.read_text().startswith("#!/usr/bin/env python3\n")
        assert f"scripts/{node.type}" in cmake, f"{node.type} missing from catkin_install_python"
