"""Benchmark 8 (the student bundle's make check) in its smoke size: a real bundle set up and checked."""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import pytest

from benchmarks import selfcheck
from benchmarks.report import BenchError, BenchOptions

pytestmark = pytest.mark.ros

OUTPUT = """check: 2 notebook(s), each run top to bottom in a copy of its folder (your folders are not changed), 2 at a time
  lab/ex08_gamepad_commands.ipynb ... 0/0 points (3 s)
  preparation/ex04_robot_params.ipynb ... 2/2 points (4 s)
check: 2/2 autograded points in all (the rest is graded by hand)
check: your hri_lab files, graded as the course grades them
  preparation/hri_lab: robot-params 10/10: 10/10 points (0 s)
  lab/hri_lab: teleoperation 22/22: 22/22 points (5 s)
check: 32/32 points for your files, beside the notebooks' autograded points above
"""


def test_the_printed_seconds_and_points_of_notebooks_and_files_add_up():
    assert selfcheck.printed_seconds(OUTPUT) == (34.0, 34.0, 12.0, 2)


@pytest.fixture
def readable_out():
    """An out folder the grader's student uid may enter (pytest's own are 0700), as out/bench is."""
    folder = Path(tempfile.mkdtemp(prefix="hri-bench-selfcheck-"))
    folder.chmod(0o755)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def test_the_smoke_run_times_a_real_make_check_of_the_answer_key_beside_its_own_printed_times(readable_out):
    messages = []
    whole, one = selfcheck.run(BenchOptions(out_dir=readable_out, smoke=True), messages.append)
    assert whole.benchmark.startswith("make check, whole bundle") and one.benchmark == "make check ONLY=ex08"
    assert whole.values["notebooks"] == 2 and one.values["notebooks"] == 1
    for row, promise in ((whole, 60.0), (one, 15.0)):
        assert row.values["promise_s"] == promise and row.values["runs"] == 1
        assert row.ratio == pytest.approx(row.values["median_s"] / max(row.values["printed_sum_s"], 1.0))
    assert [m.split(":")[1].strip().split(" run")[0] for m in messages[1:]] == ["whole", "ONLY=ex08"]


def test_an_answer_key_short_of_full_points_is_a_bench_error_not_a_time(tmp_path, monkeypatch):
    monkeypatch.setattr(selfcheck, "_make", lambda bundle, *args: (1.0, OUTPUT.replace("2/2 points (4 s)",
                                                                                        "1/2 points (4 s)")))
    with pytest.raises(BenchError, match="not full points"):
        selfcheck.measure(tmp_path, "", 1, lambda _m: None, "whole")
