"""The machine a figure comes from: CPU model, cores, OS, Python, and how busy it was around the benchmark.

A time means little without its machine: make bench prints this beside every row. "Idle" is judged on
the CPU the rest of the machine used in a short window before and after each benchmark (when none
of the benchmark's own processes run), and the load average is given as the kernel reports it.
"""

from __future__ import annotations

import math
import os
import platform
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Optional, Tuple

__all__ = ["IDLE_BUSY_CORES", "WINDOW_S", "Machine", "busy_cores", "finished", "is_idle", "sample"]

#: The rest of the machine counts as idle below this many cores busy (a quarter of one core).
IDLE_BUSY_CORES = 0.25
#: How long each before/after window watches the machine's CPU, s.
WINDOW_S = 1.0


@dataclass(frozen=True)
class Machine:
    """One benchmark's machine: what it is, the load average at its start, the cores others kept busy."""

    cpu: str
    cores: int
    os: str
    python: str
    load_1m: float
    load_5m: float
    load_15m: float
    busy_cores_before: float
    busy_cores_after: float
    idle: bool

    def text(self) -> str:
        """One table cell: ``AMD EPYC, 2 cores, Python 3.11.2; load 0.31/0.25/0.10; idle (others 0.02, 0.04 cores)``."""
        state = "idle" if self.idle else "BUSY"
        return (f"{self.cpu}, {self.cores} cores, Python {self.python}; load {self.load_1m:.2f}/{self.load_5m:.2f}/"
                f"{self.load_15m:.2f}; {state} (others {_cores(self.busy_cores_before)}, "
                f"{_cores(self.busy_cores_after)} cores)")

    def summary(self) -> str:
        """The line at the top of the output (the OS too, and what the numbers mean)."""
        return (f"{self.cpu}, {self.cores} cores, {self.os}, Python {self.python}; load average {self.load_1m:.2f}/"
                f"{self.load_5m:.2f}/{self.load_15m:.2f} (1/5/15 min); {_cores(self.busy_cores_before)} cores "
                f"busy with other work: {'idle' if self.idle else 'BUSY, figures are slower than this machine can do'}")


def _cores(value: float) -> str:
    return "?" if math.isnan(value) else f"{value:.2f}"


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def os_name() -> str:
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if line.startswith("PRETTY_NAME="):
                return line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return platform.platform(terse=True)


def _cpu_jiffies() -> Optional[Tuple[int, int]]:
    """(busy, total) jiffies of all CPUs since boot, from /proc/stat's ``cpu`` line."""
    try:
        fields = [int(v) for v in Path("/proc/stat").read_text().splitlines()[0].split()[1:]]
    except (OSError, ValueError, IndexError):
        return None
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    total = sum(fields[:8])  # user nice system idle iowait irq softirq steal (guest is inside user)
    return total - idle, total


def busy_cores(window_s: float = WINDOW_S) -> float:
    """How many cores were busy during the next ``window_s`` (NaN where /proc/stat cannot be read)."""
    first = _cpu_jiffies()
    time.sleep(window_s)
    second = _cpu_jiffies()
    if first is None or second is None or second[1] <= first[1]:
        return math.nan
    return (second[0] - first[0]) / (second[1] - first[1]) * (os.cpu_count() or 1)


def is_idle(*busy: float) -> bool:
    return all(not math.isnan(v) and v < IDLE_BUSY_CORES for v in busy)


def sample(window_s: float = WINDOW_S) -> Machine:
    """The machine now: the load average, then the cores busy during the next ``window_s``."""
    try:
        load = os.getloadavg()
    except OSError:
        load = (math.nan, math.nan, math.nan)
    before = busy_cores(window_s)
    return Machine(cpu_model(), os.cpu_count() or 0, os_name(), platform.python_version(),
                   load[0], load[1], load[2], before, before, is_idle(before))


def finished(machine: Machine, window_s: float = WINDOW_S) -> Machine:
    """``machine`` (sampled before a benchmark) with the cores busy in a window after it."""
    after = busy_cores(window_s)
    return replace(machine, busy_cores_after=after, idle=is_idle(machine.busy_cores_before, after))
