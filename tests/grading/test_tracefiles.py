"""The public reference traces (grading/traces/*.bag): one command, the same bytes, the same cases."""

from __future__ import annotations

import pytest
from grading_helpers import hri_grade

from hri_teleop.grading.cases.tracefiles import TRACE_DIR
from hri_teleop.grading.exercises.mapping_node.cases import public_mapping_case
from hri_teleop.grading.exercises.mapping_node.traces import read_mapping_trace
from hri_teleop.grading.exercises.registry import exercises
from hri_teleop.grading.exercises.teleoperation.cases import public_teleop_parts_case
from hri_teleop.grading.exercises.teleoperation.traces import read_parts_trace
from hri_teleop.ros.bags import read_topics


def test_hri_grade_traces_rewrites_the_committed_bags_byte_for_byte(tmp_path):
    proc = hri_grade("traces", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    names = [name for found in exercises() for name in found.public_traces]
    assert names == ["mapping_public.bag", "teleop_parts_public.bag", "teleop_node_public.bag"]
    for name in names:
        committed = TRACE_DIR / name
        assert committed.is_file(), f"{committed} missing: run `make traces`"
        assert (tmp_path / name).read_bytes() == committed.read_bytes(), \
            f"{name} differs from a fresh `make traces`: regenerate it (or make the generator deterministic)"


def test_the_mapping_bag_holds_the_public_case_and_the_reference_outputs():
    case, stored = read_mapping_trace()
    assert case == public_mapping_case()
    assert stored == pytest.approx(list(case.expected), abs=1e-7)  # Float32 in the bag
    topics = read_topics(TRACE_DIR / "mapping_public.bag", ["/pub_force", "/force_mapped"])
    assert [t for t, _ in topics["/pub_force"]] == [t for t, _ in topics["/force_mapped"]], \
        "each expected output is stamped with its input"


def test_the_parts_bag_holds_the_public_pad_trace():
    case = read_parts_trace()
    public = public_teleop_parts_case()
    assert case.gains == public.gains and len(case.ticks) == len(public.ticks)
    for got, want in zip(case.ticks, public.ticks):
        assert got.buttons == want.buttons
        assert dict(got.axes) == pytest.approx(dict(want.axes), abs=1e-7)  # Joy axes are float32
        assert got.force == pytest.approx(want.force, abs=1e-7)


def test_the_node_bag_ends_at_rest_after_square():
    topics = read_topics(TRACE_DIR / "teleop_node_public.bag", ["/cartesian_velocity_controller/cmd_vel", "/gripper_width"])
    twists = [m for _, m in topics["/cartesian_velocity_controller/cmd_vel"]]
    assert max(m.linear.x for m in twists) > 0.05
    last = twists[-1]
    assert (last.linear.x, last.linear.y, last.linear.z, last.angular.x, last.angular.y, last.angular.z) == (0.0,) * 6
    widths = [m.data for _, m in topics["/gripper_width"]]
    assert widths[0] == pytest.approx(0.08) and widths[-1] == pytest.approx(0.04, abs=0.002)
