"""`make mutants` from a clone: the copy holds what the tests read (tracked files, never what a run left), every
gate of issue 44 is in its scope, equivalent mutants come from a checked-in list with a reason each, and a real
survivor makes the run fail."""

from __future__ import annotations

import fnmatch
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

#: The gates whose mistakes would hurt someone (issue 44), each with a test file written for it.
GATES = {
    "hri_teleop/core/modes.py": "tests/unit/test_lab_safety_gate.py",
    "hri_teleop/course/master_mode.py": "tests/unit/test_lab_safety_gate.py",
    "hri_teleop/course/nodes.py": "tests/unit/test_lab_safety_gate.py",
    "hri_teleop/ros/master.py": "tests/unit/test_master_started_here.py",
    "hri_teleop/grading/run/clock_sleep.py": "tests/grading/test_clock_sleep_rules.py",
    "hri_teleop/ros/commands.py": "tests/unit/test_command_queue_burst.py",
    "hri_teleop/grading/points.py": "tests/grading/test_points_rules.py",
    "hri_teleop/grading/batch/late.py": "tests/grading/test_late_policy.py",
    "hri_teleop/grading/run/view.py": "tests/grading/test_student_view.py",
    "hri_teleop/grading/run/sandbox.py": "tests/grading/test_student_view.py",
    "hri_teleop/sim/arm.py": "tests/unit/test_sim_arm_late_burst.py",
    "tests/leftovers.py": "tests/unit/test_leftovers_rules.py",
}


@pytest.fixture(scope="module")
def mutants():
    if sys.version_info < (3, 9):
        pytest.skip("make mutants runs mutmut 3, which needs Python 3.10 or later")
    spec = importlib.util.spec_from_file_location("_tools_mutants_runs", REPO / "tools" / "mutants.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("module, test", sorted(GATES.items()))
def test_every_gate_is_mutated_and_judged_by_the_tests_written_for_it(mutants, module, test):
    mutmut, table = mutants.load_config(REPO / "pyproject.toml")
    assert any(fnmatch.fnmatch(module, p) for p in mutmut["only_mutate"]), f"{module} left the mutation scope"
    assert test in table[module]


@pytest.mark.parametrize("module, function", [("hri_teleop/ros/master.py", "started_here"),
                                              ("hri_teleop/course/nodes.py", "node_start"),
                                              ("hri_teleop/course/nodes.py", "launch_starts"),
                                              ("hri_teleop/sim/arm.py", "SimArm.command"),
                                              ("hri_teleop/grading/run/sandbox.py", "student_environment")])
def test_a_gate_among_plumbing_is_narrowed_to_its_rule_and_the_rule_is_kept(mutants, module, function):
    assert function in mutants.load_functions(REPO / "pyproject.toml")[module]


def test_a_narrowed_module_is_run_by_its_functions_names_and_the_others_whole(mutants):
    functions = {"hri_teleop/sim/arm.py": ["SimArm.command", "step_arm"], "tests/leftovers.py": []}
    assert mutants.mutant_patterns(["hri_teleop/sim/arm.py", "leftovers.py", "hri_teleop/core/__init__.py"],
                                   functions) == [
        "hri_teleop.sim.arm.x\u01c1SimArm\u01c1command__mutmut_*", "hri_teleop.sim.arm.x_step_arm__mutmut_*",
        "leftovers.*", "hri_teleop.core.*"]
    assert mutants.in_functions("hri_teleop.sim.arm.x\u01c1SimArm\u01c1command__mutmut_7", ["SimArm.command"])
    assert not mutants.in_functions("hri_teleop.sim.arm.x\u01c1SimArm\u01c1step__mutmut_7", ["SimArm.command"])
    assert mutants.in_functions("hri_teleop.ros.master.x_started_here__mutmut_2", ["started_here"])
    assert not mutants.in_functions("hri_teleop.ros.master.x_started_here_too__mutmut_2", ["started_here"])
    assert mutants.in_functions("anything__mutmut_1", [])


def _git(cwd: Path, *args: str) -> None:
    subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=cwd, check=True,
                   capture_output=True)


def test_the_copy_holds_the_tracked_files_and_not_what_a_run_left(mutants, tmp_path):
    """solutions/ and benchmarks/ (tests import them) come along; a catkin_ws/build or a plot left behind do not."""
    root = tmp_path / "checkout"
    for name in ("hri_teleop/core/x.py", "solutions/hri_lab/scripts/a.py", "benchmarks/nodes.py", "tests/leftovers.py",
                 "tests/unit/test_x.py", "tools/mutants_scope.py"):
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(f"# {name}\n")
    _git(root, "init", "-q")
    _git(root, "add", ".")
    _git(root, "commit", "-q", "-m", "files")
    (root / "notebooks/source/lab/catkin_ws/build").mkdir(parents=True)
    (root / "notebooks/source/lab/catkin_ws/build/CMakeCache.txt").write_text("other folder's cache\n")
    (root / "out").mkdir()
    (root / "out/plot.png").write_text("png\n")
    (root / "hri_teleop/core/x.py").write_text("# edited, not yet committed\n")
    work = tmp_path / "work"
    top = mutants.prepare(work, "[tool.mutmut]\n", {"tests/leftovers.py": "leftovers.py"}, root=root)
    copied = sorted(str(p.relative_to(work)) for p in work.rglob("*") if p.is_file())
    assert copied == ["benchmarks/nodes.py", "hri_teleop/core/x.py", "leftovers.py", "pyproject.toml",
                      "solutions/hri_lab/scripts/a.py", "tests/unit/test_x.py", "tools/mutants_scope.py"]
    assert (work / "hri_teleop/core/x.py").read_text() == "# edited, not yet committed\n"
    assert top == ["benchmarks", "hri_teleop", "leftovers.py", "solutions", "tests", "tools"]


def test_the_copys_configuration_asks_mutmut_to_copy_all_of_it_and_moves_leftovers(mutants):
    mutmut = {"source_paths": ["hri_teleop", "tests/leftovers.py"], "only_mutate": ["hri_teleop/core/*",
              "tests/leftovers.py"], "pytest_add_cli_args_test_selection": ["tests/unit/test_a.py"]}
    table = {"hri_teleop/core/a.py": ["tests/unit/test_a.py"], "tests/leftovers.py": ["tests/unit/test_b.py"]}
    text = mutants.work_pyproject(mutmut, table, {"testpaths": ["tests"]}, ["tests/leftovers.py"],
                                  ["benchmarks", "hri_teleop", "leftovers.py", "pyproject.toml", "solutions", "tests"])
    config = mutants.tomllib.loads(text)
    assert config["tool"]["mutmut"]["source_paths"] == ["hri_teleop", "leftovers.py"]
    assert config["tool"]["mutmut"]["only_mutate"] == ["leftovers.py"]
    assert config["tool"]["mutmut"]["pytest_add_cli_args_test_selection"] == ["tests/unit/test_b.py"]
    assert config["tool"]["mutmut"]["also_copy"] == ["benchmarks", "solutions", "tests"]
    assert config["tool"]["hri-teleop"]["mutants"]["leftovers.py"] == ["tests/unit/test_b.py"]


def test_every_listed_equivalent_names_a_mutant_its_change_and_why(mutants):
    equivalents = mutants.load_equivalents()
    for name, (change, why) in equivalents.items():
        assert "__mutmut_" in name and "  ->  " in change and len(why.split()) >= 4, name


def test_an_equivalent_without_a_reason_is_refused(mutants, tmp_path):
    listed = tmp_path / "equivalent.toml"
    listed.write_text('[[equivalent]]\nmutant = "m.x_f__mutmut_1"\nchange = "a  ->  b"\n')
    with pytest.raises(mutants.MutantsError, match="why"):
        mutants.load_equivalents(listed)


def _run_folder(tmp_path: Path, codes: dict) -> Path:
    """A finished mutmut run of one module, ``codes``: mutant -> exit code, with the mutants' diffs."""
    work = tmp_path / "work"
    (work / "mutants" / "pkg").mkdir(parents=True)
    (work / "pkg").mkdir()
    (work / "pkg" / "m.py").write_text("def f(x):\n    return x > 1\n")
    (work / "mutants" / "pkg" / "m.py.meta").write_text(json.dumps({"exit_code_by_key": codes}))
    return work


@pytest.mark.parametrize("listed, code", [({}, 1), ({"pkg.m.x_f__mutmut_1": ("return x > 1  ->  return x >= 1",
                                                                              "x is never 1 here")}, 0),
                                          ({"pkg.m.x_f__mutmut_1": ("return x > 1  ->  return x > 2", "stale")}, 1)])
def test_the_run_fails_while_a_survivor_is_not_listed_as_equivalent_with_its_change(mutants, tmp_path, monkeypatch,
                                                                                     listed, code, capsys):
    work = _run_folder(tmp_path, {"pkg.m.x_f__mutmut_1": 0, "pkg.m.x_f__mutmut_2": 1})
    diff = "--- m.py\n+++ m.py\n@@ -1,2 +1,2 @@\n def f(x):\n-    return x > 1\n+    return x >= 1\n"
    monkeypatch.setattr(mutants, "mutant_diff", lambda work, name, module: diff)
    assert mutants.report(work, tmp_path / "out", ["pkg/m.py"], listed, 1.5) == code
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["minutes"] == 1.5
    expected = {"killed": 1, "equivalent": 1} if code == 0 else {"killed": 1, "survived": 1}
    assert summary["modules"]["pkg/m.py"] == expected
    assert "1 killed" in capsys.readouterr().out


@pytest.mark.parametrize("change, text", [
    ("""return f"{'127.0.0.1' if host in ('localhost', '') else host}:{port}"  ->  """
     """return f"{'XX127.0.0.1XX' if host in ('localhost', '') else host}:{port}\"""", False),
    ('raise f"no master at {uri}: start one"  ->  raise f"XXno master at {uri}: start oneXX"', True),
])
def test_a_change_inside_an_f_strings_braces_is_code_not_words(mutants, change, text):
    assert mutants.is_text_change(change) is text


def test_a_survivor_on_a_line_written_twice_in_its_function_is_placed_on_the_right_one(mutants):
    source = ("def f(a):\n    try:\n        g()\n    except KeyError:\n        ok = True\n        return 1\n"
              "    except OSError:\n        ok = True\n        return 2\n")
    diff = ("--- m.py\n+++ m.py\n@@ -6,4 +6,4 @@\n     except OSError:\n-        ok = True\n+        ok = False\n"
            "         return 2\n")
    assert mutants.describe(diff, source, "m.x_f__mutmut_9") == (8, "ok = True  ->  ok = False")
