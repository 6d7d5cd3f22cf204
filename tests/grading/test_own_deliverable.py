"""Each check judges its own deliverable (issue: grading is fair): a launch file's run uses the lab's
mapping_node.py, robot_params.yaml and teleoperation.py, so a file scores the same alone and in its
package, and a broken Ex. 5 costs points in Ex. 5 only."""

from __future__ import annotations

import pytest
from grading_helpers import answer_text, write_package

pytestmark = pytest.mark.ros

BROKEN_NODE = "#!/usr/bin/env python3\nraise SystemExit('this mapping node is broken')\n"


def test_a_correct_sensor_launch_with_ex7_gets_full_marks_graded_alone(tmp_path):
    from hri_teleop.grading.exercises.sensor_launch.check import grade_sensor_launch

    launch = tmp_path / "sensor.launch"
    launch.write_text(answer_text("launch/sensor.launch"))
    result = grade_sensor_launch(launch, seed=1)
    assert result.score == result.max_score, result.failed_parts
    assert any("ran the lab's mapping_node.py, robot_params.yaml" in n for n in result.notes)


def test_a_broken_mapping_node_costs_points_in_its_own_check_only(tmp_path):
    from hri_teleop.grading.exercises.mapping_node.check import grade_mapping_node
    from hri_teleop.grading.exercises.sensor_launch.check import grade_sensor_launch

    package = write_package(tmp_path / "hri_lab", {
        "package.xml": answer_text("package.xml"),
        "launch/sensor.launch": answer_text("launch/sensor.launch"),
        "scripts/mapping_node.py": BROKEN_NODE,
    })
    launch = grade_sensor_launch(package, seed=1)
    assert launch.score == launch.max_score, launch.failed_parts
    node = grade_mapping_node(package, seed=1)
    assert node.score == 0


def test_a_correct_teleoperation_launch_gets_full_marks_graded_alone(tmp_path):
    from hri_teleop.grading.exercises.teleoperation_launch.check import grade_teleoperation_launch

    launch = tmp_path / "teleoperation.launch"
    launch.write_text(answer_text("launch/teleoperation.launch"))
    result = grade_teleoperation_launch(launch, seed=1)
    assert result.score == result.max_score, result.failed_parts
    assert any("teleoperation.py" in n and "in place of yours" in n for n in result.notes)


def test_the_students_own_file_is_never_replaced_by_the_lab_one(tmp_path):
    from hri_teleop.grading.run.workspace import prepare_workspace

    package = write_package(tmp_path / "hri_lab", {
        "package.xml": answer_text("package.xml"),
        "scripts/mapping_node.py": BROKEN_NODE,
    })
    space = prepare_workspace(package / "scripts" / "mapping_node.py", tmp_path / "session",
                              single_file=package / "scripts" / "mapping_node.py", single_key="mapping_node",
                              reference=("mapping_node", "robot_params"))
    assert space.substituted == ["robot_params"]
    assert (space.package / "scripts" / "mapping_node.py").read_text() == BROKEN_NODE


def test_without_the_labs_yaml_an_ex7_load_counts_as_ex7_not_done_not_as_a_parse_failure(tmp_path, monkeypatch):
    """The student bundle's toolkit has no robot_params.yaml: a launch file graded alone still parses."""
    import shutil

    import hri_teleop.grading.run.workspace as workspace
    from hri_teleop.course.bundle import LAB_DELIVERABLES
    from hri_teleop.grading.exercises.sensor_launch.check import grade_sensor_launch

    toolkit_lab = tmp_path / "toolkit" / "hri_lab"
    shutil.copytree(workspace.REFERENCE_PACKAGE, toolkit_lab)
    for relative in LAB_DELIVERABLES:
        (tmp_path / "toolkit" / relative).unlink()
    monkeypatch.setattr(workspace, "REFERENCE_PACKAGE", toolkit_lab)
    launch = tmp_path / "sensor.launch"
    launch.write_text(answer_text("launch/sensor.launch"))
    result = grade_sensor_launch(launch, seed=1)
    assert result.part(result.parts[0].name).passed, result.parts[0].message
    assert "Ex. 7 (voluntary) not done" in result.parts[3].note
    assert not any("in place of yours" in n for n in result.notes)
