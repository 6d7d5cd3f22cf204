"""After a reflex, from a notebook: lab.reflex() says what stopped the simulated robot in plain words and
lab.recover() sends franka_control's error recovery, which lab_sim serves; on a real roscore, the kernel
being a process of its own (rospy allows one node per process)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from hri_teleop.core.joints import JOINT_POSITION_LIMITS_VIOLATION
from hri_teleop.core.reflex import RECOVERY_HINT
from hri_teleop.course.recovery import reflex_from_errors, reflex_from_status

pytestmark = pytest.mark.ros

KERNEL = textwrap.dedent('''
    import json, sys, time
    import rospy
    from geometry_msgs.msg import Twist
    from hri_teleop.course import ensure_ros, lab
    from hri_teleop.ros.master_api import master_call

    out = {}
    ros = ensure_ros(quiet=True)
    robot = lab.start_robot(object="none")
    out["before"] = lab.reflex()
    out["recover_without_reflex"] = lab.recover()
    pub = rospy.Publisher("/cartesian_velocity_controller/cmd_vel", Twist, queue_size=10)
    deadline = time.monotonic() + 20
    while pub.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    step = Twist()
    step.linear.x = 0.1                      # 0 -> 0.1 m/s at once: a reflex
    for _ in range(10):
        pub.publish(step)
        time.sleep(0.02)
    pub.publish(Twist())
    time.sleep(0.3)                          # lab_sim publishes its status at 10 Hz
    out["during"] = lab.reflex()
    out["recovered"] = lab.recover()
    time.sleep(0.3)
    out["after"] = lab.reflex()
    lab.stop()
    json.dump(out, open(sys.argv[1], "w"))
''')


def test_a_reflex_is_explained_and_recovered_from_a_notebook_cell(ros_master, tmp_path):
    out = tmp_path / "out.json"
    env = dict(ros_master.env, HRI_MODE="home")
    env.pop("NBGRADER_EXECUTION", None)
    proc = subprocess.run([sys.executable, "-c", KERNEL, str(out)], env=env, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    result = json.loads(out.read_text())
    assert result["before"][0].startswith("No reflex: the robot is idle")
    assert result["recover_without_reflex"] is True  # franka_control's recovery succeeds without an error too
    during = "\n".join(result["during"])
    assert during.startswith("The robot stopped itself (a reflex)") and "discontinuity" in during
    assert result["during"][-1] == RECOVERY_HINT
    assert result["recovered"] is True and "recovered: the robot accepts commands again" in proc.stdout
    assert result["after"][0].startswith("No reflex")
    assert "not tracking" not in proc.stderr, proc.stderr  # lab_sim answers fast: no result may be lost


def test_without_the_simulated_robot_recovery_says_what_to_start(ros_master, tmp_path):
    script = ("import json, sys\nfrom hri_teleop.course import ensure_ros, lab\nensure_ros(quiet=True)\n"
              "json.dump(lab.recover(timeout_s=1.0), open(sys.argv[1], 'w'))")
    out = tmp_path / "out.json"
    proc = subprocess.run([sys.executable, "-c", script, str(out)], env=dict(ros_master.env, HRI_MODE="home"),
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert json.loads(out.read_text()) is False
    assert "no error recovery on /franka_control/error_recovery: at home run the start cell" in proc.stdout


def test_the_status_and_the_robots_error_flags_become_the_same_plain_words():
    status = {"state": "reflex", "explanation": "The robot stopped itself ...\n- joint 7 ...\nThen recover"}
    assert reflex_from_status(status) == ["The robot stopped itself ...", "- joint 7 ...", "Then recover"]
    assert reflex_from_status({"state": "moving", "nearest_joint_limit": ""}) == [
        "No reflex: the robot is moving and accepts commands."]

    class Errors:  # franka_msgs/Errors: one bool per libfranka flag
        __slots__ = ("joint_position_limits_violation", JOINT_POSITION_LIMITS_VIOLATION)

        def __init__(self) -> None:
            self.joint_position_limits_violation = False
            setattr(self, JOINT_POSITION_LIMITS_VIOLATION, True)

    lines = reflex_from_errors(Errors())
    assert len(lines) == 3 and "a joint reached its limit." in lines[1] and "nan" not in lines[1]

    class CartesianErrors:  # the Cartesian flags say neither which group nor by how much
        __slots__ = ("cartesian_motion_generator_velocity_discontinuity",
                     "cartesian_motion_generator_acceleration_discontinuity")

        def __init__(self) -> None:
            for name in self.__slots__:
                setattr(self, name, True)

    lines = reflex_from_errors(CartesianErrors())
    assert lines[1].startswith("- The commanded translation or rotation velocity jumped: its change within one "
                               "millisecond is too large an acceleration. Ramp")
    assert lines[2].startswith("- The commanded translation or rotation acceleration jumped: too large a jerk. Ramp")
