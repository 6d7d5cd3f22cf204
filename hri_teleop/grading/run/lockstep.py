"""The grader's clock and the waits that keep a student's nodes in lock step with it.

Under ``/use_sim_time`` the grader publishes /clock one tick at a time (:class:`GraderClock`)
and, before the next tick, waits for what the tick must produce: messages counted by a
:class:`Recorder`, connections counted at both ends from the nodes' own bus info
(:func:`connections`), a graph that has settled. Every wait is bounded on the wall clock.
Runs inside the grading session (:mod:`hri_teleop.grading.session`).
"""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Protocol, Sequence, Set, Tuple

from hri_teleop.grading.run.clock_sleep import student_clock_env
from hri_teleop.hardware.gamepad import PAD_CLOCK_ENV
from hri_teleop.ros.master import MasterError, PrivateMaster
from hri_teleop.ros.proc_table import busy_threads, process_trees

__all__ = ["GRADER_NODE", "wait_for", "Recorder", "GraderClock", "Quiescence", "wait_until_settled", "last_value",
           "connections", "node_rate_hz"]


class Session(Protocol):
    """What the waits need of a grading session (hri_teleop.grading.session.Session): its master."""

    master: PrivateMaster


#: The grader's own node in a session (its recorders and publishers; the caller id of its bus-info reads).
GRADER_NODE = "/hri_grader"


def wait_for(condition: Callable[[], bool], timeout_s: float, poll_s: float = 0.02) -> bool:
    """Poll ``condition`` every ``poll_s`` until it holds (True) or ``timeout_s`` of wall time passed."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(poll_s)
    return condition()


class Recorder:
    """Subscribes to topics of any type and keeps (time, type, decoded value) per topic."""

    #: Longest wait for an ended node's last messages, s of wall time (they are read within
    #: milliseconds; a publisher that vanished without closing its socket costs rospy's 1 s retry).
    DRAIN_TIMEOUT_S = 5.0

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        import rospy  # noqa: PLC0415 - ROS only in a session (the waits import without it)

        self._rospy = rospy
        self._clock = clock  # the grader's /clock when it owns the time: messages stamped in simulated time
        self.subs: Dict[str, Any] = {}
        self.messages: Dict[str, List[Tuple[float, str, Any]]] = {}
        self.lock = threading.Lock()
        self.event = threading.Event()
        self.closed = False

    def add(self, topic: str) -> None:
        if topic in self.subs:
            return
        self.messages.setdefault(topic, [])
        self.subs[topic] = self._rospy.Subscriber(topic, self._rospy.AnyMsg, self._callback, callback_args=topic,
                                                  queue_size=1000, tcp_nodelay=True)

    def connected(self, topic: str) -> bool:
        return topic in self.subs and self.subs[topic].get_num_connections() > 0

    def _callback(self, msg: Any, topic: str) -> None:
        now = self._clock()
        kind = msg._connection_header.get("type", "")
        value = _decode(kind, msg._buff)
        with self.lock:
            if self.closed:  # rospy still hands over the rest of a batch it read before the close
                return
            self.messages[topic].append((now, kind, value))
        self.event.set()

    def count(self, topic: str) -> int:
        with self.lock:
            return len(self.messages.get(topic, []))

    def since(self, topic: str, index: int) -> List[Tuple[float, str, Any]]:
        with self.lock:
            return list(self.messages.get(topic, [])[index:])

    def drain(self, timeout_s: float) -> bool:
        """Once the publishers have ended: until every message they sent has been read (rospy drops a
        connection only after reading its socket to the end, callbacks included), at most ``timeout_s``
        of wall time. Closing before that loses an ended node's last messages, or not, at random."""
        return wait_for(lambda: all(sub.get_num_connections() == 0 for sub in self.subs.values()), timeout_s, 0.002)

    def close(self) -> None:
        """Nothing more is recorded from here on."""
        with self.lock:
            self.closed = True
        for sub in self.subs.values():
            sub.unregister()
        self.subs.clear()


def _decode(kind: str, buff: bytes) -> Any:
    """A message's value: ``data`` for std_msgs, the 6 numbers of a Twist, else its repr."""
    import roslib.message  # noqa: PLC0415 - ROS only in a session (the waits import without it)

    cls = roslib.message.get_message_class(kind) if kind else None
    if cls is None:
        return None
    msg = cls()
    try:
        msg.deserialize(buff)
    except Exception:  # noqa: BLE001 - a corrupt message is recorded as such
        return {"__repr__": "undecodable"}
    if kind == "geometry_msgs/Twist":
        return [msg.linear.x, msg.linear.y, msg.linear.z, msg.angular.x, msg.angular.y, msg.angular.z]
    if hasattr(msg, "data") and isinstance(msg.data, (int, float, bool)):
        return msg.data
    if kind == "geometry_msgs/PoseStamped":
        return [msg.pose.position.x, msg.pose.position.y, msg.pose.position.z]
    if kind == "sensor_msgs/JointState":
        return list(msg.position)
    if kind == "diagnostic_msgs/DiagnosticStatus":
        return {value.key: value.value for value in msg.values}
    return {"__repr__": repr(msg)[:100]}


class GraderClock:
    """The grader owns the time: ``/use_sim_time`` is set and /clock advances one tick at a time.

    Each step moves the clock by one period of the node's rate and waits until the node has
    published on the lockstep topic, so what the node does per tick no longer depends on
    how busy the machine is, and a run lasts as long as the node computes. A node that
    publishes nothing after a step (it does not follow rospy.Rate) gets real-time pacing:
    the clock then moves one period per period of wall time, as before.
    """

    #: How long a step waits for the tick's messages, s of wall time (a loaded machine
    #: answers within milliseconds; a node that ignores /clock never does).
    STEP_TIMEOUT_S = 2.0
    #: The same, once the node has answered a step: it follows the clock, so a late answer is
    #: a stall of the machine (CI saw one of over 2 s with both cores busy), not a node that
    #: ignores /clock; waiting longer keeps the run on the grader's clock.
    STALL_TIMEOUT_S = 15.0

    def __init__(self, session: Session, start_s: float = 1.0, started: bool = True) -> None:
        """``started`` False: ROS time stays 0 (nodes that wait for the clock wait) until :meth:`start`."""
        import rospy  # noqa: PLC0415 - ROS only in a session (the waits import without it)
        from rosgraph_msgs.msg import Clock  # type: ignore[import-untyped]  # noqa: PLC0415 - as rospy above

        self._rospy, self._Clock = rospy, Clock
        self._master = session.master
        session.master.set_param("/use_sim_time", True)  # before the student's node starts
        self._pub = rospy.Publisher("/clock", Clock, queue_size=10, latch=True, tcp_nodelay=True)
        # Whole nanoseconds: rospy.Rate steps its deadline by int(1e9 / rate) ns, so a clock kept
        # in floats (1.14 -> 1.139999999 s) would miss a tick now and then.
        self._now_ns = int(round(start_s * 1e9))
        self.paced = False
        self.answered = 0  # steps the node answered within their timeout
        self.rescues = 0  # steps that needed one more tick to be answered (see step)
        if started:
            self._publish()

    def start(self) -> None:
        """The first reading (``start_s``): every node waiting for the clock begins at this instant."""
        self._publish()

    def _publish(self) -> None:
        self._pub.publish(self._Clock(clock=self._rospy.Time(self._now_ns // 10**9, self._now_ns % 10**9)))

    def now(self) -> float:
        return self._now_ns / 1e9

    @staticmethod
    def student_env(folder: Optional[Path], pythonpath: str = "") -> Dict[str, str]:
        """The virtual pad's script on ROS time, as the node's loop; time.sleep in the student's
        files below ``folder`` on it too (:mod:`hri_teleop.grading.run.clock_sleep`)."""
        return {PAD_CLOCK_ENV: "ros", **(student_clock_env(folder, pythonpath) if folder is not None else {})}

    def wait_for_listener(self, nodes: Set[str], proc: Any, timeout_s: float) -> bool:
        """Until one of ``nodes`` subscribes /clock (then the latched time reached it)."""
        return wait_for(lambda: bool(set(self._master.subscribers("/clock")) & set(nodes)) or not proc.running,
                     timeout_s, 0.005)

    def step(self, rate_hz: float, recorder: Recorder, topics: Sequence[str], proc: Any,
             also: Callable[[], bool] = lambda: True) -> bool:
        """One period of a loop at ``rate_hz`` (rospy.Rate's own arithmetic), then wait for the tick's messages
        (a new one on each of ``topics``) and for ``also``.

        False when they did not come within ``STEP_TIMEOUT_S``, or, once the node has answered
        a step, within ``STALL_TIMEOUT_S`` and one more tick while its publishers live: the
        caller decides whether the node ignores the clock (``paced`` from then on) or has ended.
        """
        before = [recorder.count(t) for t in topics]
        self._now_ns += int(1e9 / rate_hz)
        self._publish()
        if self.paced:
            time.sleep(1.0 / rate_hz)
            return True
        def came() -> bool:
            return all(recorder.count(t) > b for t, b in zip(topics, before)) and also()

        answered = wait_for(lambda: came() or not proc.running, self.STEP_TIMEOUT_S, 0.0002)
        if not answered and self.answered:
            # Late, from a node that followed the clock so far. Either the machine stalled, or the
            # node read the time after this step's reading had reached it: rospy.sleep(d) sleeps
            # until that reading + d, a tick past what it waits for (rospy.Rate has the same race in
            # a narrower window). One more tick wakes it; then wait while its publishers live.
            def gone() -> bool:
                return not proc.running or not all(self._master.publishers(t) for t in topics)

            self.rescues += 1
            self._now_ns += int(1e9 / rate_hz)
            self._publish()
            answered = wait_for(lambda: came() or gone(), self.STALL_TIMEOUT_S - self.STEP_TIMEOUT_S, 0.005)
            answered = answered and came()
        if answered and proc.running:
            self.answered += 1
        return answered or not proc.running


class Quiescence:
    """Waits, after a tick, until every process under grading waits for something (no thread runnable).

    Messages between the nodes travel over loopback TCP: a message sent wakes its receiver
    at once, so while one is in flight some thread is runnable. All of them waiting means
    the tick's work is done everywhere: a gripper goal reached the simulated lab, a force
    reached the teleoperation node's callback, before the next tick in every run, loaded or
    not. Two readings in a row, as a reading of many threads is not one instant. A process
    that never waits (a busy loop) would hold every tick: after one timeout it is not waited for
    again (a loaded machine gets quiet well within it: a stall CI saw lasted 2 s).
    """

    TIMEOUT_S = 5.0
    GAP_S = 0.0003

    def __init__(self, roots: Sequence[int]) -> None:
        self.roots = list(roots)
        self.pids: List[int] = []
        self.enabled = True
        self.timeouts = 0
        self.refresh()

    def refresh(self) -> None:
        """The roots and everything below them now (roslaunch starts its nodes as children)."""
        self.pids = process_trees(self.roots)

    def _quiet(self) -> bool:
        if busy_threads(self.pids):
            return False
        time.sleep(self.GAP_S)
        return busy_threads(self.pids) == 0

    def wait(self) -> bool:
        """True once quiet; False (and no more waiting) when it was not within ``TIMEOUT_S``."""
        if not self.enabled:
            return True
        if wait_for(self._quiet, self.TIMEOUT_S, 0.0002):
            return True
        self.timeouts += 1
        self.enabled = False
        return False


def wait_until_settled(session: Session, expected: Set[str], proc: Any, timeout_s: float,
                        quiet_s: float = 0.2) -> bool:
    """Until ``expected`` nodes are registered and the graph has not changed for ``quiet_s``."""
    deadline = time.monotonic() + timeout_s
    previous: Any = None
    since = time.monotonic()
    while time.monotonic() < deadline and proc.running:
        state = session.master.system_state()
        reading = (sorted((t, sorted(n)) for t, n in state[0]), sorted((t, sorted(n)) for t, n in state[1]))
        names = {n for _t, ns in list(state[0]) + list(state[1]) + list(state[2]) for n in ns}
        if reading != previous or not expected <= names:
            previous, since = reading, time.monotonic()
        elif time.monotonic() - since >= quiet_s:
            return True
        time.sleep(0.02)
    return False


def last_value(recorder: Recorder, topic: str, default: float) -> float:
    with recorder.lock:
        messages = recorder.messages.get(topic) or []
        value = messages[-1][2] if messages else default
    return float(value) if isinstance(value, (int, float)) else default


def connections(session: Session, node: str, topic: str, direction: str = "i") -> int:
    """How many connections ``node`` has on ``topic`` now (:meth:`PrivateMaster.connections`)."""
    return session.master.connections(node, topic, direction)


def node_rate_hz(session: Session, node: str, default_hz: float, param: str = "rate") -> float:
    """The loop rate a node was given (its private ``param``), else the lab's default."""
    try:
        raw = session.master.get_param(f"{node}/{param}")
        value = float(raw) if isinstance(raw, (int, float, str)) else math.nan  # nan: not a rate
    except (MasterError, ValueError):
        return default_hz
    return value if 0.0 < value <= 1000.0 else default_hz
