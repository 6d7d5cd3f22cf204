"""The rosparam commands of a notebook, worked out without a master (hri_teleop.core.rosparam_model).

Handout Ex. 3 and 4 are graded on what the student's commands do; the model must do what rosparam and the
master do (tests/integration/test_rosparam_model_vs_rosparam.py runs the same commands on a real master).
"""

from __future__ import annotations

import datetime
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


# --- the edges make mutants found (issue 44): each rule, and each threshold, fails a test when changed ------------


def _model(lines: List[str], files: Dict[str, str] = None) -> ParamModel:
    """``lines`` run as a notebook's cells; a command that fails raises (rosparam's refusal)."""
    model = ParamModel()
    for argv in shell_commands(lines):
        model.run(argv, YAML, _files(files or {}))
    return model


def _refused(line: str, files: Dict[str, str] = None) -> str:
    model = ParamModel()
    (argv,) = shell_commands([line])
    with pytest.raises(RosparamModelError) as caught:
        model.run(argv, YAML, _files(files or {}))
    return str(caught.value)


def test_an_empty_cell_has_no_commands():
    assert shell_lines("") == [] and shell_commands([""]) == []


def test_a_bash_cell_keeps_its_lines_as_written_and_its_magic_may_take_options():
    assert shell_lines("%%bash\n  rosparam set /a 1") == ["  rosparam set /a 1"]
    assert shell_lines("%%bash --no-raise-error\nrosparam set /a 1") == ["rosparam set /a 1"]


def test_a_word_is_split_only_at_spaces_and_the_shells_separators():
    assert shell_commands(["!rosparam set /MAX_X x:y,z"]) == [["rosparam", "set", "/MAX_X", "x:y,z"]]


def test_leading_variables_are_dropped_whatever_their_value_and_a_word_with_two_equals_is_one_variable():
    assert shell_commands(["!LANG=C.UTF-8 A=b=c rosparam set /a 1"]) == [["rosparam", "set", "/a", "1"]]
    assert shell_commands(["!X=1", "!=x rosparam set /a 1", "!1X=2 rosparam set /a 1"]) == []
    assert shell_commands(["!ROS_MASTER_URI=http://localhost:1/?a=b rosparam set /a 1"]) == []


def test_a_name_resolves_the_same_relative_or_absolute_and_private_under_rosparam():
    model = _model(["!rosparam set a/b 1", "!rosparam set /c 2", "!rosparam set ~p 3"])
    assert model.get("/a/b") == (True, 1) and model.get("c") == (True, 2) and model.get("/rosparam/p") == (True, 3)
    assert resolve_name("~") == "/rosparam"


def test_an_empty_value_is_the_empty_text():
    assert _value(_model(["!rosparam set /x ''"]), "/x") == ""


def test_a_list_holds_only_what_the_master_holds_and_the_refusal_names_the_parameter():
    model = _model(["!rosparam set /ok \"[{a: 1}, [2]]\""])
    assert _value(model, "/ok") == [{"a": 1}, [2]]
    assert _refused("!rosparam set /x \"[{1: a}]\"").endswith("/x: YAML dictionaries must have string keys")
    assert _refused("!rosparam set /x \"[{a: 2147483648}]\"").startswith("/x: 2147483648 is beyond")
    assert _refused("!rosparam set /x \"[1, [2147483648]]\"").startswith("/x: 2147483648 is beyond")


def test_a_date_and_time_is_held_and_a_date_alone_is_refused():
    assert _value(_model(["!rosparam set /t '2020-01-01 10:00:00'"]), "/t") == datetime.datetime(2020, 1, 1, 10)
    assert "cannot hold date" in _refused("!rosparam set /t 2020-01-01")


def test_the_root_takes_a_dictionary_key_by_key_and_refuses_any_other_value():
    model = _model(["!rosparam set / \"{a: 1}\""])
    assert _value(model, "/a") == 1 and _value(model, "/rosdistro")
    assert "global / can only be set to a dictionary" in _refused("!rosparam set / 5")


def test_a_dictionarys_absolute_key_is_set_where_it_points_not_under_the_name():
    model = _model(["!rosparam set /g \"{/abs: 1, b: {c: 2}}\""])
    assert _value(model, "/abs") == 1 and _value(model, "/g") == {"b": {"c": 2}}


def test_a_dictionarys_private_key_is_not_put_under_the_name():
    # rosparam puts it under its own process (/rosparam-<pid>/p); the model, as for `rosparam set ~p`, under /rosparam
    model = _model(["!rosparam set /g \"{~p: 1, b: 2}\""])
    assert _value(model, "/g") == {"b": 2} and _value(model, "/rosparam/p") == 1


def test_the_model_keeps_its_own_copy_of_a_set_value():
    model = ParamModel()
    value = [[1]]
    model.set("/x", value)
    value[0].append(2)
    assert _value(model, "/x") == [[1]]


@pytest.mark.parametrize("line, name, value", [
    ("!rosparam set -v /x 1", "/x", 1),
    ("!rosparam set /x -9", "/x", -9),
    ("!rosparam set /x -0", "/x", 0),
    ("!rosparam set -t notes.txt /x", "/x", "7\n"),
    ("!rosparam set --textfile notes.txt /x", "/x", "7\n"),
    ("!rosparam set --textfile=notes.txt /x", "/x", "7\n"),
    ("!rosparam set -b notes.txt /x", "/x", b"7\n"),
    ("!rosparam set --binfile notes.txt /x", "/x", b"7\n"),
    ("!rosparam set -bnotes.txt /x", "/x", b"7\n"),
    ("!rosparam set -t notes.txt /x ignored", "/x", "7\n"),
    ("!rosparam load -v c.yaml /x", "/x/k", 1),
])
def test_set_and_load_read_their_options_as_rosparam_does(line, name, value):
    assert _value(_model([line], {"notes.txt": "7\n", "c.yaml": "k: 1\n"}), name) == value


@pytest.mark.parametrize("line, message", [
    ("!rosparam set -p /x 1", "no such option: -p"),
    ("!rosparam set -t -x /x", "require an argument"),
    ("!rosparam set /x -t", "-t option requires 1 argument"),
    ("!rosparam set -t notes.txt -b notes.txt /x", "only one of"),
    ("!rosparam set --binfile=notes.txt --textfile=notes.txt /x", "only one of"),
    ("!rosparam set /x -y", "no such option: -y"),
    ("!rosparam delete -3", "no such option: -3"),
    ("!rosparam load -x c.yaml", "no such option: -x"),
    ("!rosparam dump -p d.yaml", "no such option: -p"),
    ("!rosparam load -", "reads the terminal"),
    ("!rosparam load ''", "reads the terminal"),
    ("!rosparam load c.yaml /a /b", "give a file and at most a namespace"),
    ("!rosparam delete", "give one parameter name"),
    ("!rosparam delete /a /b", "give one parameter name"),
    ("!rosparam dump d.yaml /a /b", "give a file and at most a namespace"),
])
def test_an_option_or_argument_rosparam_refuses_is_refused(line, message):
    assert message in _refused(line, {"notes.txt": "7\n", "c.yaml": "k: 1\n"})


def test_help_does_nothing_else():
    model = _model(["!rosparam set -h /x 1", "!rosparam delete -h /rosdistro", "!rosparam dump --help d.yaml"])
    assert model.get("/x") == (False, None) and _value(model, "/rosdistro") and model.dumps == []


def test_delete_and_dump_take_the_verbose_option():
    model = _model(["!rosparam set /a/b 1", "!rosparam set /c 1", "!rosparam dump -v d.yaml /a", "!rosparam delete -v /c"])
    assert model.get("/c") == (False, None) and model.dumps[0].tree == {"b": 1}


def test_delete_takes_out_exactly_the_name_at_any_depth():
    model = _model(["!rosparam set /a/b/c 1", "!rosparam set /a/b/d 2", "!rosparam set /a/e 3",
                    "!rosparam delete /a/b/c"])
    assert _value(model, "/a") == {"b": {"d": 2}, "e": 3}
    model.run(["rosparam", "delete", "a"], YAML, _files({}))
    assert model.get("/a") == (False, None) and _value(model, "/rosdistro")


def test_a_dump_records_its_namespace_and_a_copy_later_commands_leave_alone():
    model = _model(["!rosparam set /a/b/c 1", "!rosparam dump d.yaml a", "!rosparam set /a/b/c 2"])
    assert model.dumps[0].namespace == "/a" and model.dumps[0].tree == {"b": {"c": 1}}


def test_a_dump_without_a_file_writes_nothing_but_still_needs_its_namespace_set():
    model = _model(["!rosparam dump", "!rosparam dump '' /rosdistro"])
    assert model.dumps == []
    assert "parameter [/nothing] is not set" in _refused("!rosparam dump '' /nothing")


@pytest.mark.parametrize("text, where", [
    ("_ns: /abs\nx: 1\n", "/abs/x"),      # a global _ns is not put under the namespace given
    ("_ns: rel\nx: 1\n", "/top/rel/x"),
    ("_ns: ''\nx: 1\n", "/top/x"),
    ("x: 1\n", "/top/x"),
])
def test_load_puts_a_document_where_its_ns_points(text, where):
    assert _value(_model(["!rosparam load c.yaml /top"], {"c.yaml": text}), where) == 1


def test_load_sets_a_list_or_a_text_into_a_namespace_and_refuses_them_at_the_root():
    model = _model(["!rosparam load l.yaml /l", "!rosparam load t.yaml /t"], {"l.yaml": "[1, 2]\n", "t.yaml": "hi\n"})
    assert _value(model, "/l") == [1, 2] and _value(model, "/t") == "hi"
    assert "global / can only be set" in _refused("!rosparam load t.yaml", {"t.yaml": "hi\n"})


@pytest.mark.parametrize("text", [
    "a: 1\n---\n",                 # an empty document (a trailing ---)
    "a: 1\n---\n5\n",              # a number
    "a: 1\n---\n2147483648\n",      # a number the master could not hold either
    "a: 1\n---\n_ns is here\n",    # a text holding _ns
    "a: 1\n---\n[x, _ns]\n",       # a list holding _ns
    "a: 1\n---\n_ns: 5\nb: 2\n",   # a _ns that is not a name
])
def test_a_document_rosparam_cannot_look_into_stops_the_load_before_anything_is_set(text):
    model = ParamModel()
    with pytest.raises(RosparamModelError, match="nothing is loaded"):
        model.run(["rosparam", "load", "c.yaml", "/top"], YAML, _files({"c.yaml": text}))
    assert model.get("/top") == (False, None)


def test_a_document_that_fails_on_the_master_keeps_what_was_set_before_it():
    model = ParamModel()
    with pytest.raises(RosparamModelError, match="global /"):
        model.run(["rosparam", "load", "c.yaml"], YAML, _files({"c.yaml": "a: 1\n---\n[1]\n---\nb: 2\n"}))
    assert model.get("/a") == (True, 1) and model.get("/b") == (False, None)


def test_work_out_lists_each_dumps_file_namespace_and_keys():
    tree, dumps, notes = work_out([["rosparam", "load", "c.yaml"], ["rosparam", "dump", "all.yaml", "/g"],
                                   ["rosparam", "dump", "one.yaml", "/g/p"]], YAML, _files({"c.yaml": "g: {p: 1, i: 2}"}))
    assert notes == [] and value_at(tree, "/g/p") == (True, 1)
    assert dumps == [{"file": "all.yaml", "namespace": "/g", "keys": ["i", "p"]},
                     {"file": "one.yaml", "namespace": "/g/p", "keys": []}]


def test_an_unreadable_file_is_refused_with_the_error_on_one_line_cut_at_200_characters():
    def read(name: str) -> bytes:
        raise OSError("bad\n   thing " + "x" * 300)

    with pytest.raises(RosparamModelError) as caught:
        file_reader(read)("c.yaml")
    detail = ("bad thing " + "x" * 300)[:200]
    assert str(caught.value) == f"file [c.yaml] cannot be read ({detail})"


def test_a_file_that_is_not_utf8_cannot_be_read():
    with pytest.raises(RosparamModelError, match="cannot be read"):
        file_reader(lambda name: b"\xff")("c.yaml")


def test_yaml_reader_hands_the_text_over_and_refuses_its_errors_on_one_line_cut_at_200_characters():
    assert yaml_reader(lambda text: [text], (ValueError,))("a: 1") == ["a: 1"]

    def broken(text: str) -> List[Any]:
        raise ValueError("bad\n   yaml " + "y" * 300)

    with pytest.raises(RosparamModelError) as caught:
        yaml_reader(broken, (ValueError,))("a: 1")
    assert str(caught.value) == f"not YAML rosparam reads ({('bad yaml ' + 'y' * 300)[:200]})"
