"""make bench's ROS benchmarks in their smoke sizes: latency, command timing, simulation speed.

They run the real mapping_node and teleoperation on a private master (roslaunch), so the
smoke run also proves what the benchmark claims in the small: a force reaches the pad
within a few ms, not at the node's next 50 Hz tick.
"""

from __future__ import annotations

import math
import subprocess
import sys

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


def test_force_reaches_the_pad_within_a_few_ms_and_sampling_adds_its_period(tmp_path):
    rows = latency.run(BenchOptions(out_dir=tmp_path, smoke=True), _log)
    assert [r.benchmark for r in rows] == ["force → rumble, nodes only", "force → rumble, board every 10 ms",
                                           "force → rumble, board every 300 ms"]
    for row in rows:
        _check_row(row)
    nodes, board10, board300 = (r.values for r in rows)
    assert nodes["missed_steps"] == 0 and nodes["steps"] == 20
    # answered when the force arrives: polled at the 50 Hz tick the median would be ~10 ms
    assert nodes["p50_ms"] < 5.0, rows[0]
    assert nodes["hop_p50_ms"] <= nodes["mapped_p50_ms"] <= nodes["p50_ms"] + 0.5
    assert rows[0].ratio == pytest.approx(nodes["p50_ms"] / nodes["hop_p50_ms"])
    # a step waits for the board's next sample: up to 300 ms with the handout's sketch
    assert board300["p50_ms"] > board10["p50_ms"]
    assert board300["max_ms"] < 300.0 + 100.0
    assert (tmp_path / "latency" / "rumble.log").read_text().startswith("#")
    assert (tmp_path / "latency.png").stat().st_size > 10_000


def test_twist_arrives_every_period_idle_and_loaded(tmp_path):
    rows = timing.run(BenchOptions(out_dir=tmp_path, smoke=True, jobs=2), _log)
    assert [r.benchmark for r in rows] == ["twist period, idle", "twist period, 2 cores loaded"]
    for row in rows:
        _check_row(row)
        assert row.values["period_p50_ms"] == pytest.approx(20.0, abs=1.0)
        assert row.values["periods"] >= 2.0 / 0.02 * 0.8
    assert rows[1].ratio == pytest.approx(rows[1].values["dev_p99_ms"] / rows[0].values["dev_p99_ms"])


def test_simulation_runs_faster_than_real_time(tmp_path):
    row, arm = sim_speed.run(BenchOptions(out_dir=tmp_path, smoke=True), _log)
    _check_row(row)
    assert row.values["rtf_median"] > 5.0
    assert row.ratio == row.values["rtf_median"]
    assert row.values["simulated_s"] > 5.0
    # the arm's 1 ms cycle: the joints' share of it and the ratio to the robot's period
    _check_row(arm)
    assert 0.0 < arm.values["hand_alone_us"] < arm.values["cycle_us"] < 1000.0
    assert arm.values["joints_us"] == pytest.approx(arm.values["cycle_us"] - arm.values["hand_alone_us"])
    assert arm.ratio == pytest.approx(1000.0 / arm.values["cycle_us"])


def test_make_bench_prints_the_table_and_writes_results(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "sim", "--smoke", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith("Machine: ") and lines[1].startswith("| benchmark |")
    assert lines[3].startswith("| simulation flat out |")
    assert (tmp_path / "results.md").read_text().count("| simulation flat out |") == 1
    assert '"rtf_median"' in (tmp_path / "results.json").read_text()


def test_an_unknown_benchmark_is_one_line_naming_the_choices(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "latncy", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0
    assert "unknown benchmark latncy" in proc.stderr and "latency" in proc.stderr
