"""make bench names the machine beside every figure: CPU, cores, Python, load average, idle or busy."""

from __future__ import annotations

import json
import math
import os
import platform

from benchmarks import machine as M
from benchmarks.report import HEADER, BenchRow, format_row, write_results


def _machine(before: float, after: float) -> M.Machine:
    return M.Machine("AMD EPYC", 2, "Debian GNU/Linux 12 (bookworm)", "3.11.2", 0.31, 0.25, 0.1, before, after,
                     M.is_idle(before, after))


def test_a_machine_is_idle_only_when_others_kept_less_than_a_quarter_core_busy_before_and_after():
    assert _machine(0.02, 0.04).idle
    assert not _machine(0.02, 1.0).idle and not _machine(1.0, 0.02).idle
    assert not _machine(math.nan, 0.0).idle  # unknown is not idle
    assert M.IDLE_BUSY_CORES == 0.25


def test_the_cell_names_cpu_cores_python_load_and_idle_or_busy():
    idle = _machine(0.02, 0.04).text()
    assert idle == "AMD EPYC, 2 cores, Python 3.11.2; load 0.31/0.25/0.10; idle (others 0.02, 0.04 cores)"
    assert "BUSY (others 1.50, 0.04 cores)" in _machine(1.5, 0.04).text()
    summary = _machine(1.5, 1.5).summary()
    assert "Debian GNU/Linux 12" in summary and "load average 0.31/0.25/0.10 (1/5/15 min)" in summary
    assert "BUSY" in summary


def test_a_sample_reads_this_machine():
    now = M.sample(window_s=0.05)
    assert now.cores == os.cpu_count() and now.python == platform.python_version() and now.cpu
    assert now.busy_cores_before >= 0.0 and now.busy_cores_before == now.busy_cores_after
    assert now.load_1m == now.load_1m  # a number, not NaN, on Linux
    done = M.finished(now, window_s=0.05)
    assert done.busy_cores_before == now.busy_cores_before and done.busy_cores_after >= 0.0


def test_every_row_of_results_md_and_json_carries_its_machine(tmp_path):
    busy = _machine(1.5, 1.2)
    rows = [BenchRow("sim", "rtf 17", "real time", 17.0, "sim s / wall s", {"rtf": 17.0}, _machine(0.0, 0.1)),
            BenchRow("doctor", "5 s", "roscore 2 s", 2.5, "doctor / roscore", {"median_s": 5.0}, busy)]
    write_results(rows, tmp_path, busy)
    md = (tmp_path / "results.md").read_text().splitlines()
    assert md[0].startswith("Machine: AMD EPYC, 2 cores, Debian") and md[2:4] == HEADER.splitlines()
    assert md[4] == format_row(rows[0]) and md[4].endswith("| AMD EPYC, 2 cores, Python 3.11.2; load 0.31/0.25/0.10; "
                                                           "idle (others 0.00, 0.10 cores) |")
    assert md[5].endswith("BUSY (others 1.50, 1.20 cores) |")
    data = json.loads((tmp_path / "results.json").read_text())
    assert data["machine"]["idle"] is False and data["machine_text"] == busy.summary()
    assert [r["machine"]["idle"] for r in data["rows"]] == [True, False]
    assert data["rows"][0]["machine"]["cpu"] == "AMD EPYC" and data["rows"][0]["machine"]["load_1m"] == 0.31
