"""The handout's message commands in the shell the toolkit sets up: rosmsg finds Debian's std_msgs."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PUBLISH = ("import rospy; from std_msgs.msg import Float32; rospy.init_node('mapping_node'); "
           "p = rospy.Publisher('/force_mapped', Float32, queue_size=1); rospy.spin()")

pytestmark = pytest.mark.ros


def _debian_ros_without_manifests() -> bool:
    return not os.environ.get("ROS_DISTRO") and not (REPO / ".venv" / "share" / "hri-ros-msgs" / "std_msgs").is_dir()


def test_rosmsg_show_finds_std_msgs_in_the_shell_of_tools_env_sh():
    assert not _debian_ros_without_manifests(), "no manifests of Debian's message definitions: run make setup"
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_PACKAGE_PATH", "ROS_DISTRO")}
    shown = subprocess.run(["bash", "-c", ". tools/env.sh && rosmsg show std_msgs/Float32 && "
                            "rosmsg show geometry_msgs/Twist"], cwd=REPO, env=env, capture_output=True, text=True,
                           timeout=60)
    assert shown.returncode == 0, shown.stderr
    assert shown.stdout.startswith("float32 data\n"), shown.stdout
    assert "geometry_msgs/Vector3 linear\n  float64 x" in shown.stdout


def test_the_handouts_rostopic_type_into_rosmsg_show_pipe_works_on_the_kernels_master(ros_master):
    node = ros_master.run([sys.executable, "-c", PUBLISH], "mapping_node")
    ros_master.wait_for(lambda: "/mapping_node" in ros_master.publishers("/force_mapped") or not node.running, 30,
                        "/force_mapped's publisher")
    assert node.running, node.output()
    piped = subprocess.run(["bash", "-c", "set -o pipefail; rostopic type /force_mapped | rosmsg show"],
                           env=ros_master.env, capture_output=True, text=True, timeout=60)
    assert piped.returncode == 0, piped.stderr
    assert piped.stdout.strip() == "float32 data", piped.stdout
