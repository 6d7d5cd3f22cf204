"""Judging ``mapping_node.py`` (Ex. 5) from a mapping-node session: each mistake costs in its own part.

The parts depend on each other as docs/instructors.md says ("How the parts of a node check depend
on each other"): a crash fails the part that saw it and leaves the parts that need the node's
output not judged; a subscriber of another type is judged in its part and the counts are sent in
its type to judge the rest; the hidden inputs judge only what the public trace found right.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from hri_teleop.core.mapping import ADC_MAX_COUNT
from hri_teleop.grading.exercises.mapping_node.cases import MappingCase, public_mapping_case
from hri_teleop.grading.exercises.mapping_node.session import MappingNodeObservation, MappingRun
from hri_teleop.grading.judge.compare_common import (
    TOLERANCE,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
    with_box_hints,
)
from hri_teleop.grading.judge.plots import expected_vs_actual
from hri_teleop.grading.judge.tracebacks import NOT_JUDGED_CRASH, Crash, crash_text, find_crash
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import NodeFacts, Response

__all__ = ["PARTS", "compare_mapping", "mapping_plot", "TEMPLATE_MESSAGE", "SENSOR_TYPE"]

#: Part key -> (name as students read it, points; tests refer to the keys).
PARTS: Dict[str, Tuple[str, float]] = {
    "sub": ("subscribes /pub_force with the type the sensor publishes", 3),
    "pub": ("publishes /force_mapped, one message per count", 3),
    "type": ("/force_mapped is std_msgs/Float32", 2),
    "values": ("maps 0../max_sensor_force to 0..1 (public trace, /max_sensor_force = 700)", 4),
    "clip": ("clips counts above /max_sensor_force to 1.0 (public trace)", 3),
    "hidden": ("takes the range from /max_sensor_force (hidden inputs, other values)", 5),
}

#: What the sensor publishes on /pub_force (the grader's, never shown to a student as the answer).
SENSOR_TYPE = "std_msgs/Int16"
NODE = "mapping_node.py"
#: The student's file is the template as handed out (Ex. 5 not written, or Ex. 12 d) not done).
TEMPLATE_MESSAGE = ("scripts/mapping_node.py is the template as handed out: every part marked YOUR CODE HERE "
                    "still raises NotImplementedError. Write the node (Ex. 5); in the lab package, put in the "
                    "mapping_node.py you wrote in the preparation (Ex. 12 d)")
_FIND_TYPE = ("`rostopic type /pub_force` (or `rostopic info /pub_force`) with FSR_sensor.py running shows the "
              "type the sensor publishes")


def _integer_type(kind: str) -> bool:
    return bool(re.match(r"std_msgs/U?Int\d+$", kind or ""))


def _diagnose_mapping(bad: List[Tuple[int, float, float, Any]], out_type: str) -> str:
    """The most likely mistake behind wrong (count, max, expected, got) values."""
    gots = [(c, m, e, as_float(g)) for c, m, e, g in bad]
    numeric = [(c, m, e, g) for c, m, e, g in gots if g is not None]
    if _integer_type(out_type):
        return f"{out_type} holds whole numbers only, so 0.5 arrives as 0: publish std_msgs/Float32"
    if not numeric:
        return "the messages carry no number: publish Float32(value) with the mapped float"
    if any(c > m and g > 1.0 + TOLERANCE for c, m, e, g in numeric):
        return "values above 1.0 for counts above /max_sensor_force: clip the result to at most 1.0, e.g. min(1.0, value)"
    if all(g in (0.0, 1.0) for _, _, _, g in numeric):
        return ("the values are only 0 and 1: integer division? Divide as floats, count / float(max_sensor_force), "
                "not with // or int()")
    for guess, words in ((float(700), "0..700: read the range from the parameter /max_sensor_force "
                                      "(rospy.get_param) instead of writing 700"),
                         (float(ADC_MAX_COUNT), "0..1023 (the ADC's range): divide by /max_sensor_force")):
        if all(abs(g - min(1.0, max(0.0, c / guess))) <= TOLERANCE or abs(g - c / guess) <= TOLERANCE
               for c, m, e, g in numeric) and any(m != guess for c, m, e, g in numeric):
            return "the values fit a range of " + words
    public = public_mapping_case().expected
    if sum(1 for (c, m, e, g) in numeric if any(abs(g - p) <= TOLERANCE for p in public)) == len(numeric) and \
            any(m != 700 for _, m, _, _ in numeric):
        return ("the values are those of the public trace, not of the counts sent: compute each value from the "
                "count that arrives (count / max_sensor_force, clipped)")
    if all(abs(g - (1.0 - e)) <= TOLERANCE for c, m, e, g in numeric):
        return "the values run the wrong way (1 - expected): 0 counts must give 0.0"
    return "compute count / max_sensor_force and clip it to 0..1"


Item = Tuple[int, int, float, List[Response]]


def _judge_mapping(items: List[Item], out_type: str, crash: Optional[Crash] = None) -> Tuple[bool, str, List[int]]:
    """items: (count, max, expected, responses) -> (ok, message, indices of wrong items)."""
    missing = [i for i, (_, _, _, r) in enumerate(items) if not r]
    extra = [i for i, (_, _, _, r) in enumerate(items) if len(r) > 1]
    wrong = []
    for i, (_, _, expected, responses) in enumerate(items):
        if responses:
            got = as_float(responses[0][1])
            if got is None or abs(got - expected) > TOLERANCE:
                wrong.append(i)
    if not (missing or extra or wrong):
        return True, "", []
    lines: List[str] = []
    if wrong:
        lines.append(f"{len(wrong)} of {len(items)} counts gave a wrong value, e.g.:")
        for i in wrong[:3]:
            count, maximum, expected, responses = items[i]
            lines.append(f"  /pub_force = {count} with /max_sensor_force = {maximum}: expected /force_mapped = "
                         f"{expected:.6g}, got {fmt_value(responses[0][1])}")
        lines.append("hint: " + _diagnose_mapping([(items[i][0], items[i][1], items[i][2], items[i][3][0][1])
                                                   for i in wrong], out_type))
    if missing:
        count, maximum, _, _ = items[missing[0]]
        lines.append(f"{len(missing)} of {len(items)} counts got no message back (e.g. /pub_force = {count} with "
                     f"/max_sensor_force = {maximum})" + (
                         ": for those the node crashed:\n" + crash_text(crash, NODE) if crash is not None
                         else ": publish one message for every count, from the callback"))
    if extra:
        count = items[extra[0]][0]
        lines.append(f"{len(extra)} counts got more than one message (e.g. /pub_force = {count}): publish exactly "
                     "once per count")
    return False, "\n".join(lines), sorted(set(wrong + missing + extra))


def _items(run: MappingRun, case: MappingCase, which: Callable[[int, int], bool]) -> Tuple[List[Item], List[int]]:
    """The (count, max, expected, responses) of ``case`` that ``which(count, max)`` selects, and their indices."""
    chosen: List[Item] = []
    index: List[int] = []
    for i, (count, expected) in enumerate(zip(case.counts, case.expected)):
        if which(count, case.max_sensor_force):
            chosen.append((count, case.max_sensor_force, expected, run.responses[i] if i < len(run.responses) else []))
            index.append(i)
    return chosen, index


def _crash(facts: NodeFacts, package_dir: str) -> Optional[Crash]:
    """The node's crash: a traceback in its output (a callback's, or one that ended it)."""
    return find_crash(facts.output_tail, package_dir)


#: The reason on the parts that need the output of a node handed in as the template.
NOT_JUDGED_TEMPLATE = "the node is the template as handed out (see above)"


def _not_judged_reason(template: bool) -> str:
    return NOT_JUDGED_TEMPLATE if template else NOT_JUDGED_CRASH


def _failed_node(facts: NodeFacts, crash: Optional[Crash], template: bool) -> str:
    """Why the node did not do its work: the template, its crash, else its exit and output."""
    if template:
        return TEMPLATE_MESSAGE
    if crash is not None:
        return with_box_hints(crash_text(crash, NODE), facts, NODE)
    return explain_process(facts, NODE)


def _sub_part(run: MappingRun) -> Part:
    facts = run.node
    if run.input_topic == "/pub_force" and run.input_type == SENSOR_TYPE:
        return judged_part(PARTS, "sub", True)
    if run.input_topic != "/pub_force":
        others = ", ".join(t for t, _ in facts.subscriptions)
        return judged_part(PARTS, "sub", False, f"the node subscribes {others}, not /pub_force: the sensor publishes on "
                                                  "/pub_force (the grader sent the counts to your topic to judge the rest)")
    sent = ("the grader sent the counts as " + run.input_type + " to judge the rest" if run.connected
            else "rospy connects a subscriber only to publishers of its own type")
    return judged_part(PARTS, "sub", False, f"the node subscribes /pub_force as {run.input_type or 'no known type'}, "
                                              "which is not the type the sensor publishes on it, so it would get "
                                              f"nothing from the sensor: {_FIND_TYPE} ({sent})")


def compare_mapping(observation: MappingNodeObservation, cases: Sequence[MappingCase],
                    plot_dir: Optional[Path] = None, package_dir: str = "", template: bool = False) -> List[Part]:
    """The mapping-node parts from a mapping-node session (runs in the order of ``cases``, public first).

    ``package_dir``: the student's package as the node saw it (tracebacks are named relative to it);
    ``template``: the file is the template as handed out (named as such when it fails).
    """
    T = PARTS
    runs = observation.runs
    if observation.session_error or not runs:
        reason = observation.session_error or "the grader's ROS session produced nothing"
        return [not_judged_part(T, k, f"the grader could not run the node ({reason})") for k in T]
    public, public_case = runs[0], cases[0]
    facts = public.node
    crash = _crash(facts, package_dir)
    if not public.input_topic:
        if crash is not None or template:
            message, reason = _failed_node(facts, crash, template), _not_judged_reason(template)
        elif facts.started and facts.subscriptions == [] and not facts.problem:
            message = ("mapping_node.py subscribes to no topic: create rospy.Subscriber('/pub_force', <type>, callback) "
                       f"in __init__; {_FIND_TYPE}")
            reason = "the node did not subscribe to /pub_force"
        else:
            message, reason = explain_process(facts, NODE), "the node did not subscribe to /pub_force"
        return [judged_part(T, "sub", False, message)] + [not_judged_part(T, k, reason) for k in T if k != "sub"]

    parts: List[Part] = [_sub_part(public)]
    in_topic, in_type = public.input_topic, public.input_type
    out_topic, out_type = public.output_topic, public.output_type
    answered = [r for run in runs for r in run.responses if r]
    rest = ("type", "values", "clip", "hidden")
    if not out_topic:
        advertised = ", ".join(t for t, _ in facts.publications) or "nothing"
        message = (f"the node advertises {advertised}, no /force_mapped: create "
                   "rospy.Publisher('/force_mapped', Float32, queue_size=10)")
        reason = "nothing was published"
        if crash is not None or facts.exited_by_itself:
            message = _failed_node(facts, crash, template)
            reason = _not_judged_reason(template) if crash is not None else reason
        parts.append(judged_part(T, "pub", False, message))
        return parts + [not_judged_part(T, k, reason) for k in rest]
    if not public.connected:
        if parts[0].passed or in_topic != "/pub_force":
            why = f"the grader could not connect to {in_topic} ({in_type}) and {out_topic}: " + (
                _failed_node(facts, crash, template) if facts.exited_by_itself or crash is not None or template
                else "the node ran, but took no connection within 5 s (the grader ended it then)")
            parts.append(judged_part(T, "pub", False, why))
            return parts + [not_judged_part(T, k, "no connection to the node") for k in rest]
        # a subscriber of a type the grader cannot send counts in: judged in its own part only
        reason = f"the grader cannot send counts as {in_type or 'that type'} (see above)"
        return parts + [not_judged_part(T, k, reason) for k in ("pub", *rest)]
    if out_type == "std_msgs/Float32":
        type_part = judged_part(T, "type", True)
    else:
        type_part = judged_part(T, "type", False, f"{out_topic} is {out_type or 'of no known type'}; it must be "
                                                  "std_msgs/Float32 (teleoperation subscribes Float32): "
                                                  "from std_msgs.msg import Float32")
    if not answered:
        message = (f"the node advertises {out_topic} but published nothing for the {len(public_case.counts)} counts "
                   f"sent on {in_topic}: publish the mapped value in the subscriber's callback")
        reason = "nothing was published"
        tail = facts.output_tail
        if out_type != "std_msgs/Float32" and ("SerializationError" in tail or "struct.error" in tail):
            message = (f"the node advertises {out_topic} as {out_type}, and rospy could not send the mapped float "
                       f"in it (SerializationError in its output): publish std_msgs/Float32")
        elif crash is not None or template:
            message, reason = _failed_node(facts, crash, template), _not_judged_reason(template)
        elif facts.exited_by_itself:
            message = explain_process(facts, NODE)
        parts += [judged_part(T, "pub", False, message), type_part]
        return parts + [not_judged_part(T, k, reason) for k in ("values", "clip", "hidden")]
    if out_topic != "/force_mapped":
        parts.append(judged_part(T, "pub", False, f"the node publishes on {out_topic}, not /force_mapped: teleoperation "
                                                  "listens on /force_mapped (the values were judged on your topic)"))
    else:
        parts.append(judged_part(T, "pub", True))
    parts.append(type_part)

    right = {}
    for key, which in (("values", lambda c, m: c <= m), ("clip", lambda c, m: c > m)):
        chosen, index = _items(public, public_case, which)
        ok, message, wrong = _judge_mapping(chosen, out_type, crash)
        if not ok and facts.exited_by_itself and crash is None:
            message += "\n" + explain_process(facts, NODE)
        right[key] = ok
        plots = [] if ok else mapping_plot(plot_dir, public, public_case, [index[i] for i in wrong])
        parts.append(judged_part(T, key, ok, message, plots))
    parts.append(_hidden_part(runs, cases, right["values"], right["clip"], plot_dir, package_dir))
    return parts


def _hidden_part(runs: Sequence[MappingRun], cases: Sequence[MappingCase], values_ok: bool, clip_ok: bool,
                 plot_dir: Optional[Path], package_dir: str) -> Part:
    """The hidden inputs judge the range's source, in what the public trace found right only: a mistake the
    public parts judged (no clip, integer division) costs there, not here again."""
    T = PARTS
    if not (values_ok or clip_ok):
        return not_judged_part(T, "hidden", "the values of the public trace are wrong (see above); the hidden inputs "
                                            "judge where the range comes from once they are right")

    def which(count: int, max_count: int) -> bool:
        return (count <= max_count and values_ok) or (count > max_count and clip_ok)

    note = ("" if values_ok and clip_ok else
            "counts above /max_sensor_force left out here: clipping is judged in its own part" if values_ok else
            "counts up to /max_sensor_force left out here: the mapping is judged on the public trace above")
    ok_all = True
    lines: List[str] = []
    plots: List[str] = []
    for run, case in zip(runs[1:], cases[1:]):
        if not run.input_topic or not run.connected:
            ok_all = False
            crash = _crash(run.node, package_dir)
            lines.append(f"with /max_sensor_force = {case.max_sensor_force}: "
                         + (crash_text(crash, NODE) if crash is not None else explain_process(run.node, NODE)))
            continue
        chosen, index = _items(run, case, which)
        ok, message, wrong = _judge_mapping(chosen, run.output_type, _crash(run.node, package_dir))
        if not ok:
            ok_all = False
            lines.append(f"{case.label} (/max_sensor_force = {case.max_sensor_force}): {message}")
            plots += mapping_plot(plot_dir, run, case, [index[i] for i in wrong])
    if len(runs) < len(cases):
        ok_all = False
        lines.append("the hidden runs did not happen (see the parts above)")
    return judged_part(T, "hidden", ok_all, "\n".join(lines), plots, note)


def mapping_plot(plot_dir: Optional[Path], run: MappingRun, case: MappingCase, marks: List[int]) -> List[str]:
    """The values mapping_node.py sent back for one case's counts against the expected ones ([] without a folder)."""
    if plot_dir is None:
        return []
    actual = [r[0].value if r else None for r in run.responses] + [None] * (len(case.counts) - len(run.responses))
    actual = [a if as_float(a) is not None else None for a in actual]
    path = expected_vs_actual(Path(plot_dir) / f"mapping-{case.label}.png",
                              f"/force_mapped for the {case.label} counts, /max_sensor_force = {case.max_sensor_force}",
                              list(range(len(case.counts))), list(case.expected), actual, "count number", "/force_mapped",
                              inputs=list(case.counts), input_label="/pub_force (count)", marks=marks)
    return [path]
