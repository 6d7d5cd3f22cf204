"""hri_teleop.core.paramfile: the calibration value goes into a student's file, and nothing else changes."""

from __future__ import annotations

import difflib
import os
from pathlib import Path

import numpy as np
import pytest
import yaml

from hri_teleop.core.paramfile import ParamEdit, ParamFileError, set_in_launch, set_in_yaml, write_max_sensor_force

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


# -- the edges, exact messages and the file's kind (make mutants) --------------------------------------------------

ONE_PARAM = "<launch>\n  <param name='max_sensor_force' value='700'/>\n</launch>\n"


@pytest.mark.parametrize("value, written", [(1, "1"), (2, "2"), (1022, "1022"), (1023, "1023"),
                                            (np.int64(691), "691"), (np.int16(5), "5")])
def test_counts_from_1_to_1023_and_numpy_integers_are_written(value, written):
    result, edits = set_in_launch(ONE_PARAM, value, "my.launch")
    assert result == ONE_PARAM.replace("'700'", f"'{written}'")
    assert edits == [ParamEdit(2, "700", written, '<param name="max_sensor_force"> value')]


@pytest.mark.parametrize("value", [0, 1024, np.int64(0), np.int64(1024), np.float64(700.0), np.bool_(True)])
def test_a_count_of_0_or_1024_or_a_numpy_float_is_refused_naming_the_file(value):
    with pytest.raises(ParamFileError) as info:
        set_in_launch(ONE_PARAM, value, "my.launch")
    assert str(info.value) == (f"my.launch: /max_sensor_force must be an integer ADC count 1..1023, got {value!r}; "
                               "calibrate again with the piston pressed in")


def test_a_bad_count_for_a_yaml_file_names_the_file():
    with pytest.raises(ParamFileError) as info:
        set_in_yaml("max_sensor_force: 700\n", 1024, "params.yaml")
    assert str(info.value) == ("params.yaml: /max_sensor_force must be an integer ADC count 1..1023, got 1024; "
                               "calibrate again with the piston pressed in")


def test_a_launch_text_without_a_source_is_named_launch_in_messages():
    with pytest.raises(ParamFileError) as info:
        set_in_launch("<launch>\n  <node name='a' pkg='b' type='c'/>\n</launch>\n", 700)
    assert str(info.value) == ('<launch>: no /max_sensor_force parameter to set; add <param name="max_sensor_force" '
                               'value="700"/> inside <launch> (Ex. 12 g) and calibrate again')


def test_a_yaml_text_without_a_source_is_named_yaml_in_messages():
    with pytest.raises(ParamFileError) as info:
        set_in_yaml("robot_name: FER\n", 700)
    assert str(info.value) == ("<yaml>: no top-level `max_sensor_force: ...` line; add `max_sensor_force: 700` at the "
                               "start of a line and calibrate again")


def test_xml_that_is_not_well_formed_is_refused_with_the_line_of_the_mistake():
    text = "<launch>\n  <param name='max_sensor_force' value='700'>\n</launch>\n"  # line 3 closes the wrong tag
    with pytest.raises(ParamFileError) as info:
        set_in_launch(text, 700, "my.launch")
    assert str(info.value) == ("my.launch:3: not well-formed XML (mismatched tag); fix the file first (roslaunch "
                               "would refuse it too)")


def test_a_param_without_a_value_is_refused_at_its_own_line():
    text = "<launch>\n\n  <node name='a' pkg='b' type='c'/>\n  <param name='max_sensor_force' command='cat x'/>\n</launch>\n"
    with pytest.raises(ParamFileError) as info:
        set_in_launch(text, 700, "my.launch")
    assert str(info.value) == ('my.launch:4: <param name="max_sensor_force"> has no value attribute; write it as '
                               '<param name="max_sensor_force" value="700"/>')


def test_a_newline_at_the_very_start_of_the_file_counts_as_line_1():
    result, edits = set_in_launch("\n" + ONE_PARAM, 650)
    assert [e.line for e in edits] == [3]
    result, edits = set_in_yaml("\nmax_sensor_force: 700\n", 650)
    assert edits == [ParamEdit(2, "700", "650", "max_sensor_force:")]


def test_an_arg_given_by_value_changes_its_value():
    text = ('<launch>\n  <arg name="msf" value="700"/>\n'
            '  <param name="max_sensor_force" value="$(arg msf)"/>\n</launch>\n')
    result, edits = set_in_launch(text, 512)
    assert result == text.replace('value="700"', 'value="512"')
    assert edits == [ParamEdit(2, "700", "512", '<arg name="msf"> value')]


def test_an_arg_named_max_sensor_force_given_by_value_changes_its_value_when_no_param_sets_it():
    text = '<launch>\n  <arg name="max_sensor_force" value="700"/>\n</launch>\n'
    result, edits = set_in_launch(text, 512)
    assert result == text.replace('"700"', '"512"')
    assert edits == [ParamEdit(2, "700", "512", '<arg name="max_sensor_force"> value')]


def test_arg_msf_means_the_arg_declared_so_not_another_element_of_that_name():
    for node in ('  <node name="msf" pkg="p" type="t"/>\n', '  <node name="max_sensor_force" pkg="p" type="t"/>\n'):
        text = ('<launch>\n' + node + '  <arg name="msf" default="700"/>\n'
                '  <param name="max_sensor_force" value="$(arg msf)"/>\n' + node + '</launch>\n')
        result, edits = set_in_launch(text, 512)
        assert result == text.replace('default="700"', 'default="512"')
        assert edits == [ParamEdit(3, "700", "512", '<arg name="msf"> default')]


def test_every_param_setting_it_changes_once_and_an_arg_they_share_once_however_long_the_values():
    text = ('<launch>\n'
            '  <arg name="msf" default="50"/>\n'
            '  <param name="max_sensor_force" value="7"/>\n'
            '  <param if="$(arg sim)" name="max_sensor_force" value="$(arg msf)"/>\n'
            '  <param unless="$(arg sim)" name="max_sensor_force" value="$(arg msf)"/>\n'
            '  <param name="/max_sensor_force" value="700"/>\n'
            '</launch>\n')
    result, edits = set_in_launch(text, 1000)
    assert result == ('<launch>\n'
                      '  <arg name="msf" default="1000"/>\n'
                      '  <param name="max_sensor_force" value="1000"/>\n'
                      '  <param if="$(arg sim)" name="max_sensor_force" value="$(arg msf)"/>\n'
                      '  <param unless="$(arg sim)" name="max_sensor_force" value="$(arg msf)"/>\n'
                      '  <param name="/max_sensor_force" value="1000"/>\n'
                      '</launch>\n')
    assert edits == [ParamEdit(2, "50", "1000", '<arg name="msf"> default'),
                     ParamEdit(3, "7", "1000", '<param name="max_sensor_force"> value'),
                     ParamEdit(6, "700", "1000", '<param name="/max_sensor_force"> value')]


def test_a_param_inside_a_test_node_is_private_to_it():
    text = ('<launch>\n  <test test-name="t" pkg="p" type="t">\n    <param name="max_sensor_force" value="1"/>\n'
            '  </test>\n  <param name="max_sensor_force" value="700"/>\n</launch>\n')
    result, edits = set_in_launch(text, 600)
    assert result == text.replace('"700"', '"600"')
    assert [e.line for e in edits] == [5]


def test_an_arg_passed_to_an_include_sets_it_but_not_to_an_include_in_a_namespace():
    passed = ('<launch>\n  <include file="sensor.launch">\n    <arg name="max_sensor_force" value="700"/>\n'
              '  </include>\n</launch>\n')
    result, edits = set_in_launch(passed, 600)
    assert result == passed.replace('"700"', '"600"')
    assert edits == [ParamEdit(3, "700", "600", '<arg name="max_sensor_force"> value')]
    for ns in ("/", " "):
        result, _ = set_in_launch(passed.replace('<include ', f'<include ns="{ns}" '), 600)
        assert '"600"' in result
    # sensor.launch's params go to /robot/max_sensor_force there: not the global parameter
    with pytest.raises(ParamFileError, match="no /max_sensor_force parameter to set"):
        set_in_launch(passed.replace('<include ', '<include ns="robot" '), 600)


def test_a_namespace_of_slash_or_blank_is_the_global_one():
    text = ('<launch>\n  <group ns="NS">\n    <param name="max_sensor_force" value="700"/>\n'
            '  </group>\n</launch>\n')
    for ns in ("/", "", "  "):
        result, edits = set_in_launch(text.replace("NS", ns), 600)
        assert result == text.replace("NS", ns).replace('"700"', '"600"')


def test_yaml_that_is_not_valid_is_refused_with_the_line_of_the_mistake():
    with pytest.raises(ParamFileError) as info:
        set_in_yaml("robot_name: FER\nmax_sensor_force: [700\n", 700, "params.yaml")
    assert str(info.value) == "params.yaml:3: not valid YAML; fix the file first (rosparam load would refuse it too)"


def test_yaml_with_a_character_yaml_forbids_is_refused_without_a_line():
    with pytest.raises(ParamFileError) as info:
        set_in_yaml("robot_name: \x07\nmax_sensor_force: 700\n", 700, "params.yaml")
    assert str(info.value) == "params.yaml: not valid YAML; fix the file first (rosparam load would refuse it too)"


def test_a_quoted_yaml_key_is_set_and_named_without_its_quotes():
    for key in ('"max_sensor_force"', "'max_sensor_force'", "'/max_sensor_force'"):
        text = f"a: 1\n{key}: 700  # counts\n"
        result, edits = set_in_yaml(text, 677)
        assert result == f"a: 1\n{key}: 677  # counts\n"
        assert edits == [ParamEdit(2, "700", "677", key.strip("\"'") + ":")]


def test_yaml_whose_value_an_alias_elsewhere_needs_is_refused_not_broken():
    text = "max_sensor_force: &m 700\nother: *m\n"
    with pytest.raises(ParamFileError) as info:
        set_in_yaml(text, 691, "params.yaml")
    assert str(info.value) == ("params.yaml: could not set max_sensor_force without changing the file's structure; "
                               "write it as a plain line `max_sensor_force: 700`")


def test_a_yaml_line_inside_a_quoted_text_is_not_the_key():
    text = 'note: "x\nmax_sensor_force: 700 # "\n'
    with pytest.raises(ParamFileError, match="could not set max_sensor_force without changing the file's structure"):
        set_in_yaml(text, 691, "params.yaml")


XML_TEXT = "<launch>\n  <param name='max_sensor_force' value='700'/>\n</launch>\n"
YAML_TEXT = "max_sensor_force: 700\n"


@pytest.mark.parametrize("name", ["teleop.launch", "teleop.xml", "TELEOP.LAUNCH", "teleop.XML"])
def test_a_launch_or_xml_file_is_read_as_xml_whatever_its_text(tmp_path, name):
    path = tmp_path / name
    path.write_text(YAML_TEXT)
    with pytest.raises(ParamFileError, match="not well-formed XML"):
        write_max_sensor_force(path, 650)
    assert path.read_text() == YAML_TEXT
    path.write_text(XML_TEXT)
    assert write_max_sensor_force(path, 650)[0].what == '<param name="max_sensor_force"> value'


@pytest.mark.parametrize("name", ["calibration.yaml", "calibration.yml", "CALIBRATION.YAML", "calibration.YML"])
def test_a_yaml_or_yml_file_is_read_as_yaml_whatever_its_text(tmp_path, name):
    path = tmp_path / name
    path.write_text(XML_TEXT)
    with pytest.raises(ParamFileError, match="no top-level"):
        write_max_sensor_force(path, 650)
    assert path.read_text() == XML_TEXT
    path.write_text("<<: {a: 1}\n" + YAML_TEXT)  # a YAML merge key: YAML though it starts with '<'
    write_max_sensor_force(path, 650)
    assert path.read_text() == "<<: {a: 1}\nmax_sensor_force: 650\n"


@pytest.mark.parametrize("name", ["calibration", "calibration.txt"])
def test_a_file_of_another_kind_is_xml_when_its_text_starts_with_a_tag(tmp_path, name):
    path = tmp_path / name
    path.write_text("\n  " + XML_TEXT)
    write_max_sensor_force(path, 650)
    assert path.read_text() == "\n  " + XML_TEXT.replace("700", "650")
    path.write_text("\n" + YAML_TEXT)
    write_max_sensor_force(path, 650)
    assert path.read_text() == "\nmax_sensor_force: 650\n"


def test_arg_msf_means_its_declaration_not_an_include_passing_it_on():
    text = ('<launch>\n  <arg name="msf" default="700"/>\n'
            '  <param name="max_sensor_force" value="$(arg msf)"/>\n'
            '  <include file="sensor.launch">\n    <arg name="msf" value="$(arg msf)"/>\n  </include>\n</launch>\n')
    result, edits = set_in_launch(text, 691)
    assert result == text.replace('default="700"', 'default="691"')  # the include still passes $(arg msf) on
    assert edits == [ParamEdit(2, "700", "691", '<arg name="msf"> default')]
