"""Benchmark 7 (make doctor at home) in its smoke size: a real doctor run and a real roscore, rows that add up."""

from __future__ import annotations

import math

import pytest

from benchmarks import doctor
from benchmarks.report import BenchError, BenchOptions

pytestmark = pytest.mark.ros


def test_the_doctor_row_is_the_doctors_own_time_beside_a_roscore_start_and_stop(tmp_path):
    messages = []
    [row] = doctor.run(BenchOptions(out_dir=tmp_path, smoke=True), messages.append)
    v = row.values
    assert row.benchmark == "make doctor at home" and v["runs"] == 1.0
    assert all(math.isfinite(x) and x > 0 for x in v.values()), v
    assert row.ratio == pytest.approx(v["median_s"] / v["roscore_median_s"])
    assert v["share_of_promise"] == pytest.approx(v["median_s"] / doctor.PROMISE_S)
    assert "promised in docs/lab-day.md" in row.figure and "roscore start + stop" in row.reference
    assert len(messages) == 1 and messages[0].startswith("doctor: run 1: ")


def test_a_doctor_that_fails_is_a_bench_error_not_a_time(tmp_path, monkeypatch):
    monkeypatch.setattr(doctor, "lab_shell_env", lambda: {"PATH": "/nonexistent"})
    with pytest.raises(BenchError, match="make doctor at home failed"):
        doctor.doctor_s(BenchOptions(out_dir=tmp_path, smoke=True))
