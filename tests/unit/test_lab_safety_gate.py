"""The lab's safety gate: on the lab's master, or next to real hardware, nothing simulated or scripted starts.

Each case is one start a notebook makes (a launch's nodes, a student's node with its parameters) on a master
described as it answers (this kernel's or not, reachable or not, which nodes run), through the gate every
start goes through (course.master_mode.start_refusal). The lab's facts are written as the lab has them: the
hardware nodes are /serial_node (the Arduino's rosserial), /franka_control and /franka_gripper.
"""

from __future__ import annotations

from typing import List, Optional, Sequence

import pytest

from hri_teleop.core.modes import (
    GRADING,
    HOME,
    LAB,
    Start,
    describe,
    ignored_setting,
    simulation_refusal,
    start_refusal,
)
from hri_teleop.course import master_mode as gate
from hri_teleop.course.nodes import launch_starts, node_start
from hri_teleop.ros.launch_inspect import LaunchedNode
from hri_teleop.ros.master_api import MasterApiError

URI = "http://localhost:11411"
MAPPING = LaunchedNode("/mapping_node", "hri_lab", "mapping_node.py")
BOARD = LaunchedNode("/FSR_sensor", "hri_lab", "FSR_sensor.py")
SIM_ARM = LaunchedNode("/lab_sim", "hri_lab", "lab_sim.py")


@pytest.fixture
def master(monkeypatch):
    """Describe the kernel's master: ``own`` (this kernel started it), ``reachable``, the nodes ``running``
    (None: the master cannot list them), and ``HRI_MODE``. The gate asks the master which of the nodes it
    names run, as the real master API does."""

    def describe_master(own: bool = False, reachable: bool = True, running: Optional[Sequence[str]] = (),
                        hri_mode: Optional[str] = None) -> None:
        def running_nodes(among: Sequence[str], uri: Optional[str] = None) -> List[str]:
            if running is None:
                raise MasterApiError("the master does not answer getSystemState")
            if uri != URI:  # another master (the environment's, say) runs nothing of the lab's
                return []
            return [name for name in among if name in running]

        monkeypatch.setattr(gate, "started_here", lambda uri: own and uri == URI)
        monkeypatch.setattr(gate, "master_reachable", lambda uri: reachable and uri == URI)
        monkeypatch.setattr(gate, "running_nodes", running_nodes)
        monkeypatch.delenv("NBGRADER_EXECUTION", raising=False)
        if hri_mode is None:
            monkeypatch.delenv("HRI_MODE", raising=False)
        else:
            monkeypatch.setenv("HRI_MODE", hri_mode)

    return describe_master


# --- a launch is judged node by node ---------------------------------------------------------------------------

def test_a_launch_that_lists_the_simulated_board_after_the_mapping_node_is_refused_on_the_labs_master(master):
    """A student's sensor.launch with mapping_node first: the board behind it would press the real /pub_force."""
    master(own=False)
    refusal = gate.start_refusal(launch_starts([MAPPING, BOARD], "sensor.launch"), URI)
    assert refusal is not None and "FSR_sensor.py" in refusal and "refused" in refusal


def test_a_launch_whose_last_node_is_the_simulated_arm_is_refused_next_to_the_real_gripper(master):
    master(own=True, running=["/rosout", "/franka_gripper"])
    refusal = gate.start_refusal(launch_starts([MAPPING, SIM_ARM], "teleoperation.launch"), URI)
    assert refusal is not None and "lab_sim.py" in refusal and "/franka_gripper" in refusal


def test_a_launch_of_plain_nodes_only_starts_on_the_labs_master(master):
    master(own=False)
    assert gate.start_refusal(launch_starts([MAPPING, MAPPING], "sensor.launch"), URI) is None


def test_nothing_to_start_is_never_refused(master):
    master(own=False, running=["/franka_control"])
    assert gate.start_refusal([], URI) is None


# --- which master is the lab's ---------------------------------------------------------------------------------

@pytest.mark.parametrize("hardware", ["/serial_node", "/franka_control", "/franka_gripper"])
def test_each_hardware_node_alone_makes_the_kernels_own_master_refuse_the_simulation(master, hardware):
    master(own=True, running=["/rosout", hardware])
    refusal = gate.start_refusal([Start("lab_sim.py", simulated=True)], URI)
    assert refusal is not None and hardware in refusal


def test_the_kernels_own_master_without_hardware_starts_the_simulation(master):
    master(own=True, running=["/rosout", "/mapping_node", "/franka_gripper_sim"])
    assert gate.start_refusal([Start("lab_sim.py", simulated=True)], URI) is None


def test_a_master_that_cannot_list_its_nodes_is_judged_by_whose_it_is(master):
    master(own=True, running=None)
    assert gate.master_mode(URI) == gate.MasterMode(HOME, True, [])
    assert gate.start_refusal([Start("lab_sim.py", simulated=True)], URI) is None
    master(own=False, running=None)
    assert gate.start_refusal([Start("lab_sim.py", simulated=True)], URI) is not None


@pytest.mark.parametrize("hri_mode", [None, "home", "grading"])
def test_a_master_this_kernel_did_not_start_is_the_labs_whatever_hri_mode_says(master, hri_mode):
    master(own=False, hri_mode=hri_mode)
    state = gate.master_mode(URI)
    assert (state.mode, state.own, state.hardware) == (LAB, False, [])
    assert gate.start_refusal([Start("FSR_sensor.py", simulated=True)], URI) is not None


def test_the_master_is_asked_about_each_hardware_node_of_the_lab(master):
    master(own=False, running=["/serial_node", "/franka_control", "/franka_gripper", "/rosout"])
    assert sorted(gate.master_mode(URI).hardware) == ["/franka_control", "/franka_gripper", "/serial_node"]


@pytest.mark.parametrize("hri_mode, refused", [(None, False), ("home", False), ("grading", False), ("lab", True)])
def test_with_no_master_answering_the_setting_decides(master, hri_mode, refused):
    """Nothing can be harmed where no master runs: the kernel starts its own before it starts anything."""
    master(own=False, reachable=False, hri_mode=hri_mode)
    state = gate.master_mode(URI)
    assert state.own and state.hardware == []
    assert (gate.start_refusal([Start("lab_sim.py", simulated=True)], URI) is not None) is refused


def test_on_its_own_master_lab_mode_asked_for_refuses_and_home_starts(master):
    master(own=True, hri_mode="lab")
    assert gate.master_mode(URI).mode == LAB
    assert gate.start_refusal([Start("lab_sim.py", simulated=True)], URI) is not None
    master(own=True, hri_mode="home")
    assert gate.master_mode(URI).mode == HOME


# --- a student's node and its pad ------------------------------------------------------------------------------

@pytest.mark.parametrize("script, node, params, refused", [
    ("my_drive.py", "my_drive", {"pad": "virtual"}, True),          # a script would drive the real arm
    ("my_drive.py", "my_drive", {"pad": "virtual", "rate": 50}, True),
    ("my_drive.py", "my_drive", {"pad": "pygame"}, False),          # a person at the real pad
    ("my_drive.py", "my_drive", {"rate": 50}, False),               # reads no pad
    ("teleoperation.py", "teleoperation", {}, False),                # the lab's pad by default
    ("teleoperation.py", "teleoperation", {"pad": "virtual"}, True),
    ("drive.py", "teleoperation", {"pad": "virtual"}, True),         # renamed to the teleoperation node
    ("teleoperation.py", "drive", {"pad": "virtual"}, True),
    ("FSR_sensor.py", "FSR_sensor", {}, True),
    ("mapping_node.py", "mapping_node", {}, False),
])
def test_a_student_node_starts_on_the_labs_master_only_without_a_scripted_pad_or_a_simulation(
        master, script, node, params, refused):
    master(own=False)
    refusal = gate.start_refusal([node_start(script, node, params)], URI)
    assert (refusal is not None) is refused, refusal


@pytest.mark.parametrize("pad, refused", [(None, False), ("pygame", False), ("virtual", True)])
def test_a_launched_teleoperation_node_reads_the_real_pad_unless_its_pad_parameter_says_otherwise(master, pad, refused):
    master(own=False)
    teleop = LaunchedNode("/teleoperation", "hri_lab", "teleoperation.py", pad=pad)
    refusal = gate.start_refusal(launch_starts([MAPPING, teleop], "teleoperation.launch"), URI)
    assert (refusal is not None) is refused, refusal


# --- the rule's words where they differ by the master ------------------------------------------------------------

def test_hri_mode_grading_on_the_labs_master_is_reported_as_ignored():
    note = ignored_setting({"HRI_MODE": "grading"}, own_master=False)
    assert note is not None and note.startswith("HRI_MODE=grading is ignored")
    assert ignored_setting({"HRI_MODE": " Grading "}, own_master=False) is not None
    assert ignored_setting({"HRI_MODE": "grading"}, own_master=True) is None


def test_lab_mode_on_the_kernels_own_master_names_the_setting_and_a_foreign_master_names_the_master():
    own_words = "lab mode (HRI_MODE=lab)"
    foreign_words = "this master was not started by this process"
    assert own_words in str(start_refusal(LAB, Start("lab_sim.py", simulated=True), []))
    assert own_words in str(simulation_refusal(LAB, "lab_sim.py", []))
    assert own_words in str(simulation_refusal(LAB, "lab_sim.py", [], own_master=True))
    assert foreign_words in str(simulation_refusal(LAB, "lab_sim.py", [], own_master=False))
    assert "/franka_control" in str(simulation_refusal(HOME, "lab_sim.py", ["/franka_control"], own_master=False))


@pytest.mark.parametrize("mode, own, words", [
    (LAB, None, "the lab's master, the real robot and board"),           # describe(LAB): its own master by default
    (LAB, True, "the lab's master, the real robot and board"),
    (LAB, False, "a master this notebook did not start"),
    (HOME, False, "a private master and the simulated lab"),
    (GRADING, False, "as nbgrader runs it"),
])
def test_the_modes_line_names_a_foreign_master_only_in_the_lab(mode, own, words):
    line = describe(mode) if own is None else describe(mode, own_master=own)
    assert words in line


@pytest.mark.parametrize("own, hri_mode, words", [
    (False, None, "this master was not started by this process"),
    (True, "lab", "lab mode (HRI_MODE=lab)"),
])
def test_a_refusal_says_why_the_master_counts_as_the_labs(master, own, hri_mode, words):
    master(own=own, hri_mode=hri_mode)
    assert words in str(gate.start_refusal([Start("lab_sim.py", simulated=True)], URI))


@pytest.mark.parametrize("script, node, params, start", [
    ("teleoperation.py", "teleoperation", {}, Start("teleoperation.py (node /teleoperation)", pad="pygame")),
    ("teleoperation.py", "drive", {}, Start("teleoperation.py (node /drive)", pad="pygame")),
    ("drive.py", "/teleoperation", {}, Start("drive.py (node /teleoperation)", pad="pygame")),
    ("drive.py", "drive", {}, Start("drive.py (node /drive)")),
    ("drive.py", "Xteleoperation", {}, Start("drive.py (node /Xteleoperation)")),
    ("teleoperation_subscriber_publisher.py", "teleoperation_2", {},
     Start("teleoperation_subscriber_publisher.py (node /teleoperation_2)")),
    ("my/drive.py", "drive", {"pad": "virtual"}, Start("drive.py (node /drive)", pad="virtual")),
    ("FSR_sensor.py", "FSR_sensor", {"rate": 100}, Start("FSR_sensor.py (node /FSR_sensor)", simulated=True)),
    ("lab_sim.py", "lab_sim", {}, Start("lab_sim.py (node /lab_sim)", simulated=True)),
])
def test_what_a_node_start_is_named_and_which_pad_it_reads(script, node, params, start):
    """The teleoperation node (by its file or its name) reads the lab's pad unless told; other nodes read none."""
    assert node_start(script, node, params) == start


def test_what_each_node_of_a_launch_is():
    teleop = LaunchedNode("/teleoperation", "hri_lab", "teleoperation.py")
    scripted = LaunchedNode("/teleop2", "hri_lab", "teleoperation.py", pad="virtual")
    assert launch_starts([MAPPING, BOARD, teleop, scripted], "lab.launch") == [
        Start("lab.launch, whose node /mapping_node runs mapping_node.py"),
        Start("lab.launch, whose node /FSR_sensor runs FSR_sensor.py", simulated=True),
        Start("lab.launch, whose node /teleoperation runs teleoperation.py", pad="pygame"),
        Start("lab.launch, whose node /teleop2 runs teleoperation.py", pad="virtual"),
    ]


def test_a_refused_start_is_false_runs_nothing_and_its_output_is_the_refusal():
    refused = gate.NotStarted("refused to start lab_sim.py: it is simulated")
    assert not refused and refused.running is False
    assert refused.output() == "refused to start lab_sim.py: it is simulated\n"
    assert refused.stop() is None and refused.wait() is None and refused.wait(5.0) is None
    assert repr(refused) == "NotStarted('refused to start lab_sim.py: it is simulated')"


def test_a_master_with_hardware_is_described_by_its_hardware_nodes_in_order():
    from hri_teleop.core.modes import master_description

    assert master_description(True, ["/serial_node", "/franka_control"]) == (
        "this master runs real hardware (/franka_control, /serial_node)")
    assert master_description(True, []) == ""
