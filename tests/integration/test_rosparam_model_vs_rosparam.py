"""The grader's model of rosparam does what rosparam does: the same commands, run by the real rosparam on a real
master (a private one on a free port) and worked out by hri_teleop.core.rosparam_model, leave the same server
and write the same dumps. Handout Ex. 3 and 4 are graded on the model."""

from __future__ import annotations

import subprocess
import xmlrpc.client
from pathlib import Path
from typing import Any, Dict, List

import pytest
import yaml

from hri_teleop.core.rosparam_model import (
    ROSCORE_PARAMS,
    ParamModel,
    file_reader,
    shell_commands,
    shell_lines,
    yaml_reader,
)
from hri_teleop.core.yamlfile import BoundedYamlError, load_bounded_all
from hri_teleop.ros.master import PrivateMaster

pytestmark = pytest.mark.ros

ROBOT_PARAMS = ("robot_name: FER\nrobot_number: 1\nrobot_mass: 18.0\nload_gripper: true\n"
                "mixed_list: ['text', 1.0, 1]\ngains: {p: 10.0, i: 1.0, d: 5.0}\n")
SCENARIOS: Dict[str, List[str]] = {
    "ex3 as the answer key": ["!rosparam set /ex3/integer 5", "!rosparam set /ex3/integer 7",
                              "!rosparam set /ex3/text \"hello robot\"", "!rosparam set /ex3/items \"[1, 'two', 3.0]\""],
    "types yaml gives": ["!rosparam set /t/quoted \"'7'\"", "!rosparam set /t/neg -3", "!rosparam set /t/f -0.5",
                         "!rosparam set /t/yes true", "!rosparam set /t/empty ''", "!rosparam set /t/word yes"],
    "dictionaries update": ["!rosparam set /g \"{p: 1, i: 2}\"", "!rosparam set /g \"{p: 10}\"",
                            "!rosparam set /h/p 1", "!rosparam set /h 5"],
    "what fails": ["!rosparam set /bad/list [1, 'two']", "!rosparam set /bad/null '~'",
                   "!rosparam set /bad/big 2147483648", "!rosparam set /ok/big 2147483647",
                   "!rosparam set /ok/small -2147483648", "!rosparam delete /not/there", "!rosparam set /bad/only"],
    "load, delete and dump": ["!rosparam load robot_params.yaml", "!rosparam load robot_params.yaml /copy",
                              "!rosparam load docs.yaml /top", "!rosparam delete /copy/gains",
                              "!rosparam set /operator student; rosparam dump new_robot_params.yaml",
                              "!rosparam dump copy.yaml /copy", "!rosparam load missing.yaml"],
    "options and names": ["!rosparam set -p /o/p 1", "!rosparam set -v /o/v 1", "!rosparam set -t -x /o/t",
                          "!rosparam set --textfile=notes.txt /o/tf", "!rosparam set -b notes.txt /o/bin",
                          "!rosparam load -v docs.yaml /o/docs", "!rosparam load abs.yaml /o/abs",
                          "!rosparam set /o/g \"{/o_abs: 1, b: 2}\"", "!rosparam set / 5", "!rosparam delete -3",
                          "!rosparam set /o/when '2020-01-01 10:00:00'", "!rosparam set /o/day 2020-01-01",
                          "!rosparam set /o/d/e/f 1", "!rosparam delete -v /o/d/e/f", "!rosparam set -h /o/h 1"],
    "documents rosparam cannot load": ["!rosparam load trailing.yaml /trailing", "!rosparam load mixed.yaml",
                                       "!rosparam load list.yaml /list", "!rosparam load number.yaml /number"],
}
FILES = {"robot_params.yaml": ROBOT_PARAMS, "docs.yaml": "_ns: a\nx: 1\n---\ny: [2, 3]\n", "notes.txt": "7\n",
         "abs.yaml": "_ns: /o_ns\nx: 1\n", "trailing.yaml": "a: 1\n---\n", "mixed.yaml": "m: 1\n---\n[1]\n---\nn: 2\n",
         "list.yaml": "[1, 2]\n", "number.yaml": "m: 1\n---\n5\n"}
ROSCORE = set(ROSCORE_PARAMS)


def _without_roscore(tree: Any) -> Any:
    return {k: v for k, v in tree.items() if k not in ROSCORE} if isinstance(tree, dict) else tree


@pytest.fixture(scope="module")
def master():
    with PrivateMaster() as running:
        yield running


@pytest.mark.parametrize("scenario", sorted(SCENARIOS))
def test_the_model_leaves_the_server_and_the_dumps_rosparam_leaves(master, scenario, tmp_path):
    for name, text in FILES.items():
        (tmp_path / name).write_text(text)
    subprocess.run(["rosparam", "delete", "/"], env=master.env, check=True, capture_output=True, timeout=60)
    dumps = []
    for line in shell_lines("\n".join(SCENARIOS[scenario])):
        subprocess.run(["bash", "-c", line], env=master.env, cwd=tmp_path, capture_output=True, timeout=60)
        for argv in shell_commands(["!" + line]):
            if argv[1] == "dump":
                dumps.append(argv[2])
    # builtin types: a --binfile's value as bytes, a date and time as datetime, as the model holds them
    code, _msg, real = xmlrpc.client.ServerProxy(master.uri, use_builtin_types=True).getParam("/test", "/")
    assert code == 1

    model = ParamModel()
    notes = model.run_all(shell_commands(SCENARIOS[scenario]),
                          yaml_reader(load_bounded_all, (yaml.YAMLError, BoundedYamlError)),
                          file_reader(lambda name: (tmp_path / name).read_bytes()))
    assert _without_roscore(model.tree) == _without_roscore(real), notes
    assert [d.file for d in model.dumps] == dumps
    for dump in model.dumps:
        written = yaml.safe_load((tmp_path / dump.file).read_text())
        assert _without_roscore(dump.tree) == _without_roscore(written)


def test_the_failures_of_the_scenarios_are_noted():
    model = ParamModel()
    notes = model.run_all(shell_commands(SCENARIOS["what fails"]),
                          yaml_reader(load_bounded_all, (yaml.YAMLError, BoundedYamlError)),
                          file_reader(lambda name: Path(name).read_bytes()))
    assert len(notes) == 5, notes
