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
    Start,
    decide_mode,
    default_pad,
    describe,
    duplicate_refusal,
    ignored_setting,
    mode_from_env,
    pad_params,
    simulation_refusal,
    start_refusal,
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


@pytest.mark.parametrize("env", [{}, {"HRI_MODE": "home"}, {"HRI_MODE": "grading"}, {"HRI_MODE": "lab"},
                                 {"NBGRADER_EXECUTION": "autograde"}])
def test_a_master_this_process_did_not_start_is_the_lab_whatever_is_set(env):
    assert decide_mode(env, own_master=False) == LAB


@pytest.mark.parametrize("env, expected", [
    ({}, HOME),
    ({"HRI_MODE": "lab"}, LAB),
    ({"HRI_MODE": "grading"}, GRADING),
    ({"NBGRADER_EXECUTION": "autograde"}, GRADING),
])
def test_on_its_own_master_a_process_is_at_home_unless_asked_otherwise(env, expected):
    assert decide_mode(env, own_master=True) == expected


def test_a_setting_that_asks_for_less_care_on_a_foreign_master_is_named_as_ignored():
    note = ignored_setting({"HRI_MODE": "home"}, own_master=False)
    assert note is not None and note.startswith("HRI_MODE=home is ignored") and "\n" not in note
    assert ignored_setting({"HRI_MODE": "home"}, own_master=True) is None
    assert ignored_setting({"HRI_MODE": "lab"}, own_master=False) is None
    assert ignored_setting({}, own_master=False) is None


SIM = Start("the simulated board (FSR_sensor.py)", simulated=True)
SCRIPTED = Start("teleoperation.py", pad="virtual")
REAL_PAD = Start("teleoperation.py", pad="pygame")
PLAIN = Start("mapping_node.py")


@pytest.mark.parametrize("start", [SIM, SCRIPTED, REAL_PAD, PLAIN])
@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_at_home_on_its_own_master_everything_starts(mode, start):
    assert start_refusal(mode, start, [], own_master=True) is None


@pytest.mark.parametrize("start", [SIM, SCRIPTED])
def test_on_a_foreign_master_nothing_simulated_or_scripted_starts(start):
    refusal = start_refusal(LAB, start, [], own_master=False)
    assert refusal is not None and refusal.startswith(f"refused to start {start.what}")
    assert "not started by this process" in refusal and "\n" not in refusal


@pytest.mark.parametrize("start", [REAL_PAD, PLAIN])
def test_on_a_foreign_master_a_node_with_a_real_pad_and_a_plain_node_start(start):
    assert start_refusal(LAB, start, [], own_master=False) is None
    assert start_refusal(LAB, start, ["/franka_control"], own_master=False) is None


def test_the_scripted_pad_refusal_says_to_pick_the_real_pad():
    refusal = start_refusal(LAB, SCRIPTED, [], own_master=False)
    assert refusal is not None and 'set PAD = "pygame"' in refusal


@pytest.mark.parametrize("start", [SIM, SCRIPTED])
@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_next_to_real_hardware_even_on_its_own_master_nothing_simulated_or_scripted_starts(mode, start):
    refusal = start_refusal(mode, start, ["/serial_node"], own_master=True)
    assert refusal is not None and "this master runs real hardware (/serial_node)" in refusal


@pytest.mark.parametrize("start", [SIM, SCRIPTED])
def test_lab_mode_asked_for_on_its_own_master_refuses_too(start):
    refusal = start_refusal(LAB, start, [], own_master=True)
    assert refusal is not None and "HRI_MODE=lab" in refusal


def test_the_default_pad_is_the_real_one_in_the_lab_only():
    assert default_pad(LAB) == "pygame"
    assert default_pad(HOME) == "virtual"
    assert default_pad(GRADING) == "virtual"


def test_under_grading_the_script_plays_even_when_the_student_picked_the_real_pad():
    assert pad_params("pygame", "/tmp/drive.yaml", GRADING) == {"pad": "virtual", "pad_script": "/tmp/drive.yaml"}
    assert pad_params("pygame", "/tmp/drive.yaml", HOME) == {"pad": "pygame"}
    assert pad_params("pygame", None, GRADING) == {"pad": "pygame"}


def test_the_lab_line_of_a_foreign_master_says_nothing_simulated_starts():
    assert "nothing simulated or scripted is started" in describe(LAB, own_master=False)
    assert describe(HOME).startswith("home mode")


def test_ipython_shows_a_mode_error_as_its_one_line():
    assert ModeError("x")._render_traceback_() == ["ModeError: x"]


@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_at_home_and_under_grading_the_simulation_may_start_on_a_master_without_hardware(mode):
    assert simulation_refusal(mode, "board", ["/rosout", "/teleoperation", "/lab_sim"]) is None


def test_in_the_lab_no_simulation_starts_even_before_the_hardware_is_up():
    refusal = simulation_refusal(LAB, "board (FSR_sensor.py)", [], own_master=False)
    assert refusal is not None and refusal.startswith("refused to start board (FSR_sensor.py): it is simulated")
    assert "\n" not in refusal


@pytest.mark.parametrize("node", HARDWARE_NODES)
@pytest.mark.parametrize("mode", [HOME, GRADING])
def test_next_to_real_hardware_no_simulation_starts_whatever_the_mode(mode, node):
    refusal = simulation_refusal(mode, "robot", ["/rosout", node])
    assert refusal is not None and f"this master runs real hardware ({node})" in refusal


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


BROWSER = Start("teleoperation.py", pad="browser")


def test_a_browser_pad_starts_at_home_and_is_refused_in_the_lab_and_beside_real_hardware():
    assert start_refusal(HOME, BROWSER, [], own_master=True) is None
    for refusal in (start_refusal(LAB, BROWSER, [], own_master=False),
                    start_refusal(LAB, BROWSER, ["/franka_control"], own_master=False),
                    start_refusal(HOME, BROWSER, ["/franka_control"], own_master=True)):
        assert refusal is not None and "with the browser pad" in refusal and 'set PAD = "pygame"' in refusal


def test_the_browser_pad_gets_no_script_and_under_grading_the_script_plays():
    assert pad_params("browser", "/tmp/drive.yaml", HOME) == {"pad": "browser"}
    assert pad_params("browser", None, HOME) == {"pad": "browser"}
    assert pad_params("browser", "/tmp/drive.yaml", GRADING) == {"pad": "virtual", "pad_script": "/tmp/drive.yaml"}
