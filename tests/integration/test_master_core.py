"""A private master is what roscore starts, without roscore's own process: the same nodes and
parameters to every tool, and roscore itself where asked (the lab twin's) or where rosout is missing."""

from __future__ import annotations

import subprocess

import pytest
from conftest import _ros_env

from hri_teleop.ros.master import PrivateMaster
from hri_teleop.ros.master_core import core_params, rosout_program

pytestmark = pytest.mark.ros


def _rosparam(master: PrivateMaster, name: str) -> str:
    return subprocess.run(["rosparam", "get", name], env=master.env, capture_output=True, text=True,
                          timeout=60).stdout


def test_a_private_master_has_roscores_nodes_and_parameters(tmp_path):
    with PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros") as master:
        assert master.core.argv[0] == "rosmaster"
        assert master.node_names() == {"/rosout"}
        assert master.master_pid() == master.core.popen.pid
        listed = subprocess.run(["rosnode", "list"], env=master.env, capture_output=True, text=True, timeout=60)
        assert listed.stdout.split() == ["/rosout"]
        assert master.get_param("/rosdistro") == core_params(master.env)["/rosdistro"]
        assert master.get_param("/rosversion") == core_params(master.env)["/rosversion"]
        assert len(str(master.get_param("/run_id"))) == 36
        assert master.get_param("/rosversion") == subprocess.run(
            ["rosversion", "roslaunch"], env=master.env, capture_output=True, text=True, timeout=60).stdout
        assert _rosparam(master, "/rosdistro").strip().strip("'").strip() == master.get_param("/rosdistro").strip()
    assert not [p for p in master.started if p.anything_left]


def test_roscores_parameters_are_the_same_as_roscores_own(tmp_path):
    with PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "a", roscore=True) as full:
        assert full.core.argv[0] == "roscore"
        want = {name: full.get_param(name) for name in ("/rosdistro", "/rosversion")}
    with PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "b") as direct:
        assert {name: direct.get_param(name) for name in ("/rosdistro", "/rosversion")} == want
        assert direct.get_param("/run_id") != full.env.get("run_id")


def test_without_a_rosout_program_roscore_is_started(tmp_path, monkeypatch):
    from hri_teleop.ros import master as master_module

    monkeypatch.setattr(master_module, "rosout_program", lambda env: None)
    with PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros") as master:
        assert master.core.argv[0] == "roscore"
        assert "/rosout" in master.node_names()


def test_the_rosout_program_is_found_under_a_catkin_prefix_first(tmp_path):
    prefix = tmp_path / "opt" / "ros" / "noetic"
    program = prefix / "lib" / "rosout" / "rosout"
    program.parent.mkdir(parents=True)
    program.write_text("#!/bin/sh\n")
    program.chmod(0o755)
    assert rosout_program({"CMAKE_PREFIX_PATH": str(prefix)}) == str(program)
    assert rosout_program({"ROS_ROOT": str(prefix / "share" / "ros")}) == str(program)
    program.chmod(0o644)
    assert rosout_program({"CMAKE_PREFIX_PATH": str(prefix)}) != str(program)


def test_the_version_is_roslaunchs_manifest_on_the_package_path(tmp_path):
    manifest = tmp_path / "roslaunch" / "package.xml"
    manifest.parent.mkdir()
    manifest.write_text("<package><name>roslaunch</name><version> 9.8.7 </version></package>")
    params = core_params({"ROS_PACKAGE_PATH": str(tmp_path), "ROS_DISTRO": "noetic"})
    assert params["/rosversion"] == "9.8.7\n" and params["/rosdistro"] == "noetic\n"
    assert core_params({"ROS_PACKAGE_PATH": str(tmp_path)})["/rosdistro"] == "Debian\n"
