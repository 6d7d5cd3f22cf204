"""Ex. 9's session: the student's teleoperation node driven by a scripted virtual pad, fed a force, recorded.

Runs inside the session sandbox (``python -m hri_teleop.grading.session``): no judging here.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar, Dict, List, Optional, Sequence, Tuple, Type

from hri_teleop.grading.run.gains import TeleopGains
from hri_teleop.grading.run.lockstep import (
    GraderClock,
    Recorder,
    connections,
    wait_for,
)
from hri_teleop.grading.run.records import (
    ClockedObservation,
    Message,
    NodeFacts,
    SessionPlan,
    Topic,
)
from hri_teleop.grading.run.ros_session import (
    Session,
    node_facts,
    recorded_since,
    start_problem,
    wait_for_node,
)

__all__ = ["TeleopNodeObservation", "TeleopNodePlan", "run_teleop_node", "stepped_topics", "FORCE_TYPES", "SESSIONS"]


def run_teleop_node(session: Session, plan: TeleopNodePlan) -> TeleopNodeObservation:
    """The student's teleoperation.py with a scripted virtual pad and a steady /force_mapped."""
    feeder = _ForceFeeder(plan.force)
    params = [f"_{k}:={v}" for k, v in plan.gains.as_dict().items()]
    argv = [session.python, plan.script, "_pad:=virtual", "_layout:=dualshock4",
            f"_pad_script:={plan.pad_script}", *params]
    clock = GraderClock(session) if plan.clock == "grader" else None
    recorder = Recorder(clock.now if clock else time.monotonic)
    record = list(plan.record)
    # Subscribed before the node starts: the pad script plays from its start. Under the grader's
    # clock the twist (the first topic) comes last, once every other topic is connected at both
    # ends: the node's first tick waits for a listener on its twist (the template's
    # wait_for_robot), and a width published before its connection was counted would be lost.
    for topic in record[1:] if clock else record:
        recorder.add(topic)
    proc = session.start_student(argv, "teleoperation", clock.student_env(session.folder) if clock else None)
    nodes, sub, pub, ok = wait_for_node(session, proc, plan.start_timeout_s, lambda s, p: bool(p))
    problem = "" if ok else start_problem(proc, plan.start_timeout_s, "advertising a topic")
    if ok and clock is not None and record:
        others = record[1:]
        wait_for(lambda: all(recorder.connected(t) and any(connections(session, n, t, "o") > 0 for n in nodes)
                          for t in others) or not proc.running, GraderClock.STEP_TIMEOUT_S, 0.002)
        recorder.add(record[0])
    started = clock.now() if clock else time.monotonic()

    def follow_node() -> None:
        """Add what the node registered since: a node that is shutting down has unregistered its
        topics already, so a later reading never replaces an earlier one."""
        nonlocal nodes, sub, pub
        nodes2, sub2, pub2, _ = wait_for_node(session, proc, 0.0, lambda s, p: True)
        if nodes2:
            nodes = set(nodes) | set(nodes2)
            sub = sub + [x for x in sub2 if x not in sub]
            pub = pub + [x for x in pub2 if x not in pub]
        for topic, _kind in pub:
            recorder.add(topic)
        feeder.follow(sub)
        feeder.sample()

    if ok:
        feeder.follow(sub)
    if ok and clock is not None:
        clock.wait_for_listener(nodes, proc, plan.start_timeout_s)
        # The loop's first tick comes at the start time, before any step: step only after it,
        # so tick k is always at start + k periods (stepping earlier would race the node's start).
        wait_for(lambda: recorder.count(plan.record[0]) > 0 or not proc.running, plan.start_timeout_s, 0.0005)
        # Every topic of tick 0 before the first step (a message that arrived after it would be
        # stamped a tick late); a topic the node never publishes costs one step timeout, once.
        wait_for(lambda: all(recorder.count(t) > 0 for t in plan.record) or not proc.running,
              GraderClock.STEP_TIMEOUT_S, 0.0005)
        # A twist on a topic of the node's own (judged in its part) is stepped on like the expected one once
        # both ends are connected: not waited for, its queue_size=1 publisher would drop twists whenever a
        # loaded machine sends slower than the clock steps, and the loop would seem not to keep ~rate.
        follow_node()
        own = [t for t, kind in pub if kind == TWIST_TYPE and t not in plan.record]
        wait_for(lambda: all(recorder.connected(t) and any(connections(session, n, t, "o") > 0 for n in nodes)
                             for t in own) or not proc.running, GraderClock.STEP_TIMEOUT_S, 0.002)
        lockstep = stepped_topics(plan.record, lambda t: recorder.count(t) > 0,
                                  [t for t in own if recorder.connected(t)])
        tick = 0
        while clock.now() - started < plan.run_s and proc.running:
            if tick % 25 == 0:
                follow_node()
            tick += 1
            if not clock.step(float(plan.gains.rate), recorder, lockstep, proc) and proc.running:
                if clock.answered:  # it followed the clock and fell silent: it is ending (or hangs)
                    session.phase(f"silent from {clock.now() - started:.2f} s")
                    break
                session.phase(f"paced from {clock.now() - started:.2f} s")
                clock.paced = True
        proc.wait(plan.quit_grace_s)
    elif ok:
        deadline = started + plan.run_s
        while time.monotonic() < deadline and proc.running:
            follow_node()
            time.sleep(0.1)
        proc.wait(plan.quit_grace_s)
    exited = not proc.running
    exit_code = proc.returncode
    proc.stop()
    feeder.close()
    recorder.drain(Recorder.DRAIN_TIMEOUT_S)  # the node has ended: what it sent last is read, in every run
    recorder.close()
    return TeleopNodeObservation(
        problem=problem, quit_in_time=exited, clock="real time" if clock is None or clock.paced else "grader",
        rescued_steps=clock.rescues if clock else 0, node=node_facts(proc, nodes, sub, pub, problem, exited),
        exit_code=exit_code, messages=recorded_since(recorder, started), fed_force=list(feeder.fed),
        force_connected=feeder.connected)


TWIST_TYPE = "geometry_msgs/Twist"


def stepped_topics(record: Sequence[str], heard: Callable[[str], bool], own_twists: Sequence[str]) -> List[str]:
    """The topics each step of the grader's clock waits for: those of ``record`` the node published on at
    tick 0 (``heard``), then its twists on topics of its own (connected at both ends); the first of
    ``record`` when nothing else (a node that publishes nothing still gets its steps timed)."""
    topics = [t for t in record if heard(t)] + [t for t in own_twists if t not in record]
    return topics or list(record[:1])


#: The std_msgs types a force 0..1 can be sent in: a node whose force subscriber has one of them (on
#: /force_mapped or its only such topic) gets the force there (its subscriber is judged in its own part).
FORCE_TYPES = ("std_msgs/Float32", "std_msgs/Float64")


class _ForceFeeder:
    """The steady force every 50 ms of wall time: on /force_mapped as std_msgs/Float32, or where the node's
    own force subscriber listens instead (:meth:`follow`)."""

    def __init__(self, force: float) -> None:
        import rospy  # noqa: PLC0415 - ROS in the session, once its master's environment is set
        from std_msgs.msg import Float32  # noqa: PLC0415 - ROS in the session, once its master's environment is set

        self._rospy = rospy
        self._force = force
        self._lock = threading.Lock()
        self._pubs: List[Any] = [(rospy.Publisher("/force_mapped", Float32, queue_size=10), Float32)]
        self.fed: List[Topic] = []
        #: a subscriber was connected at one of the samples (the node's loop runs for seconds: a subscriber of
        #: the force's type is connected at most of them, one of another type at none)
        self.connected = False
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            with self._lock:  # a publisher is swapped under the lock: never one published after its unregister
                for publisher, make in self._pubs:
                    publisher.publish(make(data=self._force))
            self._stop.wait(0.05)

    def follow(self, subs: List[Topic]) -> None:
        """Once: send the force where the node listens when that is not /force_mapped as std_msgs/Float32."""
        if self.fed or Topic("/force_mapped", "std_msgs/Float32") in subs:
            return
        others = [s for s in subs if s.type in FORCE_TYPES]
        if len(others) != 1:
            return
        import roslib.message  # noqa: PLC0415 - ROS in the session, once its master's environment is set

        topic, kind = others[0]
        make = roslib.message.get_message_class(kind)
        with self._lock:
            if topic == "/force_mapped":  # rospy keeps one type per topic in a process
                for publisher, _ in self._pubs:
                    publisher.unregister()
                self._pubs = []
            self._pubs.append((self._rospy.Publisher(topic, make, queue_size=10), make))
        self.fed.append(Topic(topic, kind))

    def sample(self) -> None:
        with self._lock:
            self.connected = self.connected or any(p.get_num_connections() > 0 for p, _ in self._pubs)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(1.0)


#: How long a step waits for the sensor chain to pass on a tick's counts (s); a chain that
#: does not within it (a student's mapping_node that drops or merges counts) is not waited for again.


@dataclass(frozen=True)
class TeleopNodeObservation(ClockedObservation):
    KIND: ClassVar[str] = "teleop-node"

    quit_in_time: bool = False
    rescued_steps: int = 0
    node: NodeFacts = field(default_factory=NodeFacts)
    exit_code: Optional[int] = None
    messages: Dict[str, List[Message]] = field(default_factory=dict)
    #: where the grader sent the steady force instead of /force_mapped (std_msgs/Float32): the topic and
    #: type the node subscribes, so a subscriber of another type or topic costs its own part only
    fed_force: List[Topic] = field(default_factory=list)
    #: whether a subscriber of the node was connected to the grader's force publisher at some point of the run
    force_connected: bool = True


@dataclass(frozen=True)
class TeleopNodePlan(SessionPlan[TeleopNodeObservation]):
    KIND: ClassVar[str] = "teleop-node"

    script: str
    pad_script: str
    gains: TeleopGains
    force: float
    run_s: float
    quit_grace_s: float
    record: List[str]
    clock: str

    def observation_type(self) -> Type[TeleopNodeObservation]:
        return TeleopNodeObservation


#: The plans this exercise's sessions run: kind -> (plan type, what runs it).
SESSIONS: Dict[str, Tuple[Type[SessionPlan[Any]], Any]] = {TeleopNodePlan.KIND: (TeleopNodePlan, run_teleop_node)}
