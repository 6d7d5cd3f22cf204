"""Benchmark 7: `make doctor` at home, the station preflight run before every session.

The doctor starts the simulated lab on a private roscore, runs its checks and stops it all. Its
figure is the doctor's own reported time (the median of the runs); the reference is a roscore
started and stopped in the same run, the floor of anything that brings up a master.
"""

from __future__ import annotations

import re
import statistics
import subprocess
import sys
import time
from typing import Callable, List

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.paths import REPO
from hri_teleop.ros.master import MasterError, PrivateMaster, free_port, lab_shell_env

#: Runs of the doctor and of the roscore floor (alternating, so both see the same load): full, smoke.
RUNS = {False: 5, True: 1}
#: What docs/lab-day.md promises for a whole run on a lab PC, s (the README's and the Makefile's "under 10 s").
PROMISE_S = 10.0
#: A doctor that takes longer than this has hung (s): the benchmark stops it and says so.
HANG_S = 120.0
_REPORTED = re.compile(r"\((\d+(?:\.\d+)?) s\)\s*$")


def doctor_s(options: BenchOptions) -> float:
    """One ``python -m hri_teleop.apps.doctor`` at home with no master: the time it reports."""
    env = lab_shell_env()
    env.update({"HRI_MODE": "home", "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}/"})
    try:
        proc = subprocess.run([sys.executable, "-m", "hri_teleop.apps.doctor"], env=env, capture_output=True,
                              text=True, timeout=HANG_S, cwd=REPO, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        raise BenchError(f"make doctor did not end within {HANG_S:.0f} s; run it by hand to see where") from None
    found = _REPORTED.search(proc.stdout.strip())
    if proc.returncode != 0 or found is None:
        tail = " | ".join((proc.stdout + proc.stderr).strip().splitlines()[-3:])
        raise BenchError(f"make doctor at home failed (exit {proc.returncode}): {tail}")
    return float(found.group(1))


def roscore_s(options: BenchOptions) -> float:
    """Wall time of a private roscore started (up and answering) and stopped."""
    started = time.monotonic()
    master = PrivateMaster(base_env=lab_shell_env(), work_dir=options.out_dir / "doctor" / "roscore")
    try:
        master.start()
    except MasterError as exc:
        raise BenchError(f"could not start a roscore for the doctor's reference: {exc}") from None
    master.stop()
    return time.monotonic() - started


def run(options: BenchOptions, progress: Callable[[str], None]) -> List[BenchRow]:
    doctor: List[float] = []
    floor: List[float] = []
    for k in range(RUNS[options.smoke]):
        doctor.append(doctor_s(options))
        floor.append(roscore_s(options))
        progress(f"doctor: run {k + 1}: {doctor[-1]:.1f} s; roscore start+stop {floor[-1]:.2f} s")
    median, floor_median = statistics.median(doctor), statistics.median(floor)
    values = {"median_s": median, "max_s": max(doctor), "roscore_median_s": floor_median,
              "promise_s": PROMISE_S, "share_of_promise": median / PROMISE_S, "runs": float(len(doctor))}
    figure = (f"median {median:.1f} s of {len(doctor)} runs (max {max(doctor):.1f} s; "
              f"{median / PROMISE_S:.0%} of the {PROMISE_S:.0f} s promised in docs/lab-day.md)")
    reference = f"roscore start + stop {floor_median:.2f} s (median of {len(floor)})"
    return [BenchRow("make doctor at home", figure, reference, median / floor_median,
                     "doctor / roscore start+stop", values)]
