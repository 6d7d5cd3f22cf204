"""Benchmark 3: how much faster than real time the simulated lab runs flat out.

``run_lab`` steps the teleoperation controller, the arm, the hand, the object and the
sensor board in lock-step with no waiting: what the grader, the experiment rehearsal and
the tests lean on. The scenarios are the lab's own (hri_lab/scenarios/), world included.
The reference is real time: the ratio is the real-time factor itself.
"""

from __future__ import annotations

import statistics
from pathlib import Path
from typing import Callable, List, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.config import LAB_TELEOP_CONFIG, load_teleop_config
from hri_teleop.core.paths import SCENARIOS
from hri_teleop.hardware.sim.config import default_sim_yaml, load_world_config
from hri_teleop.hardware.sim.lab import run_lab
from hri_teleop.hardware.sim.virtual_pad import load_script

#: Runs of each scenario (the median counts): full run, smoke run.
REPEATS = {False: 5, True: 1}


def run_scenario(path: Path) -> Tuple[float, float, int]:
    """(simulated s, wall s, ticks) of one flat-out run of a scenario."""
    config = load_teleop_config(LAB_TELEOP_CONFIG)
    world = load_world_config(default_sim_yaml() or "", scenario=path)
    record = run_lab(load_script(path), world, config.params, config.limits,
                     max_sensor_force=world.attachment.full_travel_count)
    if record.wall_s <= 0:
        raise BenchError(f"{path.name}: the run took no measurable time")
    return record.duration_s(), record.wall_s, int(round(record.duration_s() * config.params.rate_hz))


def run(options: BenchOptions, progress: Callable[[str], None]) -> List[BenchRow]:
    scenarios = sorted(SCENARIOS.glob("*.yaml"))
    if not scenarios:
        raise BenchError(f"no scenarios in {SCENARIOS}: the checkout is incomplete")
    sim_s = wall_s = 0.0
    ticks = 0
    factors: List[float] = []
    for path in scenarios:
        for k in range(REPEATS[options.smoke]):
            simulated, wall, n = run_scenario(path)
            progress(f"sim: {path.name} run {k + 1}: {simulated:.1f} s simulated in {wall:.2f} s")
            sim_s, wall_s, ticks = sim_s + simulated, wall_s + wall, ticks + n
            factors.append(simulated / wall)
    rtf = statistics.median(factors)
    values = {"rtf_median": rtf, "rtf_min": min(factors), "simulated_s": sim_s, "wall_s": wall_s,
              "wall_per_tick_ms": wall_s / max(1, ticks) * 1e3, "runs": float(len(factors))}
    figure = (f"real-time factor {rtf:.0f} (min {min(factors):.0f}) over {len(factors)} runs of "
              f"{', '.join(p.stem for p in scenarios)}; {values['wall_per_tick_ms']:.3f} ms of wall time per control tick")
    return [BenchRow("simulation flat out", figure, "real time (factor 1)", rtf, "simulated s / wall s", values)]
