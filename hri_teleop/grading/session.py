"""The grader's ROS side: one private master, student processes on it, inputs in, outputs recorded.

A program of its own that runs inside the session sandbox, so the master and everything that talks
to it live there: a plan goes in, an observation (JSON, and a bag) comes out, and nothing is judged
here. One plan per process, since rospy joins one master per process; the kinds of plan:
docs/grading-internals.md.

    python -m hri_teleop.grading.session PLAN.json
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import json
import os
import sys
import traceback
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple, Type

from hri_teleop.grading.deliverables import DELIVERABLE_FILES
from hri_teleop.grading.run.launch_runs import run_teleop_launch_sim
from hri_teleop.grading.run.records import (
    Observation,
    SessionContext,
    SessionPlan,
    SessionRequest,
    TeleopLaunchSimPlan,
)
from hri_teleop.grading.run.ros_session import Session

__all__ = ["main", "run_plan", "session_kinds"]

Runner = Callable[[Session, Any], Observation]


def session_kinds() -> Dict[str, Tuple[Type[SessionPlan[Any]], Runner]]:
    """kind -> (plan type, what runs it): the shared simulated lab's, and each exercise's ``session`` module's
    ``SESSIONS`` (an exercise folder without one runs no session)."""
    kinds: Dict[str, Tuple[Type[SessionPlan[Any]], Runner]] = {
        TeleopLaunchSimPlan.KIND: (TeleopLaunchSimPlan, run_teleop_launch_sim)}
    for key in DELIVERABLE_FILES:
        name = f"hri_teleop.grading.exercises.{key}.session"
        spec = importlib.util.find_spec(f"hri_teleop.grading.exercises.{key}")
        if spec is None or spec.submodule_search_locations is None:
            continue  # a one-module exercise
        if importlib.util.find_spec(name) is not None:
            kinds.update(getattr(importlib.import_module(name), "SESSIONS", {}))
    return kinds


def _observe(session: Session, plan: SessionPlan[Any]) -> Observation:
    found = session_kinds().get(plan.KIND)
    if found is None or not isinstance(plan, found[0]):
        raise TypeError(f"no session runs a {type(plan).__name__}")
    return found[1](session, plan)


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
    request = SessionRequest.from_json(json.loads(Path(args[0]).read_text(encoding="utf-8")),
                                      {kind: found[0] for kind, found in session_kinds().items()})
    try:
        result = run_plan(request.context, request.plan)
    except Exception as exc:  # noqa: BLE001 - reported to the grader as a session failure
        result = request.plan.observation_type()(session_error=f"{type(exc).__name__}: {exc}",
                                                 traceback=traceback.format_exc()[-3000:])
    Path(request.context.out).write_text(json.dumps(result.to_json()), encoding="utf-8")
    os._exit(0)  # rospy's threads would otherwise keep the process alive


if __name__ == "__main__":
    sys.exit(main())
