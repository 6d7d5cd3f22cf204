"""make bench's ROS benchmarks in their smoke sizes: latency, command timing, simulation speed.

They run the real mapping_node and teleoperation on a private master (roslaunch): the smoke run
proves that each benchmark measures what it names and that its rows add up. How fast is for
`make bench` to say, beside its reference and its machine: no test here judges a time.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from typing import List

import pytest

from benchmarks import latency, sim_speed, timing
from benchmarks.report import BenchOptions, BenchRow

pytestmark = pytest.mark.ros


def _log(message: str) -> None:
    print(message)


def _check_row(row: BenchRow) -> None:
    assert row.values, row
    assert all(math.isfinite(v) and v >= 0 for v in row.values.values()), row
    assert row.ratio > 0 and math.isfinite(row.ratio), row


def test_every_force_step_reaches_the_pad_through_the_nodes_and_through_each_board(tmp_path):
    rows = latency.run(BenchOptions(out_dir=tmp_path, smoke=True), _log)
    assert [r.benchmark for r in rows] == ["force → rumble, nodes only", "force → rumble, board every 10 ms",
                                           "force → rumble, board every 300 ms"]
    for row in rows:
        _check_row(row)
    nodes, board10, board300 = (r.values for r in rows)
    assert nodes["missed_steps"] == 0 and nodes["steps"] == 20
    assert rows[0].ratio == pytest.approx(nodes["p50_ms"] / nodes["hop_p50_ms"])
    assert rows[1].ratio == pytest.approx(board10["p50_ms"] / nodes["p50_ms"])
    assert rows[2].ratio == pytest.approx(board300["p50_ms"] / board10["p50_ms"])
    assert (tmp_path / "latency" / "rumble.log").read_text().startswith("#")
    assert (tmp_path / "latency.png").stat().st_size > 10_000


def test_twists_are_recorded_idle_and_loaded(tmp_path):
    rows = timing.run(BenchOptions(out_dir=tmp_path, smoke=True, jobs=2), _log)
    assert [r.benchmark for r in rows] == ["twist period, idle", "twist period, 2 cores loaded"]
    for row in rows:
        _check_row(row)
        assert row.values["periods"] >= 1 and 0 <= row.values["missed_periods"] <= row.values["periods"]
    assert rows[1].ratio == pytest.approx(rows[1].values["dev_p99_ms"] / rows[0].values["dev_p99_ms"])


def test_simulation_rows_time_the_lab_the_arm_and_the_hand(tmp_path):
    said: List[str] = []
    row, arm, hand = sim_speed.run(BenchOptions(out_dir=tmp_path, smoke=True), said.append)
    _check_row(row)
    # the same scenarios with the arm's cycle in Python, and the profile of one run, in the same output
    assert row.values["python_cycle_rtf_median"] > 0 and arm.values["python_cycle_us"] > 0
    assert sum("sim (Python arm cycle): " in m for m in said) == 3
    profile = [m for m in said if m.startswith("sim profile (default, own time): ")]
    assert len(profile) == 8 and any("world.py" in m or "hand.py" in m for m in profile)
    assert row.ratio == row.values["rtf_median"]
    assert row.values["runs"] == 3 and row.values["simulated_s"] > 30.0  # the three scenarios, once each
    assert row.ratio == pytest.approx(row.values["rtf_median"])
    # the arm's 1 ms cycle: the joints' share of it and the ratio to the robot's period
    _check_row(arm)
    assert arm.values["joints_us"] == pytest.approx(arm.values["cycle_us"] - arm.values["hand_alone_us"])
    assert arm.ratio == pytest.approx(1000.0 / arm.values["cycle_us"])
    _check_row(hand)
    assert hand.benchmark == "gripper hand per 1 kHz cycle" and hand.ratio == pytest.approx(1000.0 / hand.values["step_us"])


def test_make_bench_prints_the_table_and_writes_results(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "sim", "--smoke", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith("Machine: ") and " cores, " in lines[0] and "Python " in lines[0]
    assert "load average " in lines[0] and lines[1].startswith("| benchmark |") and lines[1].endswith("| machine |")
    assert lines[3].startswith("| simulation flat out |") and re.search(r"cores, Python [\d.]+; load [\d.]+/", lines[3])
    assert (tmp_path / "results.md").read_text().count("| simulation flat out |") == 1
    data = json.loads((tmp_path / "results.json").read_text())
    assert "rtf_median" in data["rows"][0]["values"]
    assert all(isinstance(r["machine"]["idle"], bool) and r["machine"]["cores"] >= 1 for r in data["rows"])


def test_an_unknown_benchmark_is_one_line_naming_the_choices(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "latncy", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0
    assert "unknown benchmark latncy" in proc.stderr and "latency" in proc.stderr
