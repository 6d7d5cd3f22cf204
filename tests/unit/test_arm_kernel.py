"""The simulated arm's compiled cycle (hri_teleop/sim/arm_cycle.c) does what the Python cycle does.

Every comparison runs the same input twice, once with the C and once with Python alone
(``python_cycles``): the Cartesian side must match to the last bit (the same operations on the
same doubles), the joints to 1e-9 (pinocchio and LAPACK against the C's own kinematics and solve),
and every event, reflex and violation at the same millisecond.
"""

from __future__ import annotations

import ctypes
import math
from typing import Any, Dict, List, Sequence, Tuple

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.config import LAB_TELEOP_CONFIG, load_teleop_config
from hri_teleop.core.limits import DEFAULT_LIMITS, TwistLimiter
from hri_teleop.core.paths import SCENARIOS
from hri_teleop.sim import arm_kernel
from hri_teleop.sim.arm import SimArm, SimArmConfig
from hri_teleop.sim.arm_kernel import kernel, kernel_library, python_cycles
from hri_teleop.sim.config import default_sim_yaml, load_world_config
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.operators import random_operator
from hri_teleop.sim.virtual_pad import load_script
from hri_teleop.sim.world import LAB_ARM_CONFIG

JOINT_TOLERANCE = 1e-9
TELEOP = load_teleop_config(LAB_TELEOP_CONFIG)

Command = Tuple[float, Sequence[float]]  # (time s, twist)


def _stream(*segments: Tuple[Sequence[float], float, float]) -> List[Command]:
    """The node's 50 Hz commands toward each (twist, from s, to s), ramped inside the lab's limits."""
    limiter = TwistLimiter(DEFAULT_LIMITS)
    return [(round(start_s + 0.02 * k, 9), limiter.step(twist, 0.02))
            for twist, start_s, end_s in segments for k in range(int(round((end_s - start_s) / 0.02)))]


def _drive(config: SimArmConfig, commands: List[Command], until_s: float, recover_at: float = math.inf,
           chunk_s: float = 0.02) -> List[Dict[str, Any]]:
    """The arm's read-outs after each chunk of cycles, commands given at their times."""
    arm = SimArm(config)
    out: List[Dict[str, Any]] = []
    pending = sorted(commands, key=lambda c: c[0])
    t = 0.0
    recovered = False
    while t < until_s - 1e-9:
        t = round(t + chunk_s, 9)
        while pending and pending[0][0] <= t + 1e-9:
            at, twist = pending.pop(0)
            arm.command(twist, at)
        if not recovered and t >= recover_at:
            recovered = arm.recover(t)
        trace: List[float] = []
        arm.run_cycles(int(round(chunk_s / 0.001)), trace)
        out.append({"time": arm.time_s, "position": arm.position_m, "quat": arm.orientation_xyzw,
                    "velocity": arm.velocity, "commanded": arm.commanded_velocity, "state": arm.state,
                    "joints": arm.joint_positions, "joint_velocities": arm.joint_velocities, "trace": trace,
                    "events": [(e.time_s, e.kind, e.message) for e in arm.events],
                    "violations": [(v.time_s, v.error, v.group) for v in arm.violations]})
    return out


def _both(config: SimArmConfig, commands: List[Command], until_s: float, **kw: Any) -> Tuple[List[Dict[str, Any]], List[Dict[str, Any]]]:
    compiled = _drive(config, commands, until_s, **kw)
    with python_cycles():
        reference = _drive(config, commands, until_s, **kw)
    return compiled, reference


def _assert_same(compiled: List[Dict[str, Any]], reference: List[Dict[str, Any]]) -> None:
    assert len(compiled) == len(reference)
    for a, b in zip(compiled, reference):
        for key in ("time", "position", "quat", "velocity", "commanded", "state", "events", "violations", "trace"):
            assert a[key] == b[key], (key, a["time"], a[key], b[key])
        if a["joints"] is None:
            assert b["joints"] is None
            continue
        for key in ("joints", "joint_velocities"):
            worst = max(abs(x - y) for x, y in zip(a[key], b[key]))
            assert worst <= JOINT_TOLERANCE, (key, a["time"], worst)


def test_make_test_runs_with_the_compiled_cycle_built():
    """pip built it at `make setup` (gcc is one of the project's packages); a silent build failure
    would leave the simulation at its Python speed with every other test still green."""
    assert kernel_library() is not None and kernel() is not None


def test_hri_sim_kernel_python_chooses_the_python_cycle(monkeypatch):
    monkeypatch.setenv("HRI_SIM_KERNEL", "python")
    assert kernel() is None
    monkeypatch.delenv("HRI_SIM_KERNEL")
    assert kernel() is not None


def test_a_library_of_another_layout_or_a_broken_file_is_not_loaded(monkeypatch, tmp_path):
    broken = tmp_path / "_arm_cycle.broken.so"
    broken.write_bytes(b"not a shared library")
    monkeypatch.setattr(arm_kernel, "kernel_library", lambda: broken)
    arm_kernel.load_library.cache_clear()
    try:
        assert kernel() is None
        arm = SimArm(LAB_ARM_CONFIG)  # and the arm runs in Python
        arm.command((0.01, 0, 0, 0, 0, 0), 0.0)
        assert arm.run_until(0.05) == 50 and arm.position_m[0] > LAB_ARM_CONFIG.start_position_m[0]
    finally:
        arm_kernel.load_library.cache_clear()


def test_the_layout_check_refuses_sizes_that_differ(monkeypatch):
    monkeypatch.setattr(arm_kernel, "STATE_SIZE", arm_kernel.STATE_SIZE + 1)
    arm_kernel.load_library.cache_clear()
    try:
        assert arm_kernel.load_library() is None
    finally:
        monkeypatch.undo()
        arm_kernel.load_library.cache_clear()
    assert kernel() is not None


def test_translation_and_rotation_give_the_same_cycles_in_c_and_python():
    commands = _stream(((0.02, -0.01, 0.015, 0.0, 0.0, 0.0), 0.0, 0.2), ((0.05, 0.03, -0.02, 0.1, -0.2, 0.3), 0.2, 0.5),
                       ((-0.04, 0.02, 0.0, -0.3, 0.1, 0.0), 0.5, 0.8), ((0.0,) * 6, 0.8, 1.2))
    _assert_same(*_both(LAB_ARM_CONFIG, commands, 1.2))


def test_a_wall_met_inside_a_batch_is_the_same_event_at_the_same_millisecond():
    commands = _stream(((0.0, 0.0, -0.1, 0.0, 0.0, 0.0), 0.0, 5.0), ((0.0, 0.0, 0.05, 0.0, 0.0, 0.0), 5.0, 5.3))
    compiled, reference = _both(LAB_ARM_CONFIG, commands, 5.4)
    _assert_same(compiled, reference)
    assert any("workspace limit: z at its min" in e[2] for e in compiled[-1]["events"])


def test_a_timeout_inside_a_batch_ramps_down_the_same():
    commands = _stream(((0.03, 0.0, 0.0, 0.0, 0.2, 0.0), 0.0, 0.3))
    compiled, reference = _both(LAB_ARM_CONFIG, commands, 1.0, chunk_s=0.05)
    _assert_same(compiled, reference)
    assert compiled[-1]["state"] == "timeout"


def test_a_cartesian_reflex_inside_a_batch_and_the_recovery_are_the_same():
    commands = (_stream(((0.02, 0.0, 0.0, 0.0, 0.0, 0.0), 0.0, 0.1)) + [(0.1, (0.5, 0.0, 0.0, 0.0, 0.0, 0.0))]
                + _stream(((0.01, 0.0, 0.0, 0.0, 0.0, 0.0), 0.32, 0.6)))
    compiled, reference = _both(LAB_ARM_CONFIG, commands, 0.6, recover_at=0.3)
    _assert_same(compiled, reference)
    assert compiled[-1]["violations"] and any(e[1] == "recovered" for e in compiled[-1]["events"])


def test_a_joint_limit_reflex_comes_at_the_same_millisecond():
    commands = _stream(((0.0, 0.0, 0.0, 0.0, 0.0, 0.9), 0.0, 8.0))  # turn the hand until joint 7 stops it
    compiled, reference = _both(LAB_ARM_CONFIG, commands, 8.0)
    _assert_same(compiled, reference)
    assert any("joint" in v[1] for v in compiled[-1]["violations"])


def test_a_non_finite_command_is_refused_the_same():
    commands = _stream(((0.01, 0.0, 0.0, 0.0, 0.0, 0.0), 0.0, 0.1)) + [(0.1, (math.nan, 0.0, 0.0, 0.0, 0.0, 0.0))]
    _assert_same(*_both(LAB_ARM_CONFIG, commands, 0.3))


def test_the_hand_alone_without_joints_is_the_same():
    config = SimArmConfig(joints=False)
    commands = _stream(((0.05, 0.02, -0.03, 0.2, 0.1, -0.1), 0.0, 0.4), ((0.0,) * 6, 0.4, 0.8))
    _assert_same(*_both(config, commands, 0.8))


def test_the_hold_controller_is_the_same():
    config = SimArmConfig(controller="hold", start_position_m=LAB_ARM_CONFIG.start_position_m)
    commands = [(0.0, (0.001, 0.0, 0.0, 0.0, 0.0, 0.0)), (0.1, (0.002, 0.0, 0.0, 0.0, 0.0, 0.0))]
    _assert_same(*_both(config, commands, 0.3))


@settings(max_examples=30, deadline=None)
@given(twists=st.lists(st.tuples(*[st.floats(-0.08, 0.08)] * 3, *[st.floats(-0.4, 0.4)] * 3), min_size=1, max_size=6))
def test_any_stream_of_commands_gives_the_same_cycles(twists):
    commands = _stream(*[(t, 0.1 * i, 0.1 * (i + 1)) for i, t in enumerate(twists)])
    _assert_same(*_both(LAB_ARM_CONFIG, commands, 0.1 * len(twists) + 0.4))


def _lab(steps: Any, scenario: Any = None) -> Any:
    world = load_world_config(default_sim_yaml() or "", scenario=scenario)
    return run_lab(steps, world, TELEOP.params, TELEOP.limits, max_sensor_force=world.attachment.full_travel_count,
                   max_duration_s=20.0)


def _record(record: Any) -> Tuple[Any, ...]:
    return (record.count, record.mapped, record.rumble, record.width_target, record.width, record.speed,
            record.grip_force, record.object_height, record.violation_counts, record.reflex_explanation,
            record.grasped, record.lifted, record.crushed, record.ended_by)


@pytest.mark.parametrize("name", ["default", "joint_limit", "squeeze"])
def test_the_lab_scenarios_run_the_same_in_c_and_python(name):
    path = SCENARIOS / f"{name}.yaml"
    compiled = _lab(load_script(path), path)
    with python_cycles():
        reference = _lab(load_script(path), path)
    assert _record(compiled) == _record(reference)


def test_150_random_operators_run_the_same_in_c_and_python():
    """The same records, tick by tick, for 150 random operators (translating and turning the hand,
    squeezing, quitting); the joint-limit reflexes are the scenarios' and the tests' above."""
    moved = 0
    for seed in range(150):
        steps = random_operator(seed, duration_s=1.5)
        compiled = _lab(steps)
        with python_cycles():
            reference = _lab(steps)
        assert _record(compiled) == _record(reference), f"seed {seed}"
        moved += max(v for _, v in compiled.speed) > 0.01
    assert moved >= 60  # the comparison saw the arm move (74 of these 150 do), not 150 idle runs


def test_the_kernel_runs_the_common_cycles_and_hands_back_the_rest():
    """A direct call: cycles 1..20 of a moving arm run in C; a timeout hands back the first cycle past it."""
    arm = SimArm(LAB_ARM_CONFIG)
    arm.command((0.02, 0.0, 0.0, 0.0, 0.0, 0.0), 0.0)
    arm.run_cycles(1)
    found = kernel()
    assert found is not None
    arm._pack()
    joints = arm._joints
    assert joints is not None
    as_doubles = ctypes.POINTER(ctypes.c_double)
    args = (arm._k_state, arm._k_params, joints.state.ctypes.data_as(as_doubles), joints.consts.ctypes.data_as(as_doubles))
    assert found.run(*args, 0.001, 1, 20, None) == 21
    # the command arrived at 0.0; with timeout_s 0.3 the cycle at 0.301 s is the timeout's (Python's)
    assert found.run(*args, 0.001, 21, 400, None) == 300
