"""The grader's ROS side: one private master, student processes on it, inputs in, outputs recorded.

A program of its own that runs inside the session sandbox, so the master and everything that talks
to it live there: a plan goes in, an observation (JSON, and a bag) comes out, and nothing is judged
here. One plan per process, since rospy joins one master per process; the kinds of plan:
docs/grading-internals.md.

    python -m hri_teleop.grading.run.session PLAN.json
"""

from __future__ import annotations

import dataclasses
import json
import os
import sys
import traceback
from pathlib import Path
from typing import Any, List, Optional

from hri_teleop.grading.run.launch_runs import run_live_graph, run_teleop_launch_sim
from hri_teleop.grading.run.node_runs import run_mapping_node, run_sensor_launch, run_teleop_node
from hri_teleop.grading.run.records import (
    LiveGraphPlan,
    MappingNodePlan,
    Observation,
    SensorLaunchPlan,
    SessionContext,
    SessionPlan,
    SessionRequest,
    TeleopLaunchSimPlan,
    TeleopNodePlan,
)
from hri_teleop.grading.run.ros_session import Session

__all__ = ["main", "run_plan"]


def _observe(session: Session, plan: SessionPlan[Any]) -> Observation:
    if isinstance(plan, MappingNodePlan):
        return run_mapping_node(session, plan)
    if isinstance(plan, SensorLaunchPlan):
        return run_sensor_launch(session, plan)
    if isinstance(plan, TeleopNodePlan):
        return run_teleop_node(session, plan)
    if isinstance(plan, TeleopLaunchSimPlan):
        return run_teleop_launch_sim(session, plan)
    if isinstance(plan, LiveGraphPlan):
        return run_live_graph(session, plan)
    raise TypeError(f"no session runs a {type(plan).__name__}")


def run_plan(context: SessionContext, plan: SessionPlan[Any]) -> Observation:
    session = Session(context)
    try:
        result = _observe(session, plan)
        session.phase("observed")
    finally:
        session.stop()
    session.phase("stopped")
    return dataclasses.replace(result, phases_s=session.phases)


def main(argv: Optional[List[str]] = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    request = SessionRequest.from_json(json.loads(Path(args[0]).read_text(encoding="utf-8")))
    try:
        result = run_plan(request.context, request.plan)
    except Exception as exc:  # noqa: BLE001 - reported to the grader as a session failure
        result = request.plan.observation_type()(session_error=f"{type(exc).__name__}: {exc}",
                                                 traceback=traceback.format_exc()[-3000:])
    Path(request.context.out).write_text(json.dumps(result.to_json()), encoding="utf-8")
    os._exit(0)  # rospy's threads would otherwise keep the process alive


if __name__ == "__main__":
    sys.exit(main())
