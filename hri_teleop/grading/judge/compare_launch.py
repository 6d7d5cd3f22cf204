"""What the launch files' judges share: the parse part, a script's node found (or nearly), /max_sensor_force.

Each launch file's own parts are judged in its exercise (``exercises/sensor_launch``,
``exercises/teleoperation_launch``).
"""

from __future__ import annotations

from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.mapping import ADC_MAX_COUNT
from hri_teleop.grading.judge.compare_common import (
    explain_process,
    judged_part,
    not_judged_part,
)
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import (
    LaunchNode,
    LaunchObservation,
    LaunchParseResult,
    ProcessFacts,
)

# -- launch files ---------------------------------------------------------------------------


def parse_parts(table: Dict[str, Tuple[str, float]], parsed: LaunchParseResult, parse_facts: Optional[ProcessFacts],
                 later: Sequence[str], exercise: str, franka_hint: str = "") -> Tuple[List[Part], bool]:
    """A launch file's "parse" part; when roslaunch cannot load it, also the ``later`` parts it leaves
    unjudged, and True: nothing more to judge."""
    if not parsed.ok:
        reason = parsed.error or explain_process(parse_facts or ProcessFacts(), "parsing")
        if franka_hint and "franka_control" in reason:
            reason += franka_hint
        return ([judged_part(table, "parse", False, f"roslaunch cannot load it: {reason}")]
                + [not_judged_part(table, k, "the file does not parse") for k in later]), True
    if is_empty(parsed):
        return ([judged_part(table, "parse", False, "it parses but starts no node and sets no parameter: write the "
                             f"launch file (handout {exercise})")]
                + [not_judged_part(table, k, EMPTY_CAUSE) for k in later]), True
    return [judged_part(table, "parse", True)], False


#: Why the parts after "parse" are not judged for a launch file that starts and sets nothing.
EMPTY_CAUSE = "the file starts no node and sets no parameter (the parse part)"


def is_empty(parsed: LaunchParseResult) -> bool:
    """A launch file that parses but starts no node and sets no parameter (the template as it is)."""
    return parsed.ok and not parsed.nodes and not parsed.params


#: Characters of one entry of the student's quoted back.
SHOWN_CHARS = 60


def written(value: Any) -> str:
    """An entry of the student's as they wrote it (cut short), to quote back."""
    text = str(value).strip()
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS - 3] + "..."


def _stem(script_type: str) -> str:
    """A node's type= as a file stem to compare loosely: no folder, no extension, lower case."""
    base = script_type.strip().replace("\\", "/").rsplit("/", 1)[-1]
    return (base[:-3] if base.lower().endswith(".py") else base).lower()


def near_miss(parsed: LaunchParseResult, script: str) -> str:
    """Why a <node> that is meant to run ``script`` does not (type= without .py, another case, a folder, or
    the node's name right and its type= another file); '' when no node comes close."""
    want = _stem(script)
    for node in parsed.nodes:
        kind = node.type
        if kind == script:
            continue
        if _stem(kind) == want:
            if "/" in kind or "\\" in kind:
                fix = "the file's name alone, without its folder"
            elif not kind.lower().endswith(".py"):
                fix = "the executable file as it is in scripts/, extension included"
            else:
                fix = "the executable file exactly as it is in scripts/, upper and lower case included"
            return (f'{script}: the <node name="{written(node.name)}"> is there, but its type="{written(kind)}" is not a '
                    f"file roslaunch finds: type= must name {fix}")
        if node.name.lower() == want and _stem(kind) != want:
            return (f'{script}: the <node name="{written(node.name)}"> is there, but its type="{written(kind)}" names '
                    "another file: type= names the script the node runs, as it is in scripts/")
    return ""


def script_problem(parsed: LaunchParseResult, script: str, packages: Sequence[str], where: str, exercise: str) -> str:
    """Why no <node> runs ``script`` of one of ``packages`` ('' if one does)."""
    found = nodes_by_script(parsed).get(script, [])
    if any(n.package in packages for n in found):
        return ""
    if found:
        return f"{script} is started from package {found[0].package!r}; {where} it is in {packages[0]}"
    return near_miss(parsed, script) or (f"no node runs {script} of {packages[0]}: start it with a <node> element "
                                         f"(handout {exercise})")


def nodes_by_script(parsed: LaunchParseResult) -> Dict[str, List[LaunchNode]]:
    out: Dict[str, List[LaunchNode]] = {}
    for node in parsed.nodes:
        out.setdefault(node.type, []).append(node)
    return out


def check_max_param(params: Mapping[str, object]) -> Tuple[bool, str]:
    value = params.get("/max_sensor_force")
    if "/max_sensor_force" not in params:
        private = [k for k in params if k.endswith("/max_sensor_force")]
        if private:
            return False, (f"max_sensor_force is set as {private[0]} (inside a node: private); mapping_node reads the "
                           "global /max_sensor_force: put its <param> outside the <node> elements")
        return False, ("the launch file does not set /max_sensor_force: set it with a <param> element outside "
                       "the <node> elements (handout Ex. 6)")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        count = written(value) if isinstance(value, str) and value.strip().isdigit() else "<the count>"
        return False, (f"/max_sensor_force is {value!r} ({type(value).__name__}); it must be a number of counts: "
                       f"write value=\"{count}\" without type=\"str\"")
    if not 0 < value <= ADC_MAX_COUNT:
        return False, f"/max_sensor_force is {value!r}; it must be a count 0 < value <= {ADC_MAX_COUNT} (about 700)"
    return True, ""


def supplied_note(observation: LaunchObservation, what: str) -> str:
    """What the grader started or set in place of the launch file, to judge ``what`` ('' if nothing)."""
    if not observation.supplied:
        return ""
    return f"to judge {what} the grader supplied what the launch file lacks: " + ", ".join(observation.supplied)


