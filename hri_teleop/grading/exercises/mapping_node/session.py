"""Ex. 5's session: the student's mapping node in lockstep, one count in, what comes back recorded.

Runs inside the session sandbox (``python -m hri_teleop.grading.session``): no judging here.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field
from typing import Any, ClassVar, Dict, List, Tuple, Type

from hri_teleop.grading.run.lockstep import Recorder, wait_for
from hri_teleop.grading.run.records import (
    NodeFacts,
    Observation,
    Record,
    Response,
    SessionPlan,
)
from hri_teleop.grading.run.ros_session import (
    Session,
    forget_nodes,
    node_facts,
    pick_topic,
    start_problem,
    student_nodes,
    wait_for_node,
)
from hri_teleop.grading.run.sandbox import describe_exit

__all__ = ["MappingRun", "MappingNodeObservation", "MappingCasePlan", "MappingNodePlan", "COUNT_TYPES",
           "count_message", "run_mapping_node", "SESSIONS"]


@dataclass(frozen=True)
class MappingRun(Record):
    """One run of mapping_node.py for one case: the counts sent and what came back for each."""

    label: str = ""
    max_sensor_force: int = 0
    counts: List[int] = field(default_factory=list)
    responses: List[List[Response]] = field(default_factory=list)
    input_topic: str = ""
    input_type: str = ""
    output_topic: str = ""
    output_type: str = ""
    connected: bool = False
    node: NodeFacts = field(default_factory=NodeFacts)


@dataclass(frozen=True)
class MappingNodeObservation(Observation):
    KIND: ClassVar[str] = "mapping-node"

    runs: List[MappingRun] = field(default_factory=list)


@dataclass(frozen=True)
class MappingCasePlan(Record):
    label: str
    max_sensor_force: int
    counts: List[int]


@dataclass(frozen=True)
class MappingNodePlan(SessionPlan[MappingNodeObservation]):
    KIND: ClassVar[str] = "mapping-node"

    script: str
    cases: List[MappingCasePlan]
    response_timeout_s: float

    def observation_type(self) -> Type[MappingNodeObservation]:
        return MappingNodeObservation


def run_mapping_node(session: Session, plan: MappingNodePlan) -> MappingNodeObservation:
    import rospy  # noqa: PLC0415 - ROS in the session, once its master's environment is set
    from std_msgs.msg import Int16  # noqa: PLC0415 - ROS in the session, once its master's environment is set

    runs: List[MappingRun] = []
    for index, case in enumerate(plan.cases):
        if index > 0 and not any(runs[0].responses):
            break  # nothing came back for the public counts: the hidden ones cannot tell more
        session.master.set_param("/max_sensor_force", case.max_sensor_force)
        proc = session.start_student([session.python, plan.script], f"mapping_node-{index}")
        nodes, sub, pub, ok = wait_for_node(session, proc, plan.start_timeout_s, lambda s, p: bool(s))
        session.phase(f"{case.label}: subscribed")
        if ok and not pub:  # subscribed; give it a moment to advertise too
            nodes, sub, pub, _ = wait_for_node(session, proc, 2.0, lambda s, p: bool(p))
        in_topic = in_type = out_topic = out_type = ""
        connected = False
        responses: List[List[Response]] = []
        problem = "" if ok else start_problem(proc, plan.start_timeout_s, "subscribing to a topic")
        if ok:
            in_topic, in_type = pick_topic(sub, "/pub_force")
            out_topic, out_type = pick_topic(pub, "/force_mapped")
            if in_topic:
                count_type = count_message(in_type) or Int16  # the node's own type: the rest is judged all the same
                publisher = rospy.Publisher(in_topic, count_type, queue_size=1000, tcp_nodelay=True)
                recorder = Recorder()
                if out_topic:
                    recorder.add(out_topic)
                connected = wait_for(functools.partial(_both_ends, publisher, recorder, out_topic), 5.0)
                # and the node's own publisher has counted the recorder: a message published before
                # that is sent to nobody (its first count would get no answer under load)
                if connected and out_topic:
                    wait_for(functools.partial(_counted_by_node, session, sorted(nodes), out_topic), 5.0)
                if connected:
                    session.phase(f"{case.label}: connected")
                    responses = _lockstep(publisher, count_type, recorder, out_topic, case.counts, proc,
                                          plan.response_timeout_s)
                    session.phase(f"{case.label}: answered")
                recorder.close()
                publisher.unregister()
            nodes2, sub2, pub2, _ = wait_for_node(session, proc, 0.0, lambda s, p: True)
            if nodes2:
                nodes, sub, pub = nodes2, sub2, pub2
        exited = not proc.running
        if exited and not problem:
            problem = f"{describe_exit(proc.returncode)} while counts were being published"
        if connected and out_topic and not problem:
            proc.kill()  # every answer recorded; its exit is never explained, so no grace (rospy's 0.5 s poll)
        else:
            proc.stop()
        session.phase(f"{case.label}: ended")
        runs.append(MappingRun(label=case.label, max_sensor_force=case.max_sensor_force, counts=case.counts,
                               responses=responses, input_topic=in_topic, input_type=in_type, output_topic=out_topic,
                               output_type=out_type, connected=connected,
                               node=node_facts(proc, nodes, sub, pub, problem, exited)))
        forget_nodes(session.master, student_nodes(session.master, session.baseline))
    return MappingNodeObservation(runs=runs)


def _counted_by_node(session: Session, nodes: List[str], topic: str) -> bool:
    """One of the student's nodes has a subscriber of ``topic`` in its own bus info (the recorder)."""
    return any(session.master.connections(node, topic, "o") > 0 for node in nodes)


def _both_ends(publisher: Any, recorder: Recorder, out_topic: str) -> bool:
    """The node takes the grader's counts and (if it has an output) the recorder hears it."""
    return bool(publisher.get_num_connections() > 0 and (not out_topic or recorder.connected(out_topic)))


#: The std_msgs types a count 0..1023 fits in: a node that subscribes /pub_force as one of them gets the
#: counts in its own type (its subscriber's type is judged in its own part; the rest is judged all the same).
COUNT_TYPES = ("std_msgs/Int16", "std_msgs/Int32", "std_msgs/Int64", "std_msgs/UInt16", "std_msgs/UInt32",
               "std_msgs/UInt64", "std_msgs/Float32", "std_msgs/Float64")


def count_message(kind: str) -> Any:
    """The message class of ``kind`` when it is one of :data:`COUNT_TYPES`, else None."""
    if kind not in COUNT_TYPES:
        return None
    import roslib.message  # noqa: PLC0415 - ROS in the session, once its master's environment is set

    return roslib.message.get_message_class(kind)


def _lockstep(publisher: Any, count_type: Any, recorder: Recorder, out_topic: str, counts: List[int], proc: Any,
              timeout_s: float) -> List[List[Response]]:
    """Publish one count (as ``count_type``), collect what comes back before the next one; returns values per count."""
    floats = "Float" in getattr(count_type, "_type", "")
    responses: List[List[Response]] = []
    misses = 0  # counts that got no answer in time: after three, wait only briefly (a node that
    # never answers, or skips some counts, must not cost a second per count)
    for i, count in enumerate(counts):
        before = recorder.count(out_topic) if out_topic else 0
        recorder.event.clear()
        publisher.publish(count_type(data=float(count) if floats else int(count)))
        wait_s = (max(2.0, timeout_s) if i == 0 else timeout_s) if misses < 3 else 0.05
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline and (not out_topic or recorder.count(out_topic) == before):
            recorder.event.wait(0.005)
        if out_topic and recorder.count(out_topic) > before:
            time.sleep(0.002)  # a second message for the same count would arrive now
        else:
            misses += 1
        got = recorder.since(out_topic, before) if out_topic else []
        responses.append([Response(kind, value) for _, kind, value in got])
        if not proc.running:
            responses.extend([] for _ in counts[i + 1:])
            break
    return responses


#: The plans this exercise's sessions run: kind -> (plan type, what runs it).
SESSIONS: Dict[str, Tuple[Type[SessionPlan[Any]], Any]] = {MappingNodePlan.KIND: (MappingNodePlan, run_mapping_node)}
