"""Benchmark 3: how fast the simulated lab runs flat out, and what the Panda's joints cost per cycle.

``run_lab`` steps the teleoperation controller, the arm, the hand, the object and the sensor board
in lock-step on the lab's scenarios: the reference is real time; the same runs with the arm's cycle
in Python alone (no compiled cycle) are printed beside, with a profile of where the wall time goes.
The second row times the arm with its seven joints against the robot's 1 ms cycle (compiled, and
the Python cycle beside it), the third the gripper's fingers and the object.
"""

from __future__ import annotations

import cProfile
import pstats
import statistics
import time
from pathlib import Path
from typing import Callable, List, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.config import LAB_TELEOP_CONFIG, load_teleop_config
from hri_teleop.core.limits import DEFAULT_LIMITS, TwistLimiter
from hri_teleop.core.paths import SCENARIOS
from hri_teleop.sim.arm import SimArm, SimArmConfig
from hri_teleop.sim.arm_kernel import kernel, python_cycles
from hri_teleop.sim.config import default_sim_yaml, load_world_config
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.gripper_goals import MoveCommand
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.virtual_pad import load_script
from hri_teleop.sim.world import LAB_ARM_CONFIG

#: Runs of each scenario (the median counts): full run, smoke run.
REPEATS = {False: 5, True: 1}
#: Simulated seconds of the arm-cycle timing: full run, smoke run.
ARM_SECONDS = {False: 20.0, True: 2.0}
#: Simulated seconds of the gripper hand, each timed alone (the best counts): full run, smoke run.
HAND_REPEATS = {False: 5, True: 1}


def run_scenario(path: Path) -> Tuple[float, float, int]:
    """(simulated s, wall s, ticks) of one flat-out run of a scenario."""
    config = load_teleop_config(LAB_TELEOP_CONFIG)
    world = load_world_config(default_sim_yaml() or "", scenario=path)
    record = run_lab(load_script(path), world, config.params, config.limits,
                     max_sensor_force=world.attachment.full_travel_count)
    if record.wall_s <= 0:
        raise BenchError(f"{path.name}: the run took no measurable time")
    return record.duration_s(), record.wall_s, int(round(record.duration_s() * config.params.rate_hz))


def _factors(scenarios: List[Path], repeats: int, progress: Callable[[str], None], label: str) -> Tuple[List[float], float, float, int]:
    sim_s = wall_s = 0.0
    ticks = 0
    factors: List[float] = []
    for path in scenarios:
        for k in range(repeats):
            simulated, wall, n = run_scenario(path)
            progress(f"sim ({label}): {path.name} run {k + 1}: {simulated:.1f} s simulated in {wall:.3f} s")
            sim_s, wall_s, ticks = sim_s + simulated, wall_s + wall, ticks + n
            factors.append(simulated / wall)
    return factors, sim_s, wall_s, ticks


def profile_lines(path: Path, top: int = 8) -> List[str]:
    """Where one run of a scenario spends its wall time: the functions with the most time of their own."""
    profiler = cProfile.Profile()
    profiler.runcall(run_scenario, path)
    stats = pstats.Stats(profiler)
    total = sum(row[2] for row in stats.stats.values())  # type: ignore[attr-defined]
    rows = sorted(stats.stats.items(), key=lambda item: -item[1][2])[:top]  # type: ignore[attr-defined]
    return [f"{100.0 * own / total:5.1f}% {calls:>7} calls  {Path(file).name}:{line} {name}"
            for (file, line, name), (_, calls, own, _, _) in rows]


def run(options: BenchOptions, progress: Callable[[str], None]) -> List[BenchRow]:
    scenarios = sorted(SCENARIOS.glob("*.yaml"))
    if not scenarios:
        raise BenchError(f"no scenarios in {SCENARIOS}: the checkout is incomplete")
    if kernel() is None:
        raise BenchError("the simulated arm's compiled cycle is not built (hri_teleop/sim/_arm_cycle*.so): "
                         "run `make setup` on a machine with gcc; without it the figure is the Python cycle's")
    repeats = REPEATS[options.smoke]
    factors, sim_s, wall_s, ticks = _factors(scenarios, repeats, progress, "compiled arm cycle")
    with python_cycles():
        python_factors, _, _, _ = _factors(scenarios, repeats, progress, "Python arm cycle")
    for line in profile_lines(SCENARIOS / "default.yaml"):
        progress(f"sim profile (default, own time): {line}")
    rtf = statistics.median(factors)
    python_rtf = statistics.median(python_factors)
    values = {"rtf_median": rtf, "rtf_min": min(factors), "simulated_s": sim_s, "wall_s": wall_s,
              "wall_per_tick_ms": wall_s / max(1, ticks) * 1e3, "runs": float(len(factors)),
              "python_cycle_rtf_median": python_rtf}
    figure = (f"real-time factor {rtf:.0f} (min {min(factors):.0f}) over {len(factors)} runs of "
              f"{', '.join(p.stem for p in scenarios)}; {values['wall_per_tick_ms']:.3f} ms of wall time per control "
              f"tick; the arm's cycle in Python alone: {python_rtf:.0f}")
    return [BenchRow("simulation flat out", figure, "real time (factor 1)", rtf, "simulated s / wall s", values),
            run_arm(options, progress), run_hand(options, progress)]


def arm_cycle_us(joints: bool, seconds: float) -> float:
    """CPU microseconds per 1 ms cycle of the lab's arm under a 50 Hz limited stream that translates
    and turns the hand inside the lab's box (the hand alone when ``joints`` is False)."""
    config = LAB_ARM_CONFIG if joints else SimArmConfig(joints=False)
    arm = SimArm(config)
    limiter = TwistLimiter(DEFAULT_LIMITS)
    targets = [(0.04, -0.03, -0.05, 0.1, -0.1, 0.2), (-0.04, 0.03, 0.05, -0.1, 0.1, -0.2)]
    n = int(seconds * 50)
    started = time.process_time()
    t = 0.0
    for k in range(n):
        t += 0.02
        arm.command(limiter.step(targets[(k // 100) % 2], 0.02), t)
        arm.run_until(t)
    cpu_s = time.process_time() - started
    if arm.violation_count:
        raise BenchError(f"the timing stream broke a limit ({arm.violation_counts}): the benchmark is wrong")
    return cpu_s / (n * 20) * 1e6


def run_arm(options: BenchOptions, progress: Callable[[str], None]) -> BenchRow:
    seconds = ARM_SECONDS[options.smoke]
    with_joints = arm_cycle_us(True, seconds)
    hand_alone = arm_cycle_us(False, seconds)
    with python_cycles():
        python_joints = arm_cycle_us(True, seconds)
    progress(f"sim: arm cycle {with_joints:.1f} us with the joints, {hand_alone:.1f} us the hand alone, "
             f"{python_joints:.1f} us with the joints in Python")
    values = {"cycle_us": with_joints, "hand_alone_us": hand_alone, "joints_us": with_joints - hand_alone,
              "share_of_1ms": with_joints / 1000.0, "python_cycle_us": python_joints}
    figure = (f"{with_joints:.1f} us of CPU per 1 ms cycle with the seven joints (compiled cycle: kinematics, "
              f"the joint judge), {hand_alone:.1f} us for the hand alone; {python_joints:.1f} us in Python "
              "(pinocchio, numpy)")
    return BenchRow("Panda joints per 1 kHz cycle", figure, "the robot's 1 ms cycle", 1000.0 / with_joints,
                    "1 ms / CPU per cycle", values)


def hand_step_us(seconds: float, repeats: int) -> float:
    """CPU microseconds per 1 ms step of the gripper closing on the sponge while the arm lifts
    (the fingers, the piston's count, the finger joints read every step); the best of ``repeats``."""
    best = float("inf")
    for _ in range(repeats):
        hand = HandSim()
        hand.place_object(OBJECTS["sponge"])
        hand.send(MoveCommand(0.0, 0.1), 0.0)
        n = int(round(seconds * 1000))
        started = time.process_time()
        for k in range(1, n + 1):
            hand.step(k * 0.001, 0.01)
            _ = hand.fsr_count, hand.joint_positions_m
        best = min(best, (time.process_time() - started) / n * 1e6)
    if best <= 0:
        raise BenchError("the hand's steps took no measurable CPU time: the benchmark is wrong")
    return best


def run_hand(options: BenchOptions, progress: Callable[[str], None]) -> BenchRow:
    step_us = hand_step_us(1.0, HAND_REPEATS[options.smoke])
    progress(f"sim: gripper hand {step_us:.1f} us per 1 ms step")
    values = {"step_us": step_us, "share_of_1ms": step_us / 1000.0}
    figure = (f"{step_us:.1f} us of CPU per 1 ms step of the fingers closing on the sponge "
              f"(best of {HAND_REPEATS[options.smoke]} simulated seconds)")
    return BenchRow("gripper hand per 1 kHz cycle", figure, "the robot's 1 ms cycle", 1000.0 / step_us,
                    "1 ms / CPU per step", values)
