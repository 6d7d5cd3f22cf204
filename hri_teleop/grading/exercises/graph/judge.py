"""Judging Ex. 15's graph.yaml against the live graph of the lab's pipeline.

Feedback counts what is missing, quotes back the student's entries that do not belong and names the
command that shows the truth, never the pipeline's names or types. Each part rewards one thing (the
format, listing at least one node and one topic; the nodes; the topics and types; the links), and
links wait for what they connect: docs/instructors.md, "How the launch and graph parts depend on
each other".
"""

from __future__ import annotations

import re
from typing import Any, Dict, Iterable, List, Mapping, Sequence, Set, Tuple

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.grading.exercises.graph.session import LiveGraphObservation
from hri_teleop.grading.judge.compare_common import judged_part, not_judged_part
from hri_teleop.grading.judge.compare_launch import written
from hri_teleop.grading.results import Part

__all__ = ["PARTS", "PIPELINE_TOPICS", "SEE_NODES", "SEE_TOPICS", "compare_graph"]

#: Part key -> (name as students read it, points; tests refer to the keys).
PARTS: Dict[str, Tuple[str, float]] = {
    "format": ("graph.yaml has a list of nodes and a mapping of topics", 1),
    "nodes": ("the pipeline's nodes", 2),
    "types": ("the pipeline's topics and their message types", 3),
    "links": ("who publishes and who subscribes each topic", 3),
}


PIPELINE_TOPICS = ("/pub_force", "/force_mapped", "/gripper_width", DEFAULT_TWIST_TOPIC)
_SENSOR_ALIASES = {"/serial_node", "/FSR_sensor"}  # the Arduino in the lab, its simulation at home
_LAB_ONLY = re.compile(r"^/(franka|cartesian_velocity_controller|joint_state|robot_state|rosout|rqt|record|rosbag|rostopic)")
#: Where the student finds the truth: the tools, never what they show.
SEE_NODES = ("`rosnode list` shows the running nodes while the pipeline runs (or rqt_graph, or the graph view of "
             "the ex15 notebook)")
SEE_TOPICS = ("`rostopic list` shows the running topics while the pipeline runs, and `rostopic info <topic>` who "
              "publishes and subscribes each")


def _name(value: Any) -> str:
    text = str(value).strip()
    return text if text.startswith("/") else "/" + text


def _entries(values: Any) -> Dict[str, str]:
    """The student's node names: canonical name (the sensor's aliases as one) -> as written."""
    if values is None:
        return {}
    if isinstance(values, (str, int, float)):
        values = [values]
    if not isinstance(values, (list, tuple)):
        return {}
    out: Dict[str, str] = {}
    for value in values:
        out.setdefault(_canon_one(_name(value)), written(value))
    return out


def _canon_one(node: str) -> str:
    return "/serial_node" if node in _SENSOR_ALIASES else node


def _canon(nodes: Iterable[str]) -> Set[str]:
    return {_canon_one(n) for n in nodes}


def _count(n: int, one: str, many: str = "") -> str:
    return f"{n} {one if n == 1 else (many or one + 's')}"


def _not_listed(missing: int, of: int, what: str) -> str:
    """'1 of the pipeline's 4 nodes is not listed', 'none of the pipeline's 4 topics is listed'."""
    if missing == of:
        return f"none of the pipeline's {of} {what}s is listed"
    return f"{missing} of the pipeline's {of} {what}s {'is' if missing == 1 else 'are'} not listed"


def _listed(names: Sequence[str]) -> str:
    return ", ".join(names)


def compare_graph(answer: Any, live: LiveGraphObservation, answer_error: str = "") -> List[Part]:
    """The student's graph.yaml against the live graph of the lab's pipeline (hri_lab, no hardware)."""
    T = PARTS
    if answer_error or not isinstance(answer, dict) or not isinstance(answer.get("nodes"), (list, type(None))) \
            or not isinstance(answer.get("topics"), (dict, type(None))) or ("nodes" not in answer and "topics" not in answer):
        why = answer_error or ("graph.yaml needs `nodes:` (a list of node names) and `topics:` (a mapping from "
                               "topic name to type, publishers and subscribers); see the template")
        cause = "graph.yaml could not be read" if answer_error else "graph.yaml is not in the format (the format part)"
        return [judged_part(T, "format", False, why)] + [not_judged_part(T, k, cause) for k in ("nodes", "types", "links")]
    listed = _entries(answer.get("nodes"))
    topics = {_name(k): (written(k), v) for k, v in (answer.get("topics") or {}).items()}
    empty = [what for what, got in (("node", listed), ("topic", topics)) if not got]
    parts = [judged_part(T, "format", not empty, "" if not empty else (
        f"graph.yaml lists no {' and no '.join(empty)}: write what the running pipeline shows, in the format of the "
        f"file's comment; {SEE_NODES if 'node' in empty else SEE_TOPICS}"))]

    pubs, subs, types = live.publishers, live.subscribers, live.types
    running = _canon(n for ns in list(pubs.values()) + list(subs.values()) for n in ns)
    pipeline = _canon(n for t in PIPELINE_TOPICS for n in pubs.get(t, []) + subs.get(t, []))
    missing_nodes = pipeline - set(listed)
    strangers = {n: w for n, w in listed.items() if n not in running and not _LAB_ONLY.match(n)}
    parts.append(_nodes_part(listed, missing_nodes, strangers, len(pipeline)))
    if not topics:
        return parts + [not_judged_part(T, k, "graph.yaml lists no topic (the format part)") for k in ("types", "links")]
    parts.append(_types_part(topics, types))
    parts.append(_links_part(topics, live, pipeline, missing_nodes, set(strangers)))
    return parts


def _nodes_part(listed: Dict[str, str], missing: Set[str], strangers: Dict[str, str], of: int) -> Part:
    if not listed:
        return not_judged_part(PARTS, "nodes", "graph.yaml lists no node (the format part)")
    problems = []
    if missing:
        problems.append(_not_listed(len(missing), of, "node"))
    if strangers:
        problems.append(f"not a node of the running graph: {_listed(sorted(strangers.values()))} (check the spelling, "
                        "the leading slash, and that it is the node's name, not its script's)")
    return judged_part(PARTS, "nodes", not problems, "; ".join(problems) + (f"; {SEE_NODES}" if problems else ""))


def _topic_type(entry: Any) -> Any:
    return entry.get("type") if isinstance(entry, dict) else entry


def _types_part(topics: Dict[str, Tuple[str, Any]], types: Mapping[str, str]) -> Part:
    problems = []
    missing = [t for t in PIPELINE_TOPICS if t not in topics]
    if missing:
        problems.append(f"{_not_listed(len(missing), len(PIPELINE_TOPICS), 'topic')}: {SEE_TOPICS}")
    strangers = sorted(w for t, (w, _e) in topics.items() if t not in types and not _LAB_ONLY.match(t))
    if strangers:
        problems.append(f"not a topic of the running graph: {_listed(strangers)} (check the spelling and the leading "
                        "slash with `rostopic list`)")
    for topic in sorted(t for t in topics if t in types):
        shown, entry = topics[topic]
        kind = _topic_type(entry)
        if kind is None or str(kind).strip() == "":
            problems.append(f"{shown}: no type given; `rostopic type {topic}` prints it")
        elif str(kind).strip() != types[topic]:
            problems.append(f"{shown}: {written(kind)} is not its type; `rostopic type {topic}` prints it "
                            "(package/Message)")
    return judged_part(PARTS, "types", not problems, "\n".join(problems))


def _links_part(topics: Dict[str, Tuple[str, Any]], live: LiveGraphObservation, pipeline: Set[str],
                missing_nodes: Set[str], strangers: Set[str]) -> Part:
    """Who publishes and subscribes each of the pipeline's topics listed.

    Not charged again here: a topic not listed (the types part), a node missing from ``nodes`` and a
    name not in the running graph that ``nodes`` lists (the nodes part). A listed stranger standing where a
    node missing from ``nodes`` belongs is the same mistake (a wrong name), so the connection counts as
    right; a node missing everywhere leaves its connections not judged.
    """
    problems = []
    unjudged = 0
    for topic in PIPELINE_TOPICS:
        if topic not in topics:
            continue
        shown, entry = topics[topic]
        if not isinstance(entry, dict):
            problems.append(f"{shown}: list its publishers and subscribers (`rostopic info {topic}`)")
            continue
        for role, live_side, verb in (("publishers", live.publishers, "publish"),
                                      ("subscribers", live.subscribers, "subscribe")):
            if topic == DEFAULT_TWIST_TOPIC and role == "subscribers":
                continue  # the robot's controller: not running without the robot
            want = _canon(n for n in live_side.get(topic, []) if _canon_one(n) in pipeline)
            got = {n: w for n, w in _entries(entry.get(role)).items() if not _LAB_ONLY.match(n)}
            extra, lacking = set(got) - want, want - set(got)
            wrong = sorted(got[n] for n in extra - strangers)
            lacking_listed = len(lacking - missing_nodes)
            unjudged += max(0, len(lacking & missing_nodes) - len(extra & strangers))
            said = ([f"{_count(lacking_listed, role[:-1], role)} missing"] if lacking_listed else []) + \
                   ([f"{_listed(wrong)} {'does' if len(wrong) == 1 else 'do'} not {verb} it"] if wrong else [])
            if said:
                problems.append(f"{shown} {role}: {'; '.join(said)} (`rostopic info {topic}`)")
    unlisted = [t for t in PIPELINE_TOPICS if t not in topics]
    waiting = ([f"the connections of {_count(len(unlisted), 'topic')} not listed (the types part)"] if unlisted else []) \
        + ([f"{_count(unjudged, 'connection')} of nodes missing from `nodes` (the nodes part)"] if unjudged else [])
    if problems:
        if waiting:
            problems.append(f"not judged yet: {' and '.join(waiting)}")
        return judged_part(PARTS, "links", False, "\n".join(problems))
    if waiting:
        return not_judged_part(PARTS, "links", f"{' and '.join(waiting)}: list what the parts above find missing, "
                               "then who publishes and subscribes it")
    return judged_part(PARTS, "links", True)
