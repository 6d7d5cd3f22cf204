"""The grader's ROS side: one private master, student processes on it, inputs in, outputs recorded.

Why a separate program: it runs inside the session sandbox (its own network namespace,
see :mod:`hri_teleop.grading.run.sandbox`), so the private master and everything that talks
to it live there, and only a plan goes in and an observation (JSON, and a bag of what was
seen) comes out. It judges nothing: :mod:`hri_teleop.grading.judge.compare` does that, outside.
One plan per process (rospy can join one master per process)::

    python -m hri_teleop.grading.run.session PLAN.json

Kinds of plan: ``mapping-node`` (counts on the student's input topic, lockstep, per
/max_sensor_force), ``sensor-launch`` (roslaunch the student's file, record
/force_mapped), ``teleop-node`` (the student's teleoperation.py with a scripted virtual
pad and a steady /force_mapped), ``teleop-launch-sim`` (the student's teleoperation.launch
with the simulated lab in place of robot and board, and a scripted operator) and
``live-graph`` (the lab's reference pipeline, to read its graph).
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional

from hri_teleop.grading.run.launch_runs import run_live_graph, run_teleop_launch_sim
from hri_teleop.grading.run.node_runs import run_mapping_node, run_sensor_launch, run_teleop_node
from hri_teleop.grading.run.ros_session import Session

__all__ = ["main", "run_plan"]


_KINDS = {"mapping-node": run_mapping_node, "sensor-launch": run_sensor_launch, "teleop-node": run_teleop_node,
          "teleop-launch-sim": run_teleop_launch_sim, "live-graph": run_live_graph}


def run_plan(plan: Dict[str, Any]) -> Dict[str, Any]:
    session = Session(plan)
    try:
        result = _KINDS[plan["kind"]](session)
        session.phase("observed")
    finally:
        session.stop()
    session.phase("stopped")
    return dict(result, phases_s=session.phases)


def main(argv: Optional[List[str]] = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    plan = json.loads(Path(args[0]).read_text(encoding="utf-8"))
    try:
        result = run_plan(plan)
    except Exception as exc:  # noqa: BLE001 - reported to the grader as a session failure
        import traceback

        result = {"kind": plan.get("kind"), "session_error": f"{type(exc).__name__}: {exc}",
                  "traceback": traceback.format_exc()[-3000:]}
    Path(plan["out"]).write_text(json.dumps(result), encoding="utf-8")
    os._exit(0)  # rospy's threads would otherwise keep the process alive


if __name__ == "__main__":
    sys.exit(main())
