"""hri_teleop.core.paramfile: the calibration value goes into a student's file, and nothing else changes."""

from __future__ import annotations

import difflib
import os
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.paramfile import ParamFileError, set_in_launch, set_in_yaml, write_max_sensor_force

REPO = Path(__file__).resolve().parents[2]


def _changed_lines(before: str, after: str) -> list:
    return [line for line in difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0)
            if line[:1] in "+-" and not line.startswith(("+++", "---"))]


def test_a_literal_param_value_changes_and_every_other_character_stays():
    text = ('<launch> <!-- Ex. 12 g: max_sensor_force value="1" in a comment stays -->\n'
            '  <param name="max_sensor_force" value="700"/>   <!-- measured -->\n'
            '  <node name="m" pkg="hri_lab" type="mapping_node.py"/>\n</launch>\n')
    result, edits = set_in_launch(text, 688)
    assert result == text.replace('value="700"', 'value="688"')
    assert [(e.line, e.old, e.new) for e in edits] == [(2, "700", "688")]


def test_a_param_that_takes_an_arg_changes_the_args_default():
    text = ('<launch>\n  <arg name="msf" default="700" doc="counts"/>\n'
            '  <param name="max_sensor_force" value="$(arg msf)"/>\n</launch>\n')
    result, edits = set_in_launch(text, 512)
    assert _changed_lines(text, result) == ['-  <arg name="msf" default="700" doc="counts"/>',
                                            '+  <arg name="msf" default="512" doc="counts"/>']
    assert edits[0].what == '<arg name="msf"> default'


def test_an_arg_named_max_sensor_force_alone_is_used_when_no_param_sets_it():
    text = "<launch>\n  <arg name='max_sensor_force' default='700'/>\n  <include file='x.launch'/>\n</launch>\n"
    result, _ = set_in_launch(text, 650)
    assert "default='650'" in result and result.replace("650", "700") == text


def test_private_params_inside_a_node_are_not_the_global_parameter():
    text = ('<launch>\n  <node name="m" pkg="p" type="t">\n    <param name="max_sensor_force" value="1"/>\n'
            '  </node>\n  <param name="max_sensor_force" value="700"/>\n</launch>\n')
    result, edits = set_in_launch(text, 600)
    assert '<param name="max_sensor_force" value="1"/>' in result
    assert [e.line for e in edits] == [5]


def test_a_namespaced_group_hides_the_param_but_a_leading_slash_reaches_it():
    text = ('<launch>\n  <group ns="robot">\n    <param name="max_sensor_force" value="1"/>\n'
            '    <param name="/max_sensor_force" value="2"/>\n  </group>\n</launch>\n')
    result, edits = set_in_launch(text, 600)
    assert 'value="1"' in result and '"/max_sensor_force" value="600"' in result
    assert len(edits) == 1


def test_the_lab_and_solution_launch_files_take_the_value_in_one_line_each():
    for path in [REPO / "hri_lab/launch/teleoperation.launch", REPO / "hri_lab/launch/sensor.launch",
                 REPO / "solutions/hri_lab/launch/teleoperation.launch",
                 REPO / "solutions/hri_lab/launch/sensor.launch"]:
        text = path.read_text()
        result, edits = set_in_launch(text, 691, str(path))
        assert len(_changed_lines(text, result)) == 2, path
        assert edits and all(e.new == "691" for e in edits)


@pytest.mark.parametrize("text, words", [
    ("<launch>\n  <node name='a' pkg='b' type='c'/>\n</launch>\n", "no /max_sensor_force parameter"),
    ("<launch>\n  <param name='max_sensor_force' value='$(eval 7*100)'/>\n</launch>\n", "computed"),
    ("<launch>\n  <param name='max_sensor_force' value='$(arg nope)'/>\n</launch>\n", "no such <arg>"),
    ("<launch>\n  <param name='max_sensor_force' value='700'>\n</launch>\n", "not well-formed"),
    ("<launch>\n  <param name='max_sensor_force' command='cat x'/>\n</launch>\n", "no value attribute"),
])
def test_files_without_a_settable_param_are_refused_in_one_line(text, words):
    with pytest.raises(ParamFileError) as info:
        set_in_launch(text, 700, "my.launch")
    message = str(info.value)
    assert words in message and message.startswith("my.launch") and "\n" not in message


@pytest.mark.parametrize("value", [0, 1024, -3, 700.0, "700", True, None])
def test_only_integer_counts_1_to_1023_are_written(value):
    with pytest.raises(ParamFileError, match="integer ADC count"):
        set_in_launch("<launch><param name='max_sensor_force' value='700'/></launch>", value)


def test_yaml_keeps_comments_and_other_keys():
    text = ("# calibration (Ex. 11)\nrobot_name: FER\nmax_sensor_force: 700   # counts, piston pressed in\n"
            "gains: {p: 1}\n")
    result, edits = set_in_yaml(text, 677)
    assert result == text.replace("700", "677")
    assert yaml.safe_load(result)["max_sensor_force"] == 677
    assert edits[0].line == 3


@pytest.mark.parametrize("text, words", [
    ("robot_name: FER\n", "no top-level"),
    ("nested:\n  max_sensor_force: 700\n", "no top-level"),
    ("max_sensor_force: 700\nmax_sensor_force: 600\n", "set twice"),
    ("max_sensor_force: [700\n", "not valid YAML"),
    ("max_sensor_force:\n  - 700\n", "no value on its line"),
])
def test_yaml_without_a_plain_max_sensor_force_line_is_refused(text, words):
    with pytest.raises(ParamFileError, match=words):
        set_in_yaml(text, 700, "params.yaml")


def test_writing_a_file_replaces_it_in_place_keeping_its_mode(tmp_path):
    path = tmp_path / "teleoperation.launch"
    original = (REPO / "solutions/hri_lab/launch/teleoperation.launch").read_text()
    path.write_text(original)
    os.chmod(path, 0o640)
    edits = write_max_sensor_force(path, 642)
    assert path.read_text() == original.replace('name="max_sensor_force" value="700"',
                                                'name="max_sensor_force" value="642"')
    assert (path.stat().st_mode & 0o777) == 0o640
    assert edits[0].old == "700"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["teleoperation.launch"], "a temporary file was left"


def test_a_refused_file_is_left_untouched(tmp_path):
    path = tmp_path / "sensor.launch"
    path.write_text("<launch>\n  <node name='a' pkg='b' type='c'/>\n</launch>\n")
    before = path.read_bytes()
    with pytest.raises(ParamFileError, match=str(path)):
        write_max_sensor_force(path, 700)
    assert path.read_bytes() == before


def test_yaml_files_are_recognised_by_their_suffix(tmp_path):
    path = tmp_path / "calibration.yaml"
    path.write_text("max_sensor_force: 700\n")
    write_max_sensor_force(path, 701)
    assert path.read_text() == "max_sensor_force: 701\n"


def test_a_missing_file_names_the_path_and_what_to_give(tmp_path):
    with pytest.raises(ParamFileError, match="not found; give the path of your teleoperation.launch"):
        write_max_sensor_force(tmp_path / "nope.launch", 700)
