"""Benchmark 5 (every notebook headless, make setup with nothing missing): it runs and its rows add up.

The smoke run executes the two cheapest notebooks and the floor notebook on the real
kernel (roscore and all) and times ``make setup`` twice, so a broken benchmark fails here;
the pure helpers are checked without any of that.
"""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import pytest

from benchmarks import notebooks as bench
from benchmarks.report import BenchError, BenchOptions, format_row


def _positive(value: float) -> bool:
    return math.isfinite(value) and value > 0


@pytest.mark.ros
def test_smoke_run_gives_both_rows_with_consistent_ratios(tmp_path):
    if shutil.which("roscore") is None:
        pytest.fail("roscore not found: run 'make setup' (installs ROS 1) or source tools/env.sh")
    messages = []
    fast_before = os.environ.get("HRI_NOTEBOOK_FAST")
    rows = bench.run(BenchOptions(out_dir=tmp_path, smoke=True), messages.append)

    assert [row.benchmark for row in rows] == [bench.NOTEBOOKS_ROW, bench.SETUP_ROW]
    notebooks, setup = rows

    count = len(bench.SMOKE_NOTEBOOKS)
    assert notebooks.values["notebooks"] == count
    per_notebook = {stem: notebooks.values[f"{stem}_s"] for stem in bench.SMOKE_NOTEBOOKS}
    assert all(_positive(v) for v in per_notebook.values()), per_notebook
    assert _positive(notebooks.values["floor_s"])
    assert notebooks.values["total_s"] == pytest.approx(sum(per_notebook.values()))
    assert notebooks.values["slowest_s"] == max(per_notebook.values())
    assert notebooks.ratio == pytest.approx(notebooks.values["total_s"] / (count * notebooks.values["floor_s"]))
    assert f"{count} notebooks in" in notebooks.figure

    assert setup.values["runs"] == bench.SETUP_RUNS_SMOKE
    assert _positive(setup.values["median_s"]) and _positive(setup.values["floor_s"])
    assert setup.values["min_s"] <= setup.values["median_s"] <= setup.values["max_s"]
    assert setup.ratio == pytest.approx(setup.values["median_s"] / setup.values["floor_s"])
    assert setup.values["slowest_line_s"] > 0 and "setup.sh:" in setup.figure

    for row in rows:
        assert _positive(row.ratio)
        assert format_row(row).count("|") - format_row(row).count("\\|") == 6, "one table row, 5 cells"
    assert any(m.startswith(f"notebook 1/{count} ") for m in messages), messages
    assert any(m.startswith(f"make setup {bench.SETUP_RUNS_SMOKE}/") for m in messages), messages
    assert bench.MARKER_ENV not in os.environ, "the marker must not outlive the run"
    assert os.environ.get("HRI_NOTEBOOK_FAST") == fast_before, "fast mode only while the notebooks run"


# -- without a kernel: the failure path and the helpers ------------------------------------------

def test_a_failing_notebook_is_an_error_naming_it_not_a_time(tmp_path, monkeypatch):
    calls = []

    def fake_execute(path: Path):
        calls.append(path.stem)
        if path.stem == "ex11_calibration":
            return 1.0, {"errors": [], "grades": {"ex3_param": [1, 2]}}
        return 0.5, {"errors": [], "grades": {}}

    monkeypatch.setattr(bench, "_execute", fake_execute)
    monkeypatch.setattr(bench, "_source_course", lambda work: _fake_course(work))
    with pytest.raises(BenchError, match=r"ex11_calibration.*\n.*ex3_param got 1 of 2"):
        bench._notebooks_row(BenchOptions(out_dir=tmp_path, smoke=True), lambda message: None)
    assert calls[-1] == "ex11_calibration"


def test_fast_mode_is_on_while_notebooks_run_and_restored_after(tmp_path, monkeypatch):
    seen = []
    monkeypatch.delenv("HRI_NOTEBOOK_FAST", raising=False)
    monkeypatch.setattr(bench, "_execute", lambda path: (seen.append(os.environ.get("HRI_NOTEBOOK_FAST")) or 0.5,
                                                          {"errors": [], "grades": {"g": [2, 2]}}))
    monkeypatch.setattr(bench, "_source_course", lambda work: _fake_course(work))
    row = bench._notebooks_row(BenchOptions(out_dir=tmp_path, smoke=True), lambda message: None)
    assert set(seen) == {"1"} and "HRI_NOTEBOOK_FAST" not in os.environ
    assert row.values["total_s"] == pytest.approx(1.0) and row.ratio == pytest.approx(1.0)


def _fake_course(work: Path) -> Path:
    course = work / "course"
    for stem in bench.SMOKE_NOTEBOOKS + ("ex99_other",):
        path = course / "source" / "preparation" / f"{stem}.ipynb"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("{}")
    return course


def test_short_name_keeps_the_exercise_numbers():
    assert bench.short_name("ex12_13_teleoperation_launch") == "ex12_13"
    assert bench.short_name("ex01_fsr_and_arduino") == "ex01"
    assert bench.short_name("ex15") == "ex15"
    assert bench.short_name("floor") == "floor"


def test_floor_runs_are_spread_among_the_notebooks():
    assert bench.floor_positions(13, 3) == [2, 6, 10]
    assert bench.floor_positions(2, 1) == [1]
    assert bench.floor_positions(1, 3) == [0, 0, 0], "every floor run happens, even with one notebook"
    assert bench.floor_positions(0, 3) == []


def test_notebook_problems_names_errors_stderr_and_lost_points():
    assert bench.notebook_problems("ex04", {"errors": [], "grades": {"a": [3, 3]}}) == []
    problems = bench.notebook_problems("ex04", {"errors": ["cell 2: ValueError: x"], "grades": {"a": [3, 3], "b": [0, 2]}})
    assert problems == ["ex04: cell 2: ValueError: x", "ex04: autograded cell b got 0 of 2 points"]


def test_notebooks_figure_names_the_slowest():
    figure = bench.notebooks_figure({"ex01_fsr": 2.0, "ex12_13_launch": 31.04, "ex14_force": 20.0}, 53.04)
    assert figure == "3 notebooks in 53.0 s, one at a time (slowest ex12_13 31.0 s, ex14 20.0 s)"


def test_line_costs_charges_each_command_until_the_next_and_adds_up_a_loop():
    trace = "\n".join([
        "+\t100.005\t/x/setup.sh:10\tset -euo pipefail",
        "+\t100.010\t/x/setup.sh:44\tfor p in a b",
        "++\t100.020\t/x/setup.sh:45\tdpkg-query -W a",
        "continuation of a multi-line command",
        "+\t100.120\t/x/setup.sh:45\tdpkg-query -W b",
        "+\t100.220\t/x/setup.sh:99\tpython -c 'import rospy'",
    ])
    costs = bench.line_costs(trace, end_epoch_s=100.620)
    assert [(line, count) for _src, line, _s, count in costs] == [(99, 1), (45, 2), (44, 1), (10, 1)]
    assert [round(s, 3) for _src, _line, s, _count in costs] == [0.4, 0.2, 0.01, 0.005]
    assert bench.line_costs("", 1.0) == []


def test_setup_that_had_work_to_do_is_not_a_no_op_time():
    assert bench._SETUP_DID_WORK.search("setup: installing hri-teleop and its dependencies into .venv")
    assert not bench._SETUP_DID_WORK.search("setup: ready (Python 3.11.2, ROS from Debian packages)")


def test_leftover_processes_with_the_marker_are_found_and_stopped():
    import subprocess
    import sys

    marker = "test-marker-leftover"
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"],
                            env=dict(os.environ, **{bench.MARKER_ENV: marker}))
    try:
        left = bench._stop_leftovers(marker, grace_s=0.3)
        assert len(left) == 1 and left[0].startswith(f"{proc.pid} ")
        assert proc.wait(timeout=5) != 0
        assert bench._marked_processes(marker) == {}
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
