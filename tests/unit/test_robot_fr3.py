"""The Franka Research 3, chosen once with HRI_ROBOT=fr3: every default of the core, the simulation and the
nodes is then the FR3's (Franka's control-parameter documentation, "Limits for Franka Research 3"). The
suite itself runs with HRI_ROBOT unset (tests/conftest.py), so each case here runs in a process of its own."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
#: Franka's published limits for the FR3, typed from the documentation's tables (not read from the profile).
FR3_JOINTS = {
    "position_min_rad": [-2.7437, -1.7837, -2.9007, -3.0421, -2.8065, 0.5445, -3.0159],
    "position_max_rad": [2.7437, 1.7837, 2.9007, -0.1518, 2.8065, 4.5169, 3.0159],
    "velocity_rad_per_s": [2.62, 2.62, 2.62, 2.62, 5.26, 4.18, 5.26],
    "acceleration_rad_per_s2": [10.0] * 7,
    "jerk_rad_per_s3": [5000.0] * 7,
}
FR3_CARTESIAN = {"translation": [3.0, 9.0, 4500.0], "rotation": [2.5, 17.0, 8500.0]}


def _in_process(code: str, robot: str = "fr3") -> dict:
    env = dict(os.environ, HRI_ROBOT=robot)
    proc = subprocess.run([sys.executable, "-c", code], env=env, cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_hri_robot_fr3_makes_every_default_of_the_core_the_fr3s():
    found = _in_process("""
import json
from dataclasses import asdict
from hri_teleop.core import joints, limits, gripper, reflex
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, load_teleop_config
from hri_teleop.core.robot import LAB_ROBOT, robot_named
from hri_teleop.core.paths import REPO
lim = limits.ROBOT_LIMITS
print(json.dumps({"names": list(joints.JOINT_NAMES), "fingers": list(joints.FINGER_JOINT_NAMES),
    "joints": {k: list(v) for k, v in asdict(joints.ROBOT_JOINT_LIMITS).items()},
    "cartesian": {"translation": [lim.translation.velocity, lim.translation.acceleration, lim.translation.jerk],
                  "rotation": [lim.rotation.velocity, lim.rotation.acceleration, lim.rotation.jerk]},
    "width": gripper.GRIPPER_MAX_WIDTH_M, "lab": LAB_ROBOT.name, "default": robot_named(None).name,
    "teleop": load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml").robot.name,
    "topic": DEFAULT_TWIST_TOPIC,
    "lab_limits": [limits.DEFAULT_LIMITS.translation.acceleration, limits.DEFAULT_LIMITS.rotation.acceleration]}))
""")
    assert found["names"] == [f"fr3_joint{i}" for i in range(1, 8)]
    assert found["fingers"] == ["fr3_finger_joint1", "fr3_finger_joint2"]
    assert found["joints"] == FR3_JOINTS
    assert found["cartesian"] == FR3_CARTESIAN
    assert found["width"] == 0.08 and found["lab"] == found["default"] == found["teleop"] == "fr3"
    assert found["lab_limits"] == [0.2, 0.4]  # the lab's 0.3 and 0.6, lowered to the FR3's budget at 50 Hz
    assert found["topic"] == "/cartesian_velocity_controller/cmd_vel"


def test_the_fr3_reuses_the_pandas_chain_and_the_lab_runs_on_it_inside_its_limits():
    found = _in_process("""
import json
from hri_teleop.core.paths import REPO
from hri_teleop.core.run_record import summarize
from hri_teleop.core.config import load_teleop_config
from hri_teleop.sim.config import default_sim_yaml, load_world_config
from hri_teleop.sim.kinematics import PandaKinematics
from hri_teleop.sim.lab import run_lab
from hri_teleop.core.joints import READY_POSE_RAD
scenario = REPO / "hri_lab" / "scenarios" / "default.yaml"
world = load_world_config(default_sim_yaml(), scenario=scenario)
config = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
summary = summarize(run_lab(scenario, world, config.params, config.limits))
print(json.dumps({"robot": world.robot.name, "hand": list(PandaKinematics().position(READY_POSE_RAD)),
                  "arm_velocity": world.arm.limits.translation.velocity, "joint_velocity": list(world.arm.joint_limits.velocity_rad_per_s),
                  "ended": summary.ended_by, "violations": summary.violations, "lifted": summary.lifted,
                  "crushed": summary.crushed}))
""")
    assert found["robot"] == "fr3" and found["arm_velocity"] == 3.0
    assert found["joint_velocity"] == FR3_JOINTS["velocity_rad_per_s"]
    assert [round(v, 3) for v in found["hand"]] == [0.307, 0.0, 0.487]  # the Panda's ready pose, the same chain
    assert (found["ended"], found["violations"], found["lifted"], found["crushed"]) == ("quit", 0, True, False)


def test_the_demo_says_which_robot_it_ran():
    found = _in_process("""
import json
from hri_teleop.ros.teleop_demo import robot_ran
print(json.dumps({"said": robot_ran()}))
""")
    assert found["said"].startswith("fr3: Franka Research 3")


@pytest.mark.parametrize("value", ["ur5", "/nowhere/arm.yaml"])
def test_a_robot_that_is_not_there_is_refused_in_one_line_naming_the_choices(value):
    env = dict(os.environ, HRI_ROBOT=value)
    proc = subprocess.run([sys.executable, "-c", "import hri_teleop.core.joints"], env=env, cwd=REPO,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    last = proc.stderr.strip().splitlines()[-1]
    assert f"HRI_ROBOT={value}: no such robot profile" in last and "fr3, franka_panda" in last, last


def test_limits_by_robot_writes_the_fr3s_numbers_over_the_labs_and_leaves_the_panda_alone():
    from hri_teleop.core.config import ConfigError, load_teleop_config

    lab = REPO / "hri_lab" / "config" / "teleop.yaml"
    panda = load_teleop_config(lab)
    fr3 = load_teleop_config(lab, {"robot": "fr3"})
    assert (panda.limits.translation.acceleration, panda.limits.rotation.acceleration) == (0.3, 0.6)
    assert (fr3.limits.translation.acceleration, fr3.limits.rotation.acceleration) == (0.2, 0.4)
    assert fr3.limits.translation.velocity == panda.limits.translation.velocity == 0.25  # the rest stays
    # without limits_by_robot the lab's numbers are the FR3's too, and its jerk budget refuses them at 50 Hz
    import yaml

    from hri_teleop.core.config import teleop_config_from_dict
    from hri_teleop.core.teleop import TeleopController, TeleopError

    TeleopController(fr3.params, fr3.limits, fr3.robot.cartesian_limits)  # the FR3's controller takes them
    plain = {k: v for k, v in yaml.safe_load(lab.read_text()).items() if k != "limits_by_robot"}
    bare = teleop_config_from_dict({**plain, "robot": "fr3"})
    with pytest.raises(TeleopError) as caught:
        TeleopController(bare.params, bare.limits, bare.robot.cartesian_limits)
    assert "lower limits.translation.acceleration to <= 0.225" in str(caught.value)
    with pytest.raises(ConfigError) as caught:
        load_teleop_config(lab, {"robot": "fr3", "limits_by_robot": {"fr3": 0.2}})
    assert "limits_by_robot.fr3 must be a mapping" in str(caught.value) and "\n" not in str(caught.value)


def test_a_demo_that_recorded_nothing_says_the_nodes_own_words():
    from hri_teleop.ros.teleop_demo import node_errors

    said = ("started roslaunch server\n\x1b[31m[FATAL] [1.2]: limits.translation.acceleration 0.3 m/s^2 ... lower it"
            "\x1b[0m\n[teleoperation-4] process has died [pid 1, exit code 1, cmd x].\nshutting down\n")
    assert node_errors(said) == ["[FATAL] [1.2]: limits.translation.acceleration 0.3 m/s^2 ... lower it",
                                 "[teleoperation-4] process has died [pid 1, exit code 1, cmd x]."]
    assert node_errors("all fine\n") == []
    assert node_errors("[ERROR] a\n[ERROR] b\n[ERROR] c\n", limit=2) == ["[ERROR] b", "[ERROR] c"]


def test_the_labs_limits_are_lowered_to_a_robots_budget_only_where_they_do_not_fit():
    from hri_teleop.core.limits import LAB_LIMITS, AxisLimits, CartesianLimits, check_command_rate, lab_limits_for
    from hri_teleop.core.robot import load_robot_profile

    panda = load_robot_profile(REPO / "hri_teleop" / "core" / "robots" / "franka_panda.yaml").cartesian_limits
    fr3 = load_robot_profile(REPO / "hri_teleop" / "core" / "robots" / "fr3.yaml").cartesian_limits
    assert lab_limits_for(panda) == LAB_LIMITS
    lowered = lab_limits_for(fr3)
    assert (lowered.translation.acceleration, lowered.rotation.acceleration) == (0.2, 0.4)
    assert lowered.translation.velocity == 0.25 and lowered.rotation.jerk == 4.0
    check_command_rate(lowered, 50.0, fr3)  # fits
    # a budget the lab's number fits exactly keeps it: 0.3 m/s^2 at 50 Hz is 6 mm/s, a jerk of 6000 m/s^3 takes 6
    exact = CartesianLimits(AxisLimits(3.0, 9.0, 6000.0), AxisLimits(2.5, 25.0, 12000.0))
    assert lab_limits_for(exact).translation.acceleration == 0.3
    # one just below takes the next step down
    below = CartesianLimits(AxisLimits(3.0, 9.0, 5999.0), AxisLimits(2.5, 25.0, 12000.0))
    assert lab_limits_for(below).translation.acceleration == 0.25
    # and the teleop.yaml of the lab writes the same numbers for the FR3
    import yaml

    fr3_yaml = yaml.safe_load((REPO / "hri_lab" / "config" / "teleop.yaml").read_text())["limits_by_robot"]["fr3"]
    assert (fr3_yaml["translation"]["acceleration"], fr3_yaml["rotation"]["acceleration"]) == (0.2, 0.4)
