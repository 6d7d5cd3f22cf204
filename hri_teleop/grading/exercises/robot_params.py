"""Ex. 4's check: robot_params.yaml loaded with rosparam's own loader, against Table 1's keys, YAML types and values.

Why here: the answer key, the lab's copy (``hri_lab/config/robot_params.yaml``) and every
student's file are judged against this one table. YAML decides a value's type by how it
is written -- ``18`` is an integer, ``18.0`` a float, ``"true"`` a string -- and that
is the point of the exercise, so types are compared exactly (an int is not a float here,
unlike in the nodes' parameter checks).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

from hri_teleop.grading.cases.handout import TABLE_1
from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.judge.compare_common import explain_process
from hri_teleop.grading.judge.harness import closing_scratch, finish_check, reusable, start_check
from hri_teleop.grading.results import CheckResult, Part
from hri_teleop.grading.run.records import RosparamResult

__all__ = ["EXERCISE", "TABLE_1", "POINTS", "LOAD_PART", "part_table", "yaml_type", "written", "compare_robot_params",
           "grade_robot_params"]

PathLike = Union[str, Path]

POINTS: Dict[str, float] = {"robot_name": 1, "robot_number": 1, "robot_mass": 2, "load_gripper": 2,
                            "mixed_list": 2, "gains": 1}
LOAD_PART = "loads with rosparam load"
_LOAD_POINTS = 1.0


def yaml_type(value: Any) -> str:
    """The name Table 1 uses for the type YAML gave ``value``."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "float"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "list"
    if isinstance(value, dict):
        return "dictionary"
    return type(value).__name__


def written(value: Any) -> str:
    """How to write ``value`` in YAML (flow style, as Table 1 does)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return value if value.isidentifier() else repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(repr(v) if isinstance(v, str) else written(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {written(v)}" for k, v in value.items()) + "}"
    return repr(value)


def part_table() -> Dict[str, Tuple[str, float]]:
    """key -> (part name, points), in the order of the parts ('load' first, then Table 1)."""
    table = {"load": (LOAD_PART, _LOAD_POINTS)}
    table.update({key: (f"{key}: {written(want)} ({yaml_type(want)})", POINTS[key]) for key, want in TABLE_1.items()})
    return table


def _same(a: Any, b: Any) -> bool:
    """Equal in value *and* YAML type, recursively (1 != 1.0 != True here)."""
    if yaml_type(a) != yaml_type(b):
        return False
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return set(a) == set(b) and all(_same(a[k], b[k]) for k in a)
    return bool(a == b)


def _difference(key: str, found: Any, want: Any) -> str:
    """One sentence on what is wrong with ``found`` and how to write ``want``."""
    fix = f"write `{key}: {written(want)}`"
    if yaml_type(found) != yaml_type(want):
        if isinstance(found, str) and isinstance(want, bool) and found.lower() in ("true", "false"):
            return f"{key} is the string {found!r} (quoted), Table 1 wants a boolean; {fix} without quotes"
        if isinstance(found, int) and not isinstance(found, bool) and isinstance(want, float) and found == want:
            return (f"{key} is {found!r}, which YAML reads as an integer; Table 1 wants a float: "
                    f"write `{key}: {written(want)}` (the decimal point makes it a float)")
        if isinstance(found, str) and not isinstance(want, str):
            return f"{key} is the string {found!r}, Table 1 wants a {yaml_type(want)}; {fix} (no quotes)"
        return f"{key} is {written(found)} (a {yaml_type(found)}), Table 1 wants a {yaml_type(want)}; {fix}"
    if isinstance(want, list):
        if len(found) != len(want):
            return f"{key} has {len(found)} elements, Table 1 has {len(want)}: {fix}"
        for index, (f, w) in enumerate(zip(found, want)):
            if not _same(f, w):
                return (f"{key}[{index}] is {written(f)} (a {yaml_type(f)}), Table 1 wants {written(w)} "
                        f"(a {yaml_type(w)}); {fix}")
    if isinstance(want, dict):
        missing = [k for k in want if k not in found]
        if missing:
            return f"{key} lacks {', '.join(missing)}; {fix}"
        for k in want:
            if not _same(found[k], want[k]):
                return (f"{key}/{k} is {written(found[k])} (a {yaml_type(found[k])}), Table 1 wants "
                        f"{written(want[k])} (a {yaml_type(want[k])}); {fix}")
        extra = [k for k in found if k not in want]
        return f"{key} has keys {', '.join(map(str, extra))} that Table 1 does not; {fix}"
    return f"{key} is {written(found)}, Table 1 wants {written(want)}; {fix}"


def _find_nested(params: Mapping[str, Any], key: str) -> Optional[str]:
    for outer, value in params.items():
        if isinstance(value, dict) and key in value:
            return str(outer)
    return None


def compare_robot_params(params: Optional[Mapping[str, Any]], load_error: str = "") -> List[Part]:
    """Parts for a loaded robot_params.yaml: that it loads, then each key of Table 1.

    ``params`` is what ``rosparam load`` put into the global namespace (None if loading
    failed, with ``load_error`` saying why). Extra keys are fine (Ex. 4 e adds some).
    """
    parts: List[Part] = []
    table = part_table()
    if params is None:
        parts.append(Part(LOAD_PART, _LOAD_POINTS, False, load_error or "the file could not be loaded"))
        for key in TABLE_1:
            parts.append(Part(table[key][0], POINTS[key], False, "not judged: the file does not load (see above)"))
        return parts
    if not params:  # comments only (the untouched template): it loads, but nothing was written
        parts.append(Part(LOAD_PART, _LOAD_POINTS, False, "it loads but sets no parameter: write Table 1's "
                          "parameters, one `key: value` line each (handout Ex. 4)"))
    else:
        parts.append(Part(LOAD_PART, _LOAD_POINTS, True))
    for key, want in TABLE_1.items():
        name = table[key][0]
        if key not in params:
            outer = _find_nested(params, key)
            where = (f"; it is nested under {outer!r} (/{outer}/{key}): move it to the top level"
                     if outer else f"; add the line `{key}: {written(want)}`")
            close = [k for k in params if k.lower().replace("-", "_") == key or key in str(k)]
            hint = f" (found {close[0]!r}: check the spelling)" if close and not outer else ""
            parts.append(Part(name, POINTS[key], False, f"{key} is missing{hint}{where}"))
        elif _same(params[key], want):
            parts.append(Part(name, POINTS[key], True))
        else:
            parts.append(Part(name, POINTS[key], False, _difference(key, params[key], want)))
    return parts


@reusable("robot-params")
@closing_scratch
def grade_robot_params(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 4: Table 1's keys, YAML types and values; loaded with rosparam's own loader."""
    run, seed = start_check(EXERCISE, path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    target = run.space.file("robot_params")
    data, facts = run.probe("rosparam-load", target, "rosparam-load", RosparamResult)
    if data is None:
        parts = compare_robot_params(None, explain_process(facts, "loading robot_params.yaml"))
    elif not data.ok:
        parts = compare_robot_params(None, f"`rosparam load` fails: {data.error}")
    else:
        parts = compare_robot_params(data.params)
    return finish_check(EXERCISE, run, parts)


EXERCISE = Exercise(key="robot_params", handout="Ex. 4", assignment="preparation", parts=part_table(),
                    grade=grade_robot_params, notebook_calls={"robot_params": grade_robot_params},
                    whole_check_calls=("robot_params",))
