"""The robot in one profile: the Panda's file is where the core's numbers come from, and a lab with
another robot builds the simulated lab from its own file (here a made-up one) and runs the default
scenario with it."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from hri_teleop.core import joints, limits, reflex
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, load_teleop_config
from hri_teleop.core.robot import LAB_ROBOT as PANDA  # HRI_ROBOT unset (tests/conftest.py): the Panda
from hri_teleop.core.robot import load_robot_profile
from hri_teleop.core.robot_file import PANDA_FILE, RobotFileError
from hri_teleop.core.run_record import summarize
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.sim.arm import SimArm
from hri_teleop.sim.config import SimConfigError, default_sim_yaml, load_world_config
from hri_teleop.sim.hand_params import MAX_FORCE_N, MAX_SPEED_M_PER_S
from hri_teleop.sim.kinematics import ELBOW_JOINT, TCP_FRAME
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.world import LAB_ARM_CONFIG, robot_arm

REPO = Path(__file__).resolve().parents[2]
SCENARIOS = REPO / "hri_lab" / "scenarios"
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")


def made_up_robot(tmp_path: Path, **changes: object) -> Path:
    """The Panda's file with other Cartesian and joint limits and another gripper: the 'Acme' arm."""
    data = yaml.safe_load(PANDA_FILE.read_text())
    data["name"] = "acme_arm"
    # lower than the Panda's, high enough that the lab's 50 Hz commands are no steps to it
    data["cartesian_limits"]["translation"] = {"velocity": 0.5, "acceleration": 8.0, "jerk": 6000.0}
    data["cartesian_limits"]["rotation"] = {"velocity": 1.0, "acceleration": 15.0, "jerk": 12000.0}
    data["joints"]["velocity_rad_per_s"] = [1.5] * 7
    data["joints"]["jerk_rad_per_s3"] = [4000.0] * 7
    data["gripper"].update({"namespace": "/acme_hand", "max_width_m": 0.07, "max_speed_m_per_s": 0.08,
                            "max_force_n": 60.0})
    for dotted, value in changes.items():
        section, key = dotted.split("__")
        data[section][key] = value
    path = tmp_path / "acme_arm.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


# --- the Panda's file is the one source ---------------------------------------------------------


def test_the_cores_panda_numbers_are_the_profiles():
    assert limits.ROBOT_LIMITS == PANDA.cartesian_limits
    assert (limits.ROBOT_LIMITS.translation.velocity, limits.ROBOT_LIMITS.rotation.jerk) == (1.7, 12500.0)
    assert joints.ROBOT_JOINT_LIMITS == PANDA.joint_limits and joints.ROBOT_JOINT_LIMITS.jerk_rad_per_s3[1] == 3750.0
    assert joints.JOINT_NAMES == PANDA.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert joints.READY_POSE_RAD == PANDA.ready_pose_rad
    assert joints.FINGER_JOINT_NAMES == PANDA.gripper.finger_joints
    assert joints.JOINT_VELOCITY_DISCONTINUITY == PANDA.joint_errors["acceleration"]
    assert reflex.CARTESIAN_ACCELERATION_DISCONTINUITY == PANDA.cartesian_errors["jerk"] \
        == "cartesian_motion_generator_acceleration_discontinuity"
    assert reflex.ERROR_RECOVERY_ACTION == PANDA.topics["error_recovery"] == "/franka_control/error_recovery"
    assert DEFAULT_TWIST_TOPIC == PANDA.topics["twist_command"]
    assert (GRIPPER_MAX_WIDTH_M, MAX_SPEED_M_PER_S, MAX_FORCE_N) == (0.08, 0.1, 70.0)
    assert (TCP_FRAME, ELBOW_JOINT) == ("panda_hand_tcp", 2)  # the profile counts joints from 1
    assert all(PANDA.sources[s] for s in ("cartesian_limits", "joints", "gripper", "errors"))


def test_a_world_without_robot_is_the_pandas():
    world = load_world_config(default_sim_yaml())
    assert world.robot is PANDA and world.arm == LAB_ARM_CONFIG and world.hand.max_width_m == 0.08


# --- another robot ------------------------------------------------------------------------------


def test_a_made_up_robot_builds_the_lab_with_its_limits_and_gripper(tmp_path):
    world = load_world_config(default_sim_yaml(), {"robot": str(made_up_robot(tmp_path))})
    assert world.robot.name == "acme_arm" and world.robot.gripper.namespace == "/acme_hand"
    assert world.arm.limits.translation.velocity == 0.5 and world.arm.joint_limits.velocity_rad_per_s == (1.5,) * 7
    # the gentle stop after a timeout stays inside the robot's limits, each number the smaller one
    stop = world.arm.effective_stop_limits
    assert (stop.translation.velocity, stop.translation.acceleration, stop.translation.jerk) == (0.5, 1.0, 100.0)
    assert (world.hand.max_width_m, world.hand.initial_width_m, world.hand.max_force_n) == (0.07, 0.07, 60.0)
    # the rest of sim.yaml still applies
    assert world.arm.workspace_min_m == LAB_ARM_CONFIG.workspace_min_m


def test_the_default_scenario_runs_with_the_made_up_robot_inside_its_limits(tmp_path):
    world = load_world_config(default_sim_yaml(), {"robot": str(made_up_robot(tmp_path))},
                              scenario=SCENARIOS / "default.yaml")
    record = run_lab(SCENARIOS / "default.yaml", world, CONFIG.params, CONFIG.limits)
    summary = summarize(record)
    assert summary.ended_by == "quit" and summary.violations == 0
    assert (summary.grasped, summary.lifted, summary.crushed) == (True, True, False)
    assert max(w for _, w in record.width) <= 0.07  # the made-up hand's range, not the Panda's 0.08
    assert max(w for _, w in record.width) > 0.065  # ... and it opened to it


def test_the_simulated_arm_judges_with_the_robots_velocity_limit(tmp_path):
    """0.6 m/s, reached gently: inside the Panda's 1.7 m/s, above the made-up arm's 0.5 m/s."""
    acme = load_robot_profile(made_up_robot(tmp_path))

    def reflexes(config) -> tuple:
        arm = SimArm(config.__class__(**{**config.__dict__, "joints": False}))
        t, v = 0.0, 0.0
        while v < 0.6:
            v = min(0.6, v + 0.0005)  # 0.5 m/s^2, a jerk-free ramp after its first step
            t += 0.001
            arm.command((v, 0.0, 0.0, 0.0, 0.0, 0.0), t)
            arm.step(t)
        return arm.reflex_errors

    assert reflexes(LAB_ARM_CONFIG) == ()
    assert reflexes(robot_arm(acme)) == (acme.cartesian_errors["velocity"],)


# --- a bad file: one line naming the file and the key ---------------------------------------------


@pytest.mark.parametrize("change, words", [
    ({"gripper__max_width_m": -0.1}, "gripper.max_width_m must be a positive number"),
    ({"joints__names": ["a", "b"]}, "joints.names must be a list of 7 names"),
    ({"topics__twist_command": ""}, "topics.twist_command must be a name"),
    ({"joints__position_min_rad": [3.0] * 7}, "joint 1: position_min_rad 3 must be below position_max_rad"),
    ({"kinematics__elbow_joint": 8}, "kinematics.elbow_joint 8 is not a joint"),
    ({"cartesian_limits__translation": {"velocity": 1.0}}, "cartesian_limits.translation must be {velocity"),
])
def test_a_bad_profile_is_refused_in_one_line_naming_the_key(tmp_path, change, words):
    path = made_up_robot(tmp_path, **change)
    with pytest.raises(RobotFileError) as caught:
        load_robot_profile(path)
    message = str(caught.value)
    assert message.startswith(str(path)) and words in message and "\n" not in message


def test_a_missing_profile_in_sim_yaml_names_the_key_and_the_file(tmp_path):
    with pytest.raises(SimConfigError) as caught:
        load_world_config(default_sim_yaml(), {"robot": str(tmp_path / "nowhere.yaml")})
    message = str(caught.value)
    assert "robot" in message and "nowhere.yaml" in message and "\n" not in message


def test_a_profile_named_without_a_path_is_looked_up_beside_the_pandas():
    assert load_world_config(default_sim_yaml(), {"robot": "franka_panda"}).robot == PANDA


# --- the teleoperation node's config ---------------------------------------------------------------


def test_the_teleop_config_keeps_its_limits_inside_the_robots(tmp_path):
    from hri_teleop.core.config import ConfigError, teleop_config_from_dict
    from hri_teleop.core.config import load_teleop_config as load

    lab = REPO / "hri_lab" / "config" / "teleop.yaml"
    assert load(lab).robot == PANDA and load(lab).twist_topic == "/cartesian_velocity_controller/cmd_vel"
    acme = str(made_up_robot(tmp_path, topics__twist_command="/acme/cmd_vel"))
    fit = {"robot": acme, "width_max": 0.07, "initial_width": 0.07}  # its 70 mm hand
    assert load(lab, fit).robot.name == "acme_arm"
    # a config that names no twist_topic sends to the robot's velocity controller (teleop.yaml names one)
    assert teleop_config_from_dict({"robot": acme}).twist_topic == "/acme/cmd_vel"
    # 0.5 m/s is the made-up arm's velocity limit: the lab's 0.25 passes, 0.6 (inside the Panda's) does not
    assert load(lab, {**fit, "limits": {"translation": {"velocity": 0.5}}}).limits.translation.velocity == 0.5
    with pytest.raises(ConfigError) as caught:
        load(lab, {**fit, "limits": {"translation": {"velocity": 0.6}}})
    assert "translation.velocity=0.6 > 0.5" in str(caught.value) and "\n" not in str(caught.value)
    assert load(lab, {"limits": {"translation": {"velocity": 0.6}}}).limits.translation.velocity == 0.6


def test_a_robot_whose_limits_make_the_labs_50_hz_commands_steps_is_refused_by_the_controller(tmp_path):
    """A jerk limit of 3000 m/s^3 lets a command change by 0.003 m/s per 1 ms cycle; the lab's limiter
    changes it by 0.3 m/s^2 / 50 Hz = 0.006 m/s per message: the robot would see steps."""
    from hri_teleop.core.teleop import TeleopController, TeleopError

    acme = load_robot_profile(made_up_robot(tmp_path, cartesian_limits__translation={
        "velocity": 0.5, "acceleration": 8.0, "jerk": 3000.0}))
    with pytest.raises(TeleopError, match="sees as a step above its 0.003 m/s"):
        TeleopController(CONFIG.params, CONFIG.limits, acme.cartesian_limits)
    TeleopController(CONFIG.params, CONFIG.limits, load_robot_profile(made_up_robot(tmp_path)).cartesian_limits)


# --- the arm's description comes from the profile too --------------------------------------------


def test_the_simulated_joints_follow_the_profiles_tool_frame(tmp_path):
    """The same start position for the hand frame instead of the fingertips' TCP: the IK solves
    another pose, so the joints differ (the flange sits 10 cm higher up the arm)."""
    from hri_teleop.sim.arm import SimArm

    panda = load_world_config(default_sim_yaml())
    flange = load_world_config(default_sim_yaml(), {"robot": str(made_up_robot(tmp_path, kinematics__tool_frame="panda_hand"))})
    assert flange.arm.model.tool_frame == "panda_hand"
    q_tcp, q_hand = SimArm(panda.arm).joint_positions, SimArm(flange.arm).joint_positions
    assert max(abs(a - b) for a, b in zip(q_tcp, q_hand)) > 0.05


@pytest.mark.parametrize("change, words", [
    ({"kinematics__urdf": "robots/acme/urdf/acme.urdf"}, "kinematics.urdf 'robots/acme/urdf/acme.urdf' is not in"),
    ({"kinematics__tool_frame": "acme_tool"}, "has no frame 'acme_tool'"),
    ({"joints__names": [f"acme_joint{i}" for i in range(1, 8)]}, "name the URDF's joints in joints.names"),
])
def test_a_description_the_urdf_does_not_hold_is_named_in_one_line(tmp_path, change, words):
    with pytest.raises(SimConfigError) as caught:
        load_world_config(default_sim_yaml(), {"robot": str(made_up_robot(tmp_path, **change))})
    message = str(caught.value)
    assert message.startswith("overrides: robot") and words in message and "\n" not in message


def test_the_teleop_width_range_is_the_robots_hand(tmp_path):
    from hri_teleop.core.config import ConfigError
    from hri_teleop.core.config import load_teleop_config as load

    lab = REPO / "hri_lab" / "config" / "teleop.yaml"
    acme = str(made_up_robot(tmp_path))  # a 70 mm hand
    assert load(lab).params.gripper_max_width_m == 0.08
    with pytest.raises(ConfigError) as caught:  # teleop.yaml's 0.08 m does not fit it
        load(lab, {"robot": acme})
    assert "width_max_m <= 0.07 m" in str(caught.value) and "\n" not in str(caught.value)
    config = load(lab, {"robot": acme, "width_max": 0.07, "initial_width": 0.07})
    assert (config.params.width_max_m, config.params.gripper_max_width_m) == (0.07, 0.07)
