"""The grader's inputs and expected outputs (hri_teleop.grading.cases.inputs): public fixed, hidden seeded."""

from __future__ import annotations

from pathlib import Path

import pytest

from hri_teleop.core.mapping import map_force
from hri_teleop.grading.cases.inputs import PUBLIC_MAX_SENSOR_FORCE, seed_for
from hri_teleop.grading.exercises.mapping_node.cases import hidden_mapping_cases, public_mapping_case
from hri_teleop.grading.exercises.teleoperation.cases import (
    hidden_teleop_node_case,
    hidden_teleop_parts_case,
    public_teleop_node_case,
    public_teleop_parts_case,
    reference_parts,
)


def test_the_public_mapping_trace_covers_zero_the_maximum_above_it_and_noise():
    case = public_mapping_case()
    assert case == public_mapping_case(), "the public trace must not change between calls"
    assert case.max_sensor_force == PUBLIC_MAX_SENSOR_FORCE == 700
    counts = set(case.counts)
    assert {0, 700, 701, 1023} <= counts
    assert len([c for c in case.counts if c > 700]) >= 10
    assert len(counts) > 50
    assert case.expected == tuple(float(map_force(c, 700)) for c in case.counts)


@pytest.mark.parametrize("seed", [0, 1, 12345, 2 ** 31])
def test_hidden_mapping_cases_use_other_maxima_than_the_public_one_and_depend_on_the_seed(seed):
    cases = hidden_mapping_cases(seed)
    assert len(cases) == 2
    assert cases[0].max_sensor_force < 700 - 40 and cases[1].max_sensor_force > 700 + 40
    for case in cases:
        assert case.hidden and 0 in case.counts and case.max_sensor_force in case.counts
        assert any(c > case.max_sensor_force for c in case.counts)
    assert hidden_mapping_cases(seed) == cases
    assert hidden_mapping_cases(seed + 1) != cases


def test_seed_for_depends_on_the_last_path_components_only(tmp_path):
    a = seed_for(tmp_path / "submitted" / "alice" / "task4")
    assert a == seed_for(Path("/elsewhere/submitted/alice/task4"))
    assert a != seed_for(tmp_path / "submitted" / "bob" / "task4")


def test_reference_parts_follow_teleop_controller_rules():
    case = public_teleop_parts_case()
    expected = reference_parts(case)
    assert len(expected) == len(case.ticks)
    widths = [e.gripper_width for e in expected]
    assert min(widths) == 0.0 and max(widths) == 0.08, "the public trace drives the gripper to both ends"
    steps = {round(abs(a - b), 9) for a, b in zip(widths, widths[1:])}
    assert steps <= {0.0, round(case.gains.k_gripper / case.gains.rate, 9)}
    modes = [e.rotation_mode for e in expected]
    assert modes[0] is False and True in modes
    assert sum(1 for a, b in zip(modes, modes[1:]) if a != b) >= 4
    rumbles = {e.rumble for e in expected}
    assert {0.0, 1.0, 0.5} <= rumbles and all(0.0 <= r <= 1.0 for r in rumbles)
    for e in expected:
        assert e.cartesian_velocity == (e.velocity_if_rotation if e.rotation_mode else e.velocity_if_translation)
        assert all(v == 0.0 for v in (e.velocity_if_translation[3:] + e.velocity_if_rotation[:3]))
    assert max(e.velocity_if_translation[0] for e in expected) == pytest.approx(case.gains.k_trans)


def test_hidden_teleop_cases_change_gains_rate_and_dead_zone():
    public = public_teleop_parts_case()
    hidden = hidden_teleop_parts_case(99)
    assert hidden.gains != public.gains and hidden.hidden
    assert hidden == hidden_teleop_parts_case(99) and hidden != hidden_teleop_parts_case(100)
    reference_parts(hidden)  # the reference controller accepts the drawn rate and gains


def test_node_cases_expect_plateaus_within_the_default_velocity_limits():
    for case in (public_teleop_node_case(), hidden_teleop_node_case(5), hidden_teleop_node_case(6)):
        assert case.plateaus and all(abs(p.value) > 0.01 for p in case.plateaus)
        assert abs(case.plateaus[0].value) <= 0.25 and abs(case.plateaus[1].value) <= 0.5
        assert 0.0 < case.final_width < 0.08
        assert case.script[-1]["press"] == "west" and case.quit_s == case.script[-1]["t"]
