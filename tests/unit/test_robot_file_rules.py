"""Each rule of a robot profile file (hri_teleop.core.robot_file) and of the typed profile built from it
(hri_teleop.core.robot), at its edge: what a value of each kind must be, which sections and keys a file has,
which keys it may leave out, how HRI_ROBOT and ``robot:`` name a profile (issue 44: changing a rule fails a
test here). The Panda's and the FR3's files are the shipped ones; a changed copy of the Panda's is the bad one."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict

import pytest
import yaml

from hri_teleop.core import robot_file
from hri_teleop.core.robot import LAB_ROBOT, GripperProfile, RobotFileError, load_robot_profile, robot_named
from hri_teleop.core.robot_file import (
    PANDA_FILE,
    ROBOT_ENV,
    ROBOTS_DIR,
    lab_robot_file,
    lab_robot_path,
    panda_file,
    read_robot_file,
    robot_path,
)

FR3_FILE = ROBOTS_DIR / "fr3.yaml"


def _panda() -> Dict[str, Any]:
    return yaml.safe_load(PANDA_FILE.read_text())


def _write(tmp_path: Path, data: Any, name: str = "arm.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data))
    return path


def _changed(tmp_path: Path, section: str, key: str, value: Any) -> Path:
    data = _panda()
    data[section][key] = value
    return _write(tmp_path, data)


def _refusal(path: Path) -> str:
    with pytest.raises(RobotFileError) as caught:
        read_robot_file(path)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(str(path)), message
    return message


# --- each kind of value -------------------------------------------------------------------------------------


@pytest.mark.parametrize("value", [0, 0.0, -0.08, True, float("inf"), "0.08", None])
def test_a_positive_value_refuses_zero_a_negative_a_bool_and_a_text(tmp_path, value):
    message = _refusal(_changed(tmp_path, "gripper", "max_width_m", value))
    assert f"gripper.max_width_m must be a positive number, got {value!r}" in message


def test_a_positive_value_takes_the_smallest_positive_number_as_a_float(tmp_path):
    data = read_robot_file(_changed(tmp_path, "gripper", "max_force_n", 1))
    assert data["gripper"]["max_force_n"] == 1.0 and type(data["gripper"]["max_force_n"]) is float
    assert read_robot_file(_changed(tmp_path, "gripper", "max_width_m", 1e-12))["gripper"]["max_width_m"] == 1e-12


def test_a_number_may_be_zero_or_negative_and_is_kept_as_a_float():
    ready = read_robot_file(PANDA_FILE)["joints"]["ready_pose_rad"]
    assert ready[0] == 0.0 and ready[1] < 0 and all(type(q) is float for q in ready)


@pytest.mark.parametrize("value", [float("nan"), "0.1", True])
def test_a_number_refuses_what_is_not_a_finite_number(tmp_path, value):
    message = _refusal(_changed(tmp_path, "joints", "ready_pose_rad", [value] + [0.0] * 6))
    assert f"joints.ready_pose_rad[0] must be a number, got {value!r}" in message


@pytest.mark.parametrize("value, ok", [(1, True), (7, True), (0, False), (-1, False), (1.0, False), (True, False)])
def test_the_elbow_joint_is_a_whole_number_from_1_to_the_number_of_joints(tmp_path, value, ok):
    path = _changed(tmp_path, "kinematics", "elbow_joint", value)
    if ok:
        elbow = read_robot_file(path)["kinematics"]["elbow_joint"]
        assert elbow == value and type(elbow) is int
    else:
        assert f"kinematics.elbow_joint must be a whole number from 1, got {value!r}" in _refusal(path)


def test_an_elbow_joint_past_the_last_joint_is_refused(tmp_path):
    assert "kinematics.elbow_joint 8 is not a joint (1..7)" in _refusal(_changed(tmp_path, "kinematics", "elbow_joint", 8))


def test_a_name_is_kept_without_its_spaces_and_blank_or_not_text_is_refused(tmp_path):
    assert read_robot_file(_changed(tmp_path, "kinematics", "tool_frame", "  hand  "))["kinematics"]["tool_frame"] == "hand"
    for value in ("   ", "", 5, None):
        assert f"kinematics.tool_frame must be a name (text), got {value!r}" in _refusal(
            _changed(tmp_path, "kinematics", "tool_frame", value))


@pytest.mark.parametrize("value", [
    {"velocity": 1.0, "acceleration": 2.0},                                    # one missing
    {"velocity": 1.0, "acceleration": 2.0, "jerk": 3.0, "snap": 4.0},          # one more
    [1.0, 2.0, 3.0],                                                           # not a mapping
    ["velocity", "acceleration", "jerk"],                                      # its keys, but in a list
])
def test_an_axis_has_exactly_velocity_acceleration_and_jerk(tmp_path, value):
    message = _refusal(_changed(tmp_path, "cartesian_limits", "rotation", value))
    assert "cartesian_limits.rotation must be {velocity: V, acceleration: A, jerk: J}" in message


def test_an_axis_value_is_positive_and_named_by_its_key(tmp_path):
    message = _refusal(_changed(tmp_path, "cartesian_limits", "rotation", {"velocity": 1.0, "acceleration": 2.0,
                                                                            "jerk": 0}))
    assert "cartesian_limits.rotation.jerk must be a positive number, got 0" in message
    axis = read_robot_file(PANDA_FILE)["cartesian_limits"]["rotation"]
    assert axis == {"velocity": 2.5, "acceleration": 25.0, "jerk": 12500.0}


@pytest.mark.parametrize("value", [
    {"velocity": "a", "acceleration": "b"},
    {"velocity": "a", "acceleration": "b", "jerk": "c", "position": "d"},
    "cartesian_errors",
    ["velocity", "acceleration", "jerk"],
])
def test_an_error_table_has_exactly_its_keys(tmp_path, value):
    message = _refusal(_changed(tmp_path, "errors", "cartesian", value))
    assert "errors.cartesian must be {velocity: NAME, acceleration: NAME, jerk: NAME}" in message


def test_an_error_name_is_a_name_named_by_its_key(tmp_path):
    table = {"position": " p ", "velocity": "v", "acceleration": "a", "jerk": ""}
    assert "errors.joint.jerk must be a name (text), got ''" in _refusal(_changed(tmp_path, "errors", "joint", table))
    data = read_robot_file(_changed(tmp_path, "errors", "joint", {**table, "jerk": "j"}))
    assert data["errors"]["joint"] == {"position": "p", "velocity": "v", "acceleration": "a", "jerk": "j"}


@pytest.mark.parametrize("count", [6, 8])
def test_a_list_of_seven_has_seven(tmp_path, count):
    message = _refusal(_changed(tmp_path, "joints", "velocity_rad_per_s", [1.0] * count))
    assert "joints.velocity_rad_per_s must be a list of 7 positives" in message


def test_a_list_is_a_tuple_of_checked_items_named_by_their_index(tmp_path):
    assert read_robot_file(PANDA_FILE)["gripper"]["actions"] == ("move", "grasp", "homing", "stop")
    message = _refusal(_changed(tmp_path, "joints", "velocity_rad_per_s", [1.0, 1.0, 1.0, 0.0, 1.0, 1.0, 1.0]))
    assert "joints.velocity_rad_per_s[3] must be a positive number, got 0.0" in message
    assert "gripper.finger_joints[1] must be a name" in _refusal(_changed(tmp_path, "gripper", "finger_joints", ["a", 2]))


def test_a_list_of_any_length_takes_one_and_refuses_none_or_a_text(tmp_path):
    assert read_robot_file(_changed(tmp_path, "gripper", "actions", ["move"]))["gripper"]["actions"] == ("move",)
    for value in ([], "move"):
        assert "gripper.actions must be a list of one or more names" in _refusal(
            _changed(tmp_path, "gripper", "actions", value))


# --- sections and keys ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("data", [[1, 2], "franka", None])
def test_a_file_that_is_not_a_mapping_of_sections_is_refused(tmp_path, data):
    assert "a robot profile is a mapping of sections (cartesian_limits, joints" in _refusal(_write(tmp_path, data))


def test_an_unknown_section_is_refused_and_name_and_description_are_known(tmp_path):
    data = {**_panda(), "extras": {}}
    assert "unknown section 'extras'; the sections are name, description, cartesian_limits" in _refusal(
        _write(tmp_path, data))


def test_the_name_is_required_and_the_description_is_optional_text(tmp_path):
    data = _panda()
    del data["name"]
    assert "name must be a name (text), got None" in _refusal(_write(tmp_path, data))
    data = {**_panda(), "name": " arm "}
    del data["description"]
    read = read_robot_file(_write(tmp_path, data))
    assert read["name"] == "arm" and read["description"] == ""
    assert read_robot_file(_write(tmp_path, {**_panda(), "description": 3}))["description"] == "3"


@pytest.mark.parametrize("value", [None, [1], "joints"])
def test_a_section_missing_or_not_a_mapping_is_refused_naming_its_keys(tmp_path, value):
    data = _panda()
    if value is None:
        del data["topics"]
    else:
        data["topics"] = value
    message = _refusal(_write(tmp_path, data))
    assert "section 'topics' is missing or not a mapping" in message
    assert "(twist_command, arm_joint_states, robot_state, error_recovery)" in message


def test_a_key_a_section_does_not_have_is_refused_and_source_is_free_text(tmp_path):
    message = _refusal(_changed(tmp_path, "topics", "cmd_vel", "/x"))
    assert "topics.cmd_vel is not a key of topics (its keys: twist_command," in message
    data = read_robot_file(_changed(tmp_path, "topics", "source", 5))
    assert data["topics"]["source"] == "5" and data["gripper"]["source"].startswith("Franka Hand datasheet")
    data = _panda()
    assert "source" not in data["topics"]
    assert read_robot_file(_write(tmp_path, data))["topics"]["source"] == ""


def test_a_required_key_left_out_is_refused(tmp_path):
    data = _panda()
    del data["gripper"]["max_force_n"]
    assert "gripper.max_force_n is missing; see franka_panda.yaml" in _refusal(_write(tmp_path, data))


def test_the_urdfs_joint_names_default_to_the_topics_and_may_differ():
    panda, fr3 = read_robot_file(PANDA_FILE), read_robot_file(FR3_FILE)
    assert panda["kinematics"]["urdf_joint_names"] == panda["joints"]["names"]
    assert panda["kinematics"]["urdf_finger_joints"] == panda["gripper"]["finger_joints"]
    assert fr3["joints"]["names"][0] == "fr3_joint1" and fr3["kinematics"]["urdf_joint_names"][0] == "panda_joint1"
    assert fr3["kinematics"]["urdf_finger_joints"] == ("panda_finger_joint1", "panda_finger_joint2")


def test_an_optional_key_left_out_leaves_the_keys_after_it_read(tmp_path):
    data = _panda()
    data["kinematics"]["urdf_finger_joints"] = ["left_finger", "right_finger"]
    read = read_robot_file(_write(tmp_path, data))["kinematics"]
    assert read["urdf_joint_names"][0] == "panda_joint1" and read["urdf_finger_joints"] == ("left_finger", "right_finger")


def test_a_missing_profile_file_says_what_it_is_and_how_to_name_one(tmp_path):
    with pytest.raises(RobotFileError) as caught:
        read_robot_file(tmp_path / "arm.yaml")
    assert str(caught.value) == (f"robot profile not found: {tmp_path / 'arm.yaml'}; give the path of a robot "
                                 f"profile YAML, e.g. {PANDA_FILE}")


def test_only_the_optional_keys_may_be_left_out(tmp_path):
    data = _panda()
    del data["kinematics"]["tool_frame"]
    assert "kinematics.tool_frame is missing" in _refusal(_write(tmp_path, data))


@pytest.mark.parametrize("low, high, ok", [(-1.0, 1.0, True), (1.0, 1.0, False), (1.5, 1.0, False)])
def test_each_joints_lowest_position_is_below_its_highest(tmp_path, low, high, ok):
    data = _panda()
    data["joints"]["position_min_rad"][6] = low
    data["joints"]["position_max_rad"][6] = high
    path = _write(tmp_path, data)
    if ok:
        assert read_robot_file(path)["joints"]["position_min_rad"][6] == low
    else:
        assert f"joint 7: position_min_rad {low:g} must be below position_max_rad {high:g}" in _refusal(path)


# --- which profile: a name, a path, HRI_ROBOT -------------------------------------------------------------------


@pytest.mark.parametrize("value, expected", [
    ("fr3", ROBOTS_DIR / "fr3.yaml"),
    ("  fr3 ", ROBOTS_DIR / "fr3.yaml"),
    ("arm.yaml", Path("arm.yaml")),
    ("arm.yml", Path("arm.yml")),
    ("robots/arm", Path("robots/arm")),
    ("/abs/arm.yaml", Path("/abs/arm.yaml")),
])
def test_a_profile_is_named_by_its_name_or_its_path(value, expected):
    assert robot_path(value) == expected


def test_a_path_may_start_at_the_home_folder(monkeypatch, tmp_path):
    monkeypatch.setenv("HOME", str(tmp_path))
    assert robot_path("~/arm.yaml") == tmp_path / "arm.yaml"


@pytest.mark.parametrize("value", [None, "", "   "])
def test_hri_robot_unset_or_blank_is_the_panda(monkeypatch, value):
    if value is None:
        monkeypatch.delenv(ROBOT_ENV, raising=False)
    else:
        monkeypatch.setenv(ROBOT_ENV, value)
    assert lab_robot_path() == PANDA_FILE


def test_hri_robot_names_a_shipped_profile_or_a_file(monkeypatch, tmp_path):
    monkeypatch.setenv(ROBOT_ENV, " fr3 ")
    assert lab_robot_path() == FR3_FILE
    own = _write(tmp_path, _panda())
    monkeypatch.setenv(ROBOT_ENV, str(own))
    assert lab_robot_path() == own


@pytest.mark.parametrize("value", ["ur5", "robots"])
def test_hri_robot_naming_no_profile_file_is_refused_naming_the_shipped_ones(monkeypatch, value):
    monkeypatch.setenv(ROBOT_ENV, value)
    with pytest.raises(RobotFileError) as caught:
        lab_robot_path()
    assert str(caught.value) == (f"HRI_ROBOT={value}: no such robot profile ({ROBOTS_DIR / (value + '.yaml')}); "
                                 "name one of fr3, franka_panda or give the path of a profile YAML")


def test_a_folder_is_no_profile(monkeypatch, tmp_path):
    monkeypatch.setenv(ROBOT_ENV, str(tmp_path) + "/")
    with pytest.raises(RobotFileError, match="no such robot profile"):
        lab_robot_path()


@pytest.fixture
def fresh_lab_robot(monkeypatch):
    """lab_robot_file() read again under the test's HRI_ROBOT, and the suite's (the Panda's) after it."""
    lab_robot_file.cache_clear()
    yield monkeypatch
    monkeypatch.delenv(ROBOT_ENV, raising=False)
    lab_robot_file.cache_clear()


def test_the_lab_robot_file_is_the_pandas_read_once_or_the_one_hri_robot_names(fresh_lab_robot, tmp_path):
    fresh_lab_robot.setenv(ROBOT_ENV, "franka_panda")
    assert lab_robot_file() is panda_file()
    lab_robot_file.cache_clear()
    fresh_lab_robot.setenv(ROBOT_ENV, "fr3")
    assert lab_robot_file()["name"] == "fr3"
    lab_robot_file.cache_clear()
    fresh_lab_robot.setenv(ROBOT_ENV, str(_write(tmp_path, {**_panda(), "name": "copy"})))
    assert lab_robot_file()["name"] == "copy"  # the Panda's numbers in another file: that file, read


def test_the_pandas_file_is_read_once():
    assert panda_file() is panda_file() and panda_file()["name"] == "franka_panda"
    assert robot_file.PANDA_FILE.name == "franka_panda.yaml"


# --- the typed profile (hri_teleop.core.robot) --------------------------------------------------------------


def test_the_typed_profile_holds_every_value_of_its_file():
    data = yaml.safe_load(FR3_FILE.read_text())
    fr3 = load_robot_profile(FR3_FILE)
    assert (fr3.name, fr3.description, fr3.path) == ("fr3", data["description"], str(FR3_FILE))
    limits = data["cartesian_limits"]
    assert (fr3.cartesian_limits.translation.velocity, fr3.cartesian_limits.translation.jerk) == (
        limits["translation"]["velocity"], limits["translation"]["jerk"])
    assert fr3.cartesian_limits.rotation.acceleration == limits["rotation"]["acceleration"]
    joints = data["joints"]
    assert fr3.joint_names == tuple(joints["names"]) and fr3.ready_pose_rad == tuple(joints["ready_pose_rad"])
    for key in ("position_min_rad", "position_max_rad", "velocity_rad_per_s", "acceleration_rad_per_s2",
                "jerk_rad_per_s3"):
        assert getattr(fr3.joint_limits, key) == tuple(joints[key]), key
    kin = data["kinematics"]
    assert (fr3.urdf, fr3.tool_frame, fr3.elbow_joint) == (kin["urdf"], kin["tool_frame"], kin["elbow_joint"])
    assert fr3.urdf_joint_names == tuple(kin["urdf_joint_names"])
    assert fr3.urdf_finger_joints == tuple(kin["urdf_finger_joints"])
    grip = data["gripper"]
    assert fr3.gripper == GripperProfile(grip["namespace"], tuple(grip["actions"]), tuple(grip["finger_joints"]),
                                         grip["max_width_m"], grip["max_speed_m_per_s"], grip["max_force_n"])
    assert fr3.topics == {k: v for k, v in data["topics"].items() if k != "source"}
    assert fr3.cartesian_errors == data["errors"]["cartesian"] and fr3.joint_errors == data["errors"]["joint"]
    assert fr3.non_finite_error == data["errors"]["non_finite"]
    assert fr3.sources == {s: data[s]["source"] for s in ("cartesian_limits", "joints", "kinematics", "gripper",
                                                          "topics", "errors")}


def test_a_profile_built_from_a_file_has_no_path_unless_given():
    from hri_teleop.core.robot import RobotProfile

    assert RobotProfile.from_file(read_robot_file(PANDA_FILE)).path == ""


def test_the_hand_numbers_are_kept_apart(tmp_path):
    data = _panda()
    data["gripper"].update({"max_width_m": 0.07, "max_speed_m_per_s": 0.05, "max_force_n": 60.0})
    hand = load_robot_profile(_write(tmp_path, data)).gripper
    assert (hand.max_width_m, hand.max_speed_m_per_s, hand.max_force_n) == (0.07, 0.05, 60.0)


def test_robot_none_or_the_lab_robots_name_is_the_lab_robot_itself():
    assert robot_named(None) is LAB_ROBOT and robot_named("franka_panda") is LAB_ROBOT
    assert robot_named(str(PANDA_FILE)) is LAB_ROBOT


def test_robot_naming_another_profile_loads_it(tmp_path):
    assert robot_named("fr3").name == "fr3" and robot_named(" fr3 ").path == str(FR3_FILE)
    own = _write(tmp_path, {**_panda(), "name": "copy"})
    assert robot_named(str(own)).name == "copy"


@pytest.mark.parametrize("value", ["", "  ", 3, ["fr3"]])
def test_robot_that_is_not_a_name_is_refused_in_one_line(value):
    with pytest.raises(RobotFileError) as caught:
        robot_named(value)
    assert str(caught.value) == ("robot must be a profile's name (e.g. franka_panda, fr3) or a path to one, "
                                 f"got {value!r}")
