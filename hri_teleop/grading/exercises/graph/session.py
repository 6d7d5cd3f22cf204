"""Ex. 15's session: the lab's reference pipeline run on a private master, who publishes and subscribes what.

Runs inside the session sandbox (``python -m hri_teleop.grading.session``): no judging here.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, ClassVar, Dict, List, Tuple, Type

from hri_teleop.grading.run.launch_runs import topic_connections
from hri_teleop.grading.run.lockstep import wait_for
from hri_teleop.grading.run.records import Observation, SessionPlan
from hri_teleop.grading.run.ros_session import (
    Session,
    topic_graph,
)

__all__ = ["LiveGraphObservation", "LiveGraphPlan", "run_live_graph", "SESSIONS"]


@dataclass(frozen=True)
class LiveGraphObservation(Observation):
    """The lab's reference pipeline: who publishes and subscribes each topic, and its type."""

    KIND: ClassVar[str] = "live-graph"

    problem: str = ""
    publishers: Dict[str, List[str]] = field(default_factory=dict)
    subscribers: Dict[str, List[str]] = field(default_factory=dict)
    types: Dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class LiveGraphPlan(SessionPlan[LiveGraphObservation]):
    KIND: ClassVar[str] = "live-graph"

    launch_args: List[str]
    nodes: List[str]

    def observation_type(self) -> Type[LiveGraphObservation]:
        return LiveGraphObservation


def run_live_graph(session: Session, plan: LiveGraphPlan) -> LiveGraphObservation:
    """The lab's reference pipeline without hardware: its nodes, topics, types and connections."""
    launch = session.master.run(["roslaunch", "--wait", "hri_lab", "teleoperation.launch", *plan.launch_args],
                                "reference")
    want = set(plan.nodes)
    ok = wait_for(lambda: want <= set(session.master.node_names()) or not launch.running, plan.start_timeout_s, 0.1)
    if not ok or not launch.running:
        out = launch.output()[-1500:]
        launch.stop()
        return LiveGraphObservation(problem=f"the reference teleoperation.launch did not start: {out}")
    previous: Any = None
    for _ in range(50):  # until two readings 0.3 s apart agree
        pubs, subs, types = topic_graph(session.master)
        reading = (sorted((t, sorted(n)) for t, n in pubs.items()), sorted((t, sorted(n)) for t, n in subs.items()))
        if reading == previous:
            break
        previous = reading
        time.sleep(0.3)
    launch.stop()
    publishers, subscribers = topic_connections(pubs, subs)
    return LiveGraphObservation(problem="", publishers=publishers, subscribers=subscribers, types=types)


#: The plans this exercise's sessions run: kind -> (plan type, what runs it).
SESSIONS: Dict[str, Tuple[Type[SessionPlan[Any]], Any]] = {LiveGraphPlan.KIND: (LiveGraphPlan, run_live_graph)}
