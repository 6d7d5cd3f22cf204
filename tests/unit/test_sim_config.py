"""The simulation settings: sim.yaml loads to the defaults, layers override, every mistake is one line."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.attachment import Attachment
from hri_teleop.sim.board import HANDOUT_FIRMWARE_RATE_HZ, BoardConfig
from hri_teleop.sim.config import (
    PARAM_ALIASES,
    SECTION_KEYS,
    TOP_KEYS,
    SimConfigError,
    default_sim_yaml,
    describe,
    load_world_config,
    scenario_world_overrides,
    world_config_from_dict,
    world_overrides_from_params,
)
from hri_teleop.sim.grasp_objects import OBJECTS, GraspObject
from hri_teleop.sim.hand_params import HandParams
from hri_teleop.sim.world import LAB_ARM_CONFIG, ROBOT_HAND_KEYS, LabWorld, WorldConfig

REPO = Path(__file__).resolve().parents[2]
SIM_YAML = REPO / "hri_lab" / "config" / "sim.yaml"
SCENARIOS = REPO / "hri_lab" / "scenarios"
NODE_KEYS = ("config", "scenario", "board", "twist_topic")


def one_line(info) -> str:
    message = str(info.value)
    assert "\n" not in message, message
    return message


def write(tmp_path: Path, name: str, data) -> Path:
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else yaml.safe_dump(data))
    return path


# --- the lab's file ----------------------------------------------------------------------


def test_lab_sim_yaml_is_the_dataclass_defaults_plus_its_object():
    raw = yaml.safe_load(SIM_YAML.read_text())
    config = load_world_config(SIM_YAML)
    assert config == WorldConfig(object=OBJECTS[raw["object"]])
    assert config.arm == LAB_ARM_CONFIG
    assert config.board == BoardConfig()


def test_lab_sim_yaml_spells_out_every_setting():
    raw = yaml.safe_load(SIM_YAML.read_text())
    assert set(raw) == set(TOP_KEYS)
    for section, keys in SECTION_KEYS.items():
        from_robot = set(ROBOT_HAND_KEYS) if section == "hand" else set()  # the robot profile's gripper range
        assert set(raw[section]) == set(keys) - from_robot, section


def test_default_sim_yaml_finds_the_lab_file_in_a_checkout():
    assert default_sim_yaml() == SIM_YAML


def test_an_empty_file_is_the_default_world_without_an_object(tmp_path):
    assert load_world_config(write(tmp_path, "empty.yaml", "")) == WorldConfig()
    assert load_world_config("") == WorldConfig()


def test_describe_names_the_object_and_the_board():
    line = describe(load_world_config(SIM_YAML))
    assert "egg" in line and "100 Hz" in line and "\n" not in line
    assert "no object" in describe(WorldConfig())


# --- every key reaches its field -----------------------------------------------------------


@pytest.mark.parametrize("data, read", [
    ({"table_z_m": -0.01}, lambda c: c.table_z_m == -0.01),
    ({"capture_radius_m": 0.02}, lambda c: c.capture_radius_m == 0.02),
    ({"object_xy_m": [0.4, 0.1]}, lambda c: c.object_xy_m == (0.4, 0.1)),
    ({"arm": {"timeout_s": 0.25}}, lambda c: c.arm.timeout_s == 0.25),
    ({"arm": {"start_position_m": [0.4, 0.0, 0.03]}}, lambda c: c.arm.start_position_m == (0.4, 0.0, 0.03)),
    ({"arm": {"workspace_max_m": [0.6, 0.3, 0.5]}}, lambda c: c.arm.workspace_max_m == (0.6, 0.3, 0.5)),
    ({"arm": {"controller": "hold"}}, lambda c: c.arm.controller == "hold"),
    # pointing down, turned 0.3 rad about the base's z axis
    ({"arm": {"start_orientation_xyzw": [0.98877108, 0.14943813, 0.0, 0.0]}},
     lambda c: c.arm.start_orientation_xyzw == pytest.approx((0.98877108, 0.14943813, 0.0, 0.0), abs=1e-8)),
    ({"hand": {"initial_width_m": 0.05}}, lambda c: c.hand.initial_width_m == 0.05),
    ({"hand": {"homing_force_n": 5}}, lambda c: c.hand.homing_force_n == 5.0),
    ({"attachment": {"piston_travel_m": 0.004}}, lambda c: c.attachment.piston_travel_m == 0.004),
    ({"attachment": {"spring_n_per_m": 400.0}}, lambda c: c.attachment.full_travel_force_n == pytest.approx(1.2)),
    ({"board": {"rate_hz": 3.333}}, lambda c: c.board.period_s == pytest.approx(0.3, abs=1e-4)),
    ({"board": {"noise_counts": 0}}, lambda c: c.board.noise_counts == 0.0),
    ({"board": {"seed": None}}, lambda c: c.board.seed is None),
    ({"board": {"seed": 7}}, lambda c: c.board.seed == 7),
])
def test_each_key_sets_its_field_and_leaves_the_rest_at_the_defaults(data, read):
    config = world_config_from_dict(data, "test")
    assert read(config)
    default = WorldConfig()
    changed = {name for name in ("arm", "hand", "attachment", "board", "table_z_m", "capture_radius_m",
                                 "object_xy_m") if getattr(config, name) != getattr(default, name)}
    assert changed == {next(iter(data))}


def test_the_handout_firmware_rate_is_one_sample_per_300_ms():
    config = world_config_from_dict({"board": {"rate_hz": HANDOUT_FIRMWARE_RATE_HZ}})
    world = LabWorld(config)
    samples = world.advance(3.0)
    times = [t for t, _ in samples]
    assert len(times) == 11  # the first cycle, then t = 0.3, 0.6, ..., 3.0
    assert [b - a for a, b in zip(times[1:], times[2:])] == pytest.approx([0.3] * 9)


@pytest.mark.parametrize("name", sorted(OBJECTS))
def test_objects_by_name(name):
    assert world_config_from_dict({"object": name}).object is OBJECTS[name]


@pytest.mark.parametrize("value", ["none", "None", None])
def test_none_means_nothing_to_grasp(value):
    assert world_config_from_dict({"object": value}).object is None


def test_a_custom_object_from_its_fields():
    config = world_config_from_dict({"object": {
        "name": "cup", "width_m": 0.06, "stiffness_n_per_m": 2.0e4, "mass_kg": 0.1,
        "friction_coefficient": 0.5, "breaking_force_n": None, "note": "paper cup"}})
    assert config.object == GraspObject("cup", 0.06, 2.0e4, 0.1, 0.5, None, "paper cup")


def test_a_custom_object_without_a_name_is_called_custom():
    config = world_config_from_dict({"object": {"width_m": 0.03, "stiffness_n_per_m": 1000.0, "mass_kg": 0.01,
                                                "friction_coefficient": 0.5, "breaking_force_n": 5}})
    assert config.object.name == "custom" and config.object.breaking_force_n == 5.0


# --- mistakes: one line, the file, the key, the fix ---------------------------------------


@pytest.mark.parametrize("data, expected", [
    ({"objcet": "egg"}, ["unknown key 'objcet'", "did you mean 'object'"]),
    ({"board": {"rat_hz": 3}}, ["unknown key 'board.rat_hz'", "did you mean 'rate_hz'"]),
    ({"arm": {"limits": {}}}, ["unknown key 'arm.limits'", "timeout_s"]),
    ({"hand": {"width": 0.05}}, ["unknown key 'hand.width'", "initial_width_m"]),
    ({"object": "eg"}, ["unknown object 'eg'", "did you mean 'egg'", "sponge"]),
    ({"object": {"name": "cup", "width_m": 0.06}}, ["custom object needs stiffness_n_per_m", "mass_kg"]),
    ({"object": {"width_m": 0.06, "stiffness_n_per_m": 1.0, "mass_kg": 0.1, "friction_coefficient": 0.5,
                 "colour": "red"}}, ["unknown key 'object.colour'"]),
    ({"object": 3}, ["object must be a name", "egg"]),
    ({"object": {"width_m": -0.06, "stiffness_n_per_m": 1.0, "mass_kg": 0.1, "friction_coefficient": 0.5}},
     ["object.width_m must be > 0", "e.g."]),
    ({"arm": {"timeout_s": "0.1"}}, ["arm.timeout_s must be a number", "'0.1'", "without quotes"]),
    ({"arm": {"timeout_s": True}}, ["arm.timeout_s must be a number", "bool"]),
    ({"arm": {"timeout_s": 0}}, ["arm.timeout_s must be a positive number", "e.g. 0.1"]),
    ({"arm": {"start_position_m": [0.3, 0.0]}}, ["arm.start_position_m must be a list of 3 numbers",
                                                 "[0.4, 0.0, 0.4867]"]),
    ({"arm": {"start_position_m": [0.9, 0.0, 0.3]}}, ["arm.start_position_m x = 0.9 m is outside the workspace",
                                                      "widen the box"]),
    ({"arm": {"workspace_min_m": [0.9, -0.5, 0.015]}}, ["arm: workspace x: min 0.9 m must be below max",
                                                        "swap or widen"]),
    ({"arm": {"start_orientation_xyzw": [1, 1, 0, 0]}}, ["unit quaternion"]),
    ({"arm": {"start_orientation_xyzw": [0, 0, 0, 1]}}, ["arm.start_position_m", "out of the Panda's reach",
                                                          "nearer the ready pose"]),
    ({"arm": {"controller": "smooth"}}, ["controller must be one of interpolate, hold"]),
    ({"arm": 0.1}, ["arm must be a mapping", "arm: {start_position_m"]),
    ({"hand": {"initial_width_m": 0.1}}, ["hand.initial_width_m must lie in 0 .. 0.08 m", "fully open"]),
    ({"hand": {"move_force_n": 80}}, ["hand.move_force_n", "max_force_n", "lower them"]),
    ({"attachment": {"spring_n_per_m": "1e6"}}, ["attachment.spring_n_per_m must be a number",
                                                 "1.0e+6"]),
    ({"attachment": {"piston_travel_m": 0}}, ["attachment.piston_travel_m must be > 0", "3 mm"]),
    ({"board": {"rate_hz": 0}}, ["board.rate_hz must be in (0, 1000] Hz", "3.333 (the handout's 300 ms)"]),
    ({"board": {"noise_counts": -1}}, ["board.noise_counts must be in [0, 50]"]),
    ({"board": {"seed": 1.5}}, ["board.seed must be an integer or null"]),
    ({"capture_radius_m": 0}, ["capture_radius_m must be a positive distance", "e.g. 0.01"]),
    ({"object_xy_m": [0.3, "a"]}, ["object_xy_m must be a list of 2 numbers"]),
    ({"table_z_m": 0.05}, ["table top (0.05 m) is above the workspace floor", "lower the table"]),
])
def test_a_mistake_is_one_line_naming_the_file_the_key_and_the_fix(tmp_path, data, expected):
    path = write(tmp_path, "my_sim.yaml", data)
    with pytest.raises(SimConfigError) as info:
        load_world_config(path)
    message = one_line(info)
    assert message.startswith(f"{path}: "), message
    for text in expected:
        assert text in message, message


def test_a_yaml_syntax_error_names_the_line(tmp_path):
    path = write(tmp_path, "broken.yaml", "object: egg\nboard:\n  rate_hz: [100\n")
    with pytest.raises(SimConfigError) as info:
        load_world_config(path)
    message = one_line(info)
    assert message.startswith(f"{path}:") and "fix the YAML syntax" in message


def test_a_missing_file_and_a_list_are_refused(tmp_path):
    with pytest.raises(SimConfigError, match="file not found: .*nope.yaml; check the path"):
        load_world_config(tmp_path / "nope.yaml")
    with pytest.raises(SimConfigError, match="not a mapping"):
        load_world_config(write(tmp_path, "list.yaml", [1, 2]))


# --- layers: sim.yaml < scenario world: < private parameters ------------------------------


def test_a_scenario_world_overrides_the_file(tmp_path):
    scenario = write(tmp_path, "scenario.yaml", {"description": "x", "world": {"object": "sponge",
                                                                             "board": {"rate_hz": 50.0}},
                                                 "steps": [{"t": 1.0, "press": "south"}]})
    config = load_world_config(SIM_YAML, scenario=scenario)
    assert config.object is OBJECTS["sponge"]
    assert config.board == BoardConfig(rate_hz=50.0)  # the rest of board stays the file's


def test_the_lab_scenarios_load_over_sim_yaml():
    for scenario in sorted(SCENARIOS.glob("*.yaml")):
        assert isinstance(load_world_config(SIM_YAML, scenario=scenario), WorldConfig), scenario


def test_a_scenario_without_world_or_a_plain_pad_script_changes_nothing(tmp_path):
    for data in ({"description": "only steps", "steps": []}, [{"t": 1.0, "press": "south"}], ""):
        scenario = write(tmp_path, "s.yaml", data)
        assert scenario_world_overrides(scenario) == {}
        assert load_world_config(SIM_YAML, scenario=scenario) == load_world_config(SIM_YAML)


def test_a_mistake_in_a_scenario_names_the_scenario_not_sim_yaml(tmp_path):
    scenario = write(tmp_path, "bad_scenario.yaml", {"world": {"board": {"rate_hz": -5}}})
    with pytest.raises(SimConfigError) as info:
        load_world_config(SIM_YAML, scenario=scenario)
    message = one_line(info)
    assert message.startswith(f"{scenario} (world:): board.rate_hz"), message
    scenario = write(tmp_path, "bad_world.yaml", {"world": ["egg"]})
    with pytest.raises(SimConfigError, match="world must be a mapping of sim.yaml keys"):
        load_world_config(SIM_YAML, scenario=scenario)


def test_parameters_override_the_scenario_which_overrides_the_file(tmp_path):
    scenario = write(tmp_path, "s.yaml", {"world": {"object": "sponge", "board": {"rate_hz": 50.0}}})
    overrides = world_overrides_from_params({"object": "block", "noise_counts": 0.0}, "/lab_sim", NODE_KEYS)
    config = load_world_config(SIM_YAML, overrides, "/lab_sim", scenario=scenario)
    assert config.object is OBJECTS["block"]
    assert config.board == BoardConfig(rate_hz=50.0, noise_counts=0.0)


def test_parameter_aliases_set_one_key_of_a_section():
    overrides = world_overrides_from_params(
        {"board_rate_hz": 3.333, "noise_counts": 2.0, "board_seed": 3, "arm_timeout_s": 0.2,
         "initial_width_m": 0.05, "arm": {"timeout_s": 0.5, "start_position_m": [0.3, 0.0, 0.3]},
         "config": "/x.yaml", "board": False}, "/lab_sim", NODE_KEYS)
    assert overrides == {"board": {"rate_hz": 3.333, "noise_counts": 2.0, "seed": 3},
                         "arm": {"timeout_s": 0.2, "start_position_m": [0.3, 0.0, 0.3]},
                         "hand": {"initial_width_m": 0.05}}
    config = world_config_from_dict(overrides)
    assert config.arm.timeout_s == 0.2 and config.hand == HandParams(initial_width_m=0.05)
    assert set(PARAM_ALIASES) == {"board_rate_hz", "noise_counts", "board_seed", "arm_timeout_s", "initial_width_m"}


def test_an_unknown_parameter_is_a_typo_with_the_closest_name():
    with pytest.raises(SimConfigError) as info:
        world_overrides_from_params({"board_rate": 10}, "/lab_sim private parameters", NODE_KEYS)
    message = one_line(info)
    assert "unknown parameter ~board_rate; did you mean ~board_rate_hz?" in message
    assert "~scenario" in message and "~noise_counts" in message


def test_a_bad_parameter_names_the_parameters_not_the_file():
    overrides = world_overrides_from_params({"board_rate_hz": 0}, "/lab_sim private parameters", NODE_KEYS)
    with pytest.raises(SimConfigError) as info:
        load_world_config(SIM_YAML, overrides, "/lab_sim private parameters")
    assert one_line(info).startswith("/lab_sim private parameters: board.rate_hz must be in (0, 1000]")


def test_a_cross_check_names_every_layer_involved():
    overrides = {"table_z_m": 0.03}  # above sim.yaml's workspace floor
    with pytest.raises(SimConfigError) as info:
        load_world_config(SIM_YAML, overrides, "/lab_sim private parameters")
    assert one_line(info).startswith(f"{SIM_YAML} and /lab_sim private parameters: the table top")


def test_the_file_wins_nothing_it_does_not_set():
    """A layer replaces only the keys it names: hand speed from the file, width from a parameter."""
    config = world_config_from_dict({"hand": {"max_speed_m_per_s": 0.05, "homing_speed_m_per_s": 0.02}})
    assert dataclasses.replace(config.hand, max_speed_m_per_s=0.1, homing_speed_m_per_s=0.05) == HandParams()
    assert config.attachment == Attachment()
