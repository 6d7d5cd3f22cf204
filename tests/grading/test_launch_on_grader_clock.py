"""teleoperation.launch under grading runs on the grader's clock: lab_sim, the lab's teleoperation
node and gripper_manager follow /clock, and each step waits until lab_sim has applied the tick's
command. The same twists and the same arm path come out idle and with both cores busy."""

from __future__ import annotations

import pytest
from grading_helpers import answer_text, busy_cores, write_package

from hri_teleop.grading.exercises.sensor_launch import check as sensor_check
from hri_teleop.grading.exercises.sensor_launch.judge import compare_sensor_launch
from hri_teleop.grading.exercises.teleoperation_launch import check as launch_check
from hri_teleop.grading.exercises.teleoperation_launch.judge import compare_teleop_launch_sim

pytestmark = pytest.mark.ros

TWIST = "/cartesian_velocity_controller/cmd_vel"


def _same_series(a, b, at_least):
    """(time, value) series of two runs: the same messages at the same simulated times."""
    assert len(a) >= at_least, (len(a), len(b))
    assert a == b


def _observe(package, loaded: bool):

    from hri_teleop.grading.exercises.teleoperation_launch.check import grade_teleoperation_launch

    seen = []
    original = compare_teleop_launch_sim

    def spy(parsed, observation, *args, **kwargs):
        seen.append(observation)
        return original(parsed, observation, *args, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(launch_check, "compare_teleop_launch_sim", spy)
        if loaded:
            with busy_cores(2):
                result = grade_teleoperation_launch(package)
        else:
            result = grade_teleoperation_launch(package)
    return result, seen[0]


def test_the_launch_check_gives_the_same_twists_and_arm_path_idle_and_loaded(tmp_path):
    package = write_package(tmp_path / "hri_lab", {"package.xml": answer_text("package.xml"),
                                                   "launch/teleoperation.launch": answer_text("launch/teleoperation.launch")})
    runs = [_observe(package, loaded) for loaded in (False, True)]
    for result, observation in runs:
        assert result.score == result.max_score, result.failed_parts
        assert observation.clock == "grader", observation.lab_sim_log
        assert not any("real time" in n for n in result.notes)
    (_, idle), (_, loaded) = runs
    twists = [[(t, v) for t, _k, v in o.messages[TWIST]] for o in (idle, loaded)]
    _same_series(*twists, at_least=200)
    # The arm's path depends on when lab_sim applied each command; the poses' publication
    # times do not matter. Where it went and where it stopped are the same.
    z = [[v[2] for _t, _k, v in o.messages["/lab_sim/ee_pose"]] for o in (idle, loaded)]
    assert max(z[0]) - z[0][0] > 0.02  # the pad lifted the arm
    assert max(z[0]) == pytest.approx(max(z[1]), abs=1e-9)
    assert z[0][-1] == pytest.approx(z[1][-1], abs=1e-9)


def test_the_sensor_launch_pairs_the_same_counts_and_mappings_idle_and_loaded(tmp_path):

    from hri_teleop.grading.exercises.sensor_launch.check import grade_sensor_launch

    package = write_package(tmp_path / "hri_lab", {"package.xml": answer_text("package.xml"),
                                                   "launch/sensor.launch": answer_text("launch/sensor.launch")})
    seen = []
    original = compare_sensor_launch

    def spy(parsed, observation, *args, **kwargs):
        seen.append(observation)
        return original(parsed, observation, *args, **kwargs)

    results = []
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(sensor_check, "compare_sensor_launch", spy)
        results.append(grade_sensor_launch(package))
        with busy_cores(2):
            results.append(grade_sensor_launch(package))
    for result, observation in zip(results, seen):
        assert result.score == result.max_score, result.failed_parts
        assert observation.clock == "grader"
    series = [[(t, v) for t, _k, v in o.force_mapped] for o in seen]
    counts = [[(t, v) for t, _k, v in o.pub_force] for o in seen]
    _same_series(*series, at_least=9)
    _same_series(*counts, at_least=9)
