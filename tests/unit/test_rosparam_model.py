"""The rosparam commands of a notebook, worked out without a master (hri_teleop.core.rosparam_model).

Handout Ex. 3 and 4 are graded on what the student's commands do; the model must do what rosparam and the
master do (tests/integration/test_rosparam_model_vs_rosparam.py runs the same commands on a real master).
"""

from __future__ import annotations

from typing import Any, Dict, List

import pytest
import yaml

from hri_teleop.core.rosparam_model import (
    INT32_MAX,
    INT32_MIN,
    MAX_COMMANDS,
    ParamModel,
    RosparamModelError,
    dumped_to,
    file_reader,
    resolve_name,
    shell_commands,
    shell_lines,
    value_at,
    work_out,
    yaml_reader,
)
from hri_teleop.core.yamlfile import BoundedYamlError, load_bounded_all

YAML = yaml_reader(load_bounded_all, (yaml.YAMLError, BoundedYamlError))


def _files(files: Dict[str, str]):
    def read(name: str) -> bytes:
        if name not in files:
            raise FileNotFoundError(name)
        return files[name].encode()
    return file_reader(read)


def _run(lines: List[str], files: Dict[str, str] = None) -> ParamModel:
    model = ParamModel()
    model.notes = model.run_all(shell_commands(lines), YAML, _files(files or {}))  # type: ignore[attr-defined]
    return model


def _value(model: ParamModel, name: str) -> Any:
    found, value = model.get(name)
    assert found, (name, model.tree)
    return value


# --- which lines of a cell are shell commands ---------------------------------------------------------------


def test_bang_lines_are_commands_and_python_lines_are_not():
    cell = "x = 1\n!rosparam set /a 1\n  !rosparam set /b 2\nprint(x != 2)\n!!rosparam get /a\n%sx rosparam list"
    assert shell_lines(cell) == ["rosparam set /a 1", "rosparam set /b 2", "rosparam get /a", "rosparam list"]


def test_every_line_of_a_bash_cell_is_a_command_and_only_there():
    assert shell_lines("%%bash\nrosparam set /a 1\nrosparam set /b 2") == ["rosparam set /a 1", "rosparam set /b 2"]
    assert shell_lines("%%sh\nrosparam set /a 1") == ["rosparam set /a 1"]
    assert shell_lines("%%script bash\nrosparam set /a 1") == ["rosparam set /a 1"]
    assert shell_lines("# %%bash\nrosparam set /a 1") == []
    assert shell_lines("%%bashful\nrosparam set /a 1") == []


def test_a_trailing_backslash_goes_on_on_the_next_line():
    assert shell_lines("!rosparam set \\\n/a 1") == ["rosparam set /a 1"]
    assert shell_lines("!rosparam set /a \\") == ["rosparam set /a "]


def test_commands_split_at_the_shells_separators_and_keep_their_quotes():
    assert shell_commands(["!rosparam set /a 1; rosparam set /b \"[1, 'two']\" && echo ok | cat"]) == [
        ["rosparam", "set", "/a", "1"], ["rosparam", "set", "/b", "[1, 'two']"]]
    assert shell_commands(["!rosparam set /a 1 # a comment"]) == [["rosparam", "set", "/a", "1"]]


def test_an_open_quote_runs_nothing():
    assert shell_commands(["!rosparam set /a \"hello"]) == []


def test_a_command_for_another_master_is_left_out_and_other_variables_dropped():
    assert shell_commands(["!ROS_MASTER_URI=http://localhost:1 rosparam set /a 1"]) == []
    assert shell_commands(["!LANG=C /opt/ros/bin/rosparam set /a 1"]) == [["rosparam", "set", "/a", "1"]]
    assert shell_commands(["!rostopic list", "!echo rosparam set /a 1"]) == []


def test_no_more_than_the_cap_of_commands_is_taken():
    assert len(shell_commands(["!rosparam get /a\n" * (MAX_COMMANDS + 5)])) == MAX_COMMANDS


# --- names and values ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name, resolved", [("", "/"), ("/", "/"), ("a", "/a"), ("/a/b/", "/a/b"), ("a//b", "/a/b"),
                                            ("~p", "/rosparam/p")])
def test_names_resolve_as_rosparam_resolves_them(name, resolved):
    assert resolve_name(name) == resolved


@pytest.mark.parametrize("value, kind", [("7", int), ("-7", int), ("7.0", float), ("hello", str), ("'7'", str),
                                         ("[1, two]", list), ("true", bool), ("", str)])
def test_a_set_value_gets_the_type_yaml_gives_it(value, kind):
    model = ParamModel()
    model.run(["rosparam", "set", "/x", value], YAML, _files({}))
    assert type(_value(model, "/x")) is kind


def test_integers_stop_at_the_masters_32_bits_on_each_side():
    for good in (INT32_MAX, INT32_MIN):
        model = ParamModel()
        model.run(["rosparam", "set", "/x", str(good)], YAML, _files({}))
        assert _value(model, "/x") == good
    for bad in (INT32_MAX + 1, INT32_MIN - 1):
        with pytest.raises(RosparamModelError, match="32-bit"):
            ParamModel().run(["rosparam", "set", "/x", str(bad)], YAML, _files({}))


def test_null_cannot_be_set():
    with pytest.raises(RosparamModelError, match="null"):
        ParamModel().run(["rosparam", "set", "/x", "~"], YAML, _files({}))


def test_a_dictionary_updates_what_is_there_key_by_key():
    model = _run(["!rosparam set /g \"{p: 1, i: 2}\"", "!rosparam set /g \"{p: 10}\""])
    assert _value(model, "/g") == {"p": 10, "i": 2}


def test_a_value_replaces_a_namespace_and_a_namespace_replaces_a_value():
    model = _run(["!rosparam set /g/p 1", "!rosparam set /g 5"])
    assert _value(model, "/g") == 5
    model = _run(["!rosparam set /g 5", "!rosparam set /g/p 1"])
    assert _value(model, "/g") == {"p": 1}


@pytest.mark.parametrize("args, message", [(["/x"], "name and a value"), ([], "name and a value"),
                                           (["/x", "[1,", "two]"], "too many arguments"),
                                           (["/x", "1", "-q"], "no such option")])
def test_set_with_the_wrong_arguments_fails_as_rosparam_does(args, message):
    with pytest.raises(RosparamModelError, match=message):
        ParamModel().run(["rosparam", "set", *args], YAML, _files({}))


def test_a_negative_number_is_a_value_not_an_option():
    model = _run(["!rosparam set /x -3", "!rosparam set -v /y -0.5"])
    assert _value(model, "/x") == -3 and _value(model, "/y") == -0.5


def test_set_from_a_text_file_takes_its_text():
    model = _run(["!rosparam set -t notes.txt /x"], {"notes.txt": "7\n"})
    assert _value(model, "/x") == "7\n"


# --- load, delete, dump -------------------------------------------------------------------------------------------


def test_load_merges_the_file_into_the_root_or_the_namespace_given():
    files = {"c.yaml": "robot_mass: 18.0\ngains: {p: 10.0}\n"}
    model = _run(["!rosparam load c.yaml", "!rosparam load c.yaml /copy"], files)
    assert _value(model, "/robot_mass") == 18.0 and _value(model, "/copy/gains") == {"p": 10.0}
    assert _value(model, "/rosdistro")  # what roscore put there stays


def test_load_honours_ns_in_each_document():
    model = _run(["!rosparam load c.yaml /top"], {"c.yaml": "_ns: a\nx: 1\n---\ny: 2\n"})
    assert _value(model, "/top/a/x") == 1 and _value(model, "/top/y") == 2


@pytest.mark.parametrize("files, name, message", [
    ({}, "missing.yaml", "does not exist"),
    ({"c.yaml": "[1, 2]"}, "c.yaml", "global / can only be set to a dictionary"),
    ({"c.yaml": "a: [1"}, "c.yaml", "not YAML"),
    ({}, "/etc/passwd", "outside your assignment"),
    ({}, "../other/c.yaml", "outside your assignment"),
])
def test_a_load_that_rosparam_refuses_fails_with_the_cause(files, name, message):
    with pytest.raises(RosparamModelError, match=message):
        ParamModel().run(["rosparam", "load", name], YAML, _files(files))


def test_delete_takes_a_parameter_out_and_fails_on_one_not_set():
    model = _run(["!rosparam set /a/b 1", "!rosparam set /a/c 2", "!rosparam delete /a/b"])
    assert _value(model, "/a") == {"c": 2}
    with pytest.raises(RosparamModelError, match="not set"):
        model.run(["rosparam", "delete", "/a/b"], YAML, _files({}))
    model.run(["rosparam", "delete", "/"], YAML, _files({}))
    assert model.tree == {}


def test_a_dump_records_the_tree_below_its_namespace():
    model = _run(["!rosparam set /a/b 1", "!rosparam dump all.yaml", "!rosparam dump a.yaml /a"])
    assert sorted(model.dumps[0].tree) == ["a", "rosdistro", "roslaunch", "rosversion", "run_id"]
    assert model.dumps[1].tree == {"b": 1}
    assert dumped_to(model.dumps, "./a.yaml") is model.dumps[1] and dumped_to(model.dumps, "b.yaml") is None
    with pytest.raises(RosparamModelError, match="not set"):
        model.run(["rosparam", "dump", "x.yaml", "/nothing"], YAML, _files({}))


def test_a_failing_command_leaves_a_note_and_the_ones_after_it_run():
    tree, dumps, notes = work_out([["rosparam", "set", "/x"], ["rosparam", "set", "/y", "1"]], YAML, _files({}))
    assert value_at(tree, "/y") == (True, 1) and value_at(tree, "/x") == (False, None)
    assert notes == ["`rosparam set /x` fails: rosparam set: give a parameter name and a value"]
    assert dumps == []


def test_a_python_tag_in_a_value_runs_nothing_and_is_refused_as_rosparam_refuses_it(tmp_path):
    marker = tmp_path / "ran"
    _tree, _dumps, notes = work_out([["rosparam", "set", "/x", f"!!python/object/apply:os.system ['touch {marker}']"],
                                     ["rosparam", "load", "evil.yaml"]], YAML,
                                    _files({"evil.yaml": f"x: !!python/object/apply:os.system ['touch {marker}']\n"}))
    assert not marker.exists()
    assert len(notes) == 2 and all("not YAML rosparam reads" in n for n in notes), notes
