"""Benchmark 2: how steadily the teleoperation node publishes its twist.

The Franka's controller expects a command every period; a late one is a step in
velocity, a missing one a stop. A subscriber in another process (as the robot's
controller is) time-stamps every twist for a while, first with the machine idle, then
with every core kept busy by spinning processes. The reference of the idle row is the
configured period (teleop.yaml's ``rate``), that of the loaded row the idle figure.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Callable, List

from benchmarks.nodes import MeasuredNodes
from benchmarks.report import BenchOptions, BenchRow
from benchmarks.stats import PeriodStats, period_stats
from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, LAB_TELEOP_CONFIG, load_teleop_config
from hri_teleop.ros.master import ManagedProcess

#: Seconds of twist recorded per condition (full run, smoke run).
SECONDS = {False: 30.0, True: 2.0}


class CpuLoad:
    """``n`` processes spinning at full speed (one per core); a context manager that stops them."""

    def __init__(self, n: int, work_dir: Path) -> None:
        self.n, self.work_dir = n, work_dir
        self.procs: List[ManagedProcess] = []

    def __enter__(self) -> "CpuLoad":
        for k in range(self.n):
            self.procs.append(ManagedProcess([sys.executable, "-c", "while True: pass"], dict(os.environ),
                                             self.work_dir / f"cpu_load_{k}.log"))
        return self

    def __exit__(self, *exc: object) -> None:
        for proc in self.procs:
            proc.stop(timeout_s=2.0)


def _record(nodes: MeasuredNodes, seconds: float, name: str) -> List[float]:
    data = nodes.probe(["timing", "--topic", DEFAULT_TWIST_TOPIC, "--seconds", f"{seconds:g}"], name,
                       timeout_s=seconds + 60.0)
    return data["arrivals_s"]


def run(options: BenchOptions, progress: Callable[[str], None]) -> List[BenchRow]:
    rate_hz = load_teleop_config(LAB_TELEOP_CONFIG).params.rate_hz
    nominal_s = 1.0 / rate_hz
    seconds = SECONDS[options.smoke]
    cores = options.jobs or os.cpu_count() or 1
    work = options.out_dir / "timing"
    with MeasuredNodes(work) as nodes:
        progress(f"timing: {seconds:g} s of twist at {rate_hz:g} Hz, machine idle")
        idle = period_stats(_record(nodes, seconds, "probe-timing-idle"), nominal_s)
        progress(f"timing: {seconds:g} s of twist with {cores} spinning processes")
        with CpuLoad(cores, work):
            loaded = period_stats(_record(nodes, seconds, "probe-timing-loaded"), nominal_s)
    return [_row("twist period, idle", idle, f"configured period {idle.nominal_ms:.0f} ms ({rate_hz:g} Hz)",
                 idle.p99_dev_ms / idle.nominal_ms, "p99 deviation / period"),
            _row(f"twist period, {cores} cores loaded", loaded, f"idle p99 deviation {idle.p99_dev_ms:.2f} ms",
                 loaded.p99_dev_ms / idle.p99_dev_ms if idle.p99_dev_ms > 0 else float("inf"), "p99 deviation / idle")]


def _row(name: str, stats: PeriodStats, reference: str, ratio: float, means: str) -> BenchRow:
    values = {"period_p50_ms": stats.p50_period_ms, "dev_p50_ms": stats.p50_dev_ms, "dev_p99_ms": stats.p99_dev_ms,
              "dev_max_ms": stats.max_dev_ms, "missed_periods": float(stats.missed), "periods": float(stats.n_periods)}
    return BenchRow(name, stats.text(), reference, ratio, means, values)
