"""Home, lab and grading: which mode a notebook is in, and what it may start there."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.modes import (
    GRADING,
    HARDWARE_NODES,
    HOME,
    LAB,
    ModeError,
    duplicate_refusal,
    mode_from_env,
    pad_params,
    simulation_refusal,
)


@pytest.mark.parametrize("env, expected", [
    ({}, HOME),
    ({"HRI_MODE": "lab"}, LAB),
    ({"HRI_MODE": " Lab "}, LAB),
    ({"HRI_MODE": "home", "NBGRADER_EXECUTION": "autograde"}, HOME),   # an explicit mode wins
    ({"NBGRADER_EXECUTION": "autograde"}, GRADING),
    ({"NBGRADER_EXECUTION": ""}, HOME),
    ({"HRI_MODE": ""}, HOME),
])
def test_the_mode_is_hri_mode_else_grading_under_nbgrader_else_home(env, expected):
    assert mode_from_env(env) == expected


def test_an_unknown_mode_is_one_line_naming_the_three():
    with pytest.raises(ModeError, match="HRI_MODE='labs' is not a mode: set it to home, lab or grading"):
        mode_from_env({"HRI_MODE": "labs"})


def test_ipython_shows_a_mode_error_as_its_one_line():
    assert ModeError("x")._render_traceback_() == ["ModeError: x"]


@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_at_home_and_under_grading_the_simulation_may_start_on_a_master_without_hardware(mode):
    assert simulation_refusal(mode, "board", ["/rosout", "/teleoperation", "/lab_sim"]) is None


def test_in_the_lab_no_simulation_starts_even_before_the_hardware_is_up():
    refusal = simulation_refusal(LAB, "board (FSR_sensor.py)", [])
    assert refusal is not None and refusal.startswith("lab mode: no simulated board (FSR_sensor.py)")
    assert "\n" not in refusal


@pytest.mark.parametrize("node", HARDWARE_NODES)
@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_next_to_real_hardware_no_simulation_starts_whatever_the_mode(mode, node):
    refusal = simulation_refusal(mode, "robot", ["/rosout", node])
    assert refusal is not None and node in refusal and "HRI_MODE=lab" in refusal


def test_a_running_name_refuses_a_second_node_and_says_how_to_stop_it():
    refusal = duplicate_refusal(["teleoperation"], ["/rosout", "/teleoperation"])
    assert refusal is not None
    assert refusal.startswith("/teleoperation already running") and "rosnode kill /teleoperation" in refusal


def test_names_that_do_not_run_start():
    assert duplicate_refusal(["/teleoperation", "/mapping_node"], ["/rosout", "/teleoperation_2"]) is None
    assert duplicate_refusal([], ["/teleoperation"]) is None


@given(st.lists(st.from_regex(r"/?[a-z][a-z_]{0,8}", fullmatch=True), max_size=5),
       st.lists(st.from_regex(r"/[a-z][a-z_]{0,8}", fullmatch=True), max_size=5))
def test_a_refusal_comes_exactly_when_a_wanted_name_runs(wanted, running):
    absolute = {w if w.startswith("/") else "/" + w for w in wanted}
    assert (duplicate_refusal(wanted, running) is not None) == bool(absolute & set(running))


def test_a_real_pad_gets_no_script_and_the_virtual_pad_gets_its_script():
    assert pad_params("pygame", "/tmp/drive.yaml") == {"pad": "pygame"}
    assert pad_params("virtual", "/tmp/drive.yaml") == {"pad": "virtual", "pad_script": "/tmp/drive.yaml"}
    assert pad_params("virtual") == {"pad": "virtual"}


def test_an_unknown_pad_is_one_line_naming_both():
    with pytest.raises(ModeError, match="pad='joystick' is not a gamepad: use 'virtual'"):
        pad_params("joystick")
