"""One grading session's ROS side: its private master, the student's processes and their graph.

What the student's nodes subscribe and publish is read from the master, not from their code.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Set, Tuple

from hri_teleop.grading.run.lockstep import (
    GRADER_NODE,
    Recorder,
    wait_for,
)
from hri_teleop.grading.run.records import Message, NodeFacts, ProcessFacts, SessionContext, Topic
from hri_teleop.grading.run.sandbox import StudentProcess, describe_exit
from hri_teleop.ros.master import PrivateMaster, stop_side_by_side

__all__ = ["IGNORED_TOPICS", "topic_graph", "student_nodes", "forget_nodes", "node_io", "node_facts", "start_problem", "wait_for_node", "launch_facts", "pick_topic", "Session"]

IGNORED_TOPICS = ("/rosout", "/rosout_agg")


# -- what a student's node did ------------------------------------------------------------

def topic_graph(master: PrivateMaster) -> Tuple[Dict[str, Set[str]], Dict[str, Set[str]], Dict[str, str]]:
    """(topic -> publisher nodes, topic -> subscriber nodes, topic -> type) from the master."""
    pubs, subs, _ = master.system_state()
    types = master.topic_types()
    return ({t: set(n) for t, n in pubs}, {t: set(n) for t, n in subs}, types)


def student_nodes(master: PrivateMaster, baseline: Set[str]) -> Set[str]:
    return {n for n in master.node_names() if n not in baseline and n != GRADER_NODE and n != "/rosout"}


def forget_nodes(master: PrivateMaster, nodes: Set[str]) -> None:
    """Remove a stopped student node's registrations: a killed node never unregisters itself,
    and the next run may reuse its name."""
    proxy = master._proxy()
    pubs, subs, srvs = master.system_state()
    for node in nodes:
        code, _, uri = proxy.lookupNode(GRADER_NODE, node)
        if code != 1:
            continue
        for topic, names in pubs:
            if node in names:
                proxy.unregisterPublisher(node, topic, uri)
        for topic, names in subs:
            if node in names:
                proxy.unregisterSubscriber(node, topic, uri)
        for service, names in srvs:
            if node in names:
                code, _, service_uri = proxy.lookupService(GRADER_NODE, service)
                if code == 1:
                    proxy.unregisterService(node, service, service_uri)


def node_io(master: PrivateMaster, nodes: Set[str]) -> Tuple[List[Topic], List[Topic]]:
    """(topic, type) the nodes subscribe and publish (rosout left out)."""
    pubs, subs, types = topic_graph(master)
    sub = sorted(Topic(t, types.get(t, "")) for t, n in subs.items() if n & nodes and t not in IGNORED_TOPICS)
    pub = sorted(Topic(t, types.get(t, "")) for t, n in pubs.items() if n & nodes and t not in IGNORED_TOPICS)
    return sub, pub


def node_facts(proc: Any, nodes: Set[str], sub: List[Topic], pub: List[Topic], problem: str,
           exited_by_itself: bool) -> NodeFacts:
    return NodeFacts(started=bool(nodes), nodes=sorted(nodes), subscriptions=sub, publications=pub,
                     exited_by_itself=exited_by_itself, exit_code=proc.returncode, output_tail=proc.output_tail(),
                     output_bytes=proc.output_size(), problem=problem)


# -- the session ---------------------------------------------------------------------------

class Session:
    def __init__(self, context: SessionContext) -> None:
        self._t0 = time.monotonic()
        #: Wall seconds from the session's start to each named phase: where a slow check spends its time.
        self.phases: Dict[str, float] = {}
        self.dir = Path(context.session_dir)
        self.folder = Path(context.student_folder) if context.student_folder else None
        self.limits = context.limits
        self.uid = context.uid
        self.python = context.python
        self.guard = context.guard
        self.env = dict(context.env)
        self.master = PrivateMaster(base_env=self.env, work_dir=self.dir / "ros")
        self.master.start()
        for key in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_LOG_DIR", "ROS_HOME"):
            os.environ[key] = self.master.env[key]
        import rospy  # noqa: PLC0415 - ROS in the session, once its master's environment is set

        rospy.init_node(GRADER_NODE.strip("/"), disable_signals=True, disable_rosout=True)
        self.baseline = set(self.master.node_names())
        self.started: List[Any] = []
        self.phase("master up")

    def phase(self, name: str) -> None:
        self.phases[name] = round(time.monotonic() - self._t0, 3)

    def student_env(self) -> Dict[str, str]:
        env = dict(self.master.env)
        assert self.folder is not None
        ros_home = self.folder / ".ros"
        env.update({"ROS_HOME": str(ros_home), "ROS_LOG_DIR": str(ros_home / "log"), "HOME": str(self.folder),
                    "PYTHONDONTWRITEBYTECODE": "1", "PYTHONUNBUFFERED": "1", "MPLBACKEND": "Agg",
                    "SDL_VIDEODRIVER": "dummy", "SDL_AUDIODRIVER": "dummy"})
        return env

    def start_student(self, argv: List[str], name: str, extra_env: Optional[Dict[str, str]] = None) -> Any:
        assert self.folder is not None
        env = self.student_env()
        extra = dict(extra_env or {})
        if "PYTHONPATH" in extra:  # the extra folders first, the session's after them
            extra["PYTHONPATH"] = os.pathsep.join(p for p in (extra["PYTHONPATH"], env.get("PYTHONPATH", "")) if p)
        proc = StudentProcess(argv, self.folder, dict(env, **extra),
                              self.dir / "logs" / f"{name}.log", self.limits, uid=self.uid, nested=True, guard=self.guard)
        self.started.append(proc)
        return proc

    def stop(self) -> None:
        """Every student process at once (each gets its SIGINT grace), then the grader's helpers and the master."""
        stop_side_by_side(self.started)
        self.master.stop(quick=True)


def start_problem(proc: Any, timeout_s: float, what: str) -> str:
    if not proc.running:
        return f"{describe_exit(proc.returncode)} before {what}"
    count = proc.process_count()
    crowd = (f"; it ran {count} processes and threads at once (the limit is {proc.limits.processes}): do not "
             "fork or start threads in a loop") if count > 40 else ""
    return (f"was still running after {timeout_s:.0f} s without {what} (an endless loop before it, "
            f"or waiting for something that never comes?){crowd}")


def wait_for_node(session: Session, proc: Any, timeout_s: float, want: Callable[[List[Topic], List[Topic]], bool]
                   ) -> Tuple[Set[str], List[Topic], List[Topic], bool]:
    """Wait until the student's node(s) satisfy ``want(subs, pubs)``, it dies, or the time is up."""
    nodes: Set[str] = set()
    sub: List[Topic] = []
    pub: List[Topic] = []

    def ready() -> bool:
        nonlocal nodes, sub, pub
        nodes = student_nodes(session.master, session.baseline)
        if nodes:
            sub, pub = node_io(session.master, nodes)
        return (bool(nodes) and want(sub, pub)) or not proc.running

    ok = wait_for(ready, timeout_s, 0.05) and proc.running
    return nodes, sub, pub, ok


def launch_facts(launch: Any, exited: bool) -> ProcessFacts:
    """roslaunch's end and last output (its ``problem`` is the observation's)."""
    return ProcessFacts(exit_code=launch.returncode, exited_by_itself=exited, output_tail=launch.output_tail(),
                        output_bytes=launch.output_size())


def recorded_since(recorder: Recorder, started: float, topics: Optional[List[str]] = None) -> Dict[str, List[Message]]:
    """The recorder's messages per topic (those of ``topics`` only, if given), stamped in seconds since ``started``."""
    return {t: [Message(round(ts - started, 4), k, v) for ts, k, v in msgs] for t, msgs in recorder.messages.items()
            if topics is None or t in topics}


def pick_topic(topics: List[Topic], wanted: str) -> Tuple[str, str]:
    """(topic, type): ``wanted`` if present, else the only other one, else ('', '')."""
    for topic, kind in topics:
        if topic == wanted:
            return topic, kind
    if len(topics) == 1:
        return topics[0][0], topics[0][1]
    return "", ""
