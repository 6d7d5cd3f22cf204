"""Ex. 6-7's session: the student's sensor.launch run by roslaunch, /force_mapped recorded on the grader's clock.

Runs inside the session sandbox (``python -m hri_teleop.grading.session``): no judging here.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, ClassVar, Dict, List, Tuple, Type

from hri_teleop.grading.run.lockstep import (
    GraderClock,
    Recorder,
    connections,
    node_rate_hz,
    wait_for,
    wait_until_settled,
)
from hri_teleop.grading.run.records import (
    LaunchObservation,
    LaunchPlan,
    Message,
    SessionPlan,
)
from hri_teleop.grading.run.ros_session import (
    IGNORED_TOPICS,
    Session,
    launch_facts,
    start_problem,
    student_nodes,
    topic_graph,
)
from hri_teleop.grading.run.sandbox import describe_exit
from hri_teleop.ros.master import stop_side_by_side

__all__ = ["SensorLaunchObservation", "SensorLaunchPlan", "run_sensor_launch", "SESSIONS"]


@dataclass(frozen=True)
class SensorLaunchObservation(LaunchObservation):
    KIND: ClassVar[str] = "sensor-launch"

    force_mapped: List[Message] = field(default_factory=list)
    pub_force: List[Message] = field(default_factory=list)


@dataclass(frozen=True)
class SensorLaunchPlan(LaunchPlan[SensorLaunchObservation]):
    KIND: ClassVar[str] = "sensor-launch"

    run_fsr_sensor: bool
    fsr_sensor: str
    run_mapping_node: bool
    mapping_script: str
    record_s: float
    record_messages: int
    fsr_node: str
    default_fsr_rate_hz: float
    mapping_node_name: str

    def observation_type(self) -> Type[SensorLaunchObservation]:
        return SensorLaunchObservation


def _record_sensor_on_clock(session: Session, plan: SensorLaunchPlan, clock: GraderClock, recorder: Recorder,
                            launch: Any, want: int) -> None:
    """Step the clock one sensor period at a time until ``want`` values came out of /force_mapped.

    Each step waits for the tick's count on /pub_force and its mapping on /force_mapped
    (once each has spoken), so every count is paired with its own mapping, idle or busy.
    """
    wait_until_settled(session, set(plan.expect_nodes), launch, plan.settle_timeout_s)
    wait_for(lambda: (recorder.connected("/pub_force") and recorder.connected("/force_mapped")
                   and connections(session, plan.mapping_node_name, "/pub_force") > 0
                   and connections(session, plan.fsr_node, "/pub_force", "o") >= 2
                   and connections(session, plan.mapping_node_name, "/force_mapped", "o") >= 1)
          or not launch.running, 5.0, 0.002)
    rate_hz = node_rate_hz(session, plan.fsr_node, plan.default_fsr_rate_hz, "rate_hz")
    clock.start()  # the sensor's first count, with everything connected: the same in every run
    wait_for(lambda: (recorder.count("/pub_force") > 0 and recorder.count("/force_mapped") > 0) or not launch.running,
          GraderClock.STEP_TIMEOUT_S, 0.0005)
    for _ in range(int(plan.record_s * rate_hz)):
        if (want and recorder.count("/force_mapped") >= want) or not launch.running:
            break
        lockstep = [t for t in ("/pub_force", "/force_mapped") if recorder.count(t)] or ["/pub_force"]
        if not clock.step(rate_hz, recorder, lockstep, launch) and not clock.paced and launch.running:
            clock.paced = True


def run_sensor_launch(session: Session, plan: SensorLaunchPlan) -> SensorLaunchObservation:
    """roslaunch the student's sensor.launch; supply what it lacks so the flow can still be judged."""
    supplied: List[str] = []
    # Before anything reads /use_sim_time; time starts once every node is up and connected.
    clock = GraderClock(session, started=False) if plan.clock == "grader" else None
    if plan.set_max_sensor_force is not None:
        session.master.set_param("/max_sensor_force", plan.set_max_sensor_force)
        supplied.append("/max_sensor_force")
    extra: List[Any] = []
    launch = session.start_student(["roslaunch", "--wait", plan.launch_file], "roslaunch",
                                   clock.student_env(session.folder) if clock else None)
    if plan.run_fsr_sensor:
        extra.append(session.master.run([session.python, plan.fsr_sensor], "grader_FSR_sensor"))
        supplied.append("FSR_sensor.py")
    if plan.run_mapping_node:
        extra.append(session.start_student([session.python, plan.mapping_script], "grader_mapping_node"))
        supplied.append("mapping_node.py")
    recorder = Recorder(clock.now if clock else time.monotonic)
    ok = wait_for(lambda: bool(session.master.publishers("/force_mapped")) or not launch.running,
               plan.start_timeout_s, 0.05) and launch.running
    problem = "" if ok else start_problem(launch, plan.start_timeout_s, "anything publishing /force_mapped")
    if ok:
        recorder.add("/force_mapped")
        recorder.add("/pub_force")
        wait_for(lambda: recorder.connected("/force_mapped"), 5.0)
        want = plan.record_messages
        if clock is not None:
            _record_sensor_on_clock(session, plan, clock, recorder, launch, want)
        else:
            wait_for(lambda: recorder.count("/force_mapped") > 0 or not launch.running, plan.start_timeout_s)
            # Enough messages to judge, not a fixed time: a busy machine records the same number.
            wait_for(lambda: bool(want and recorder.count("/force_mapped") >= want) or not launch.running,
                  plan.record_s, 0.01)
    nodes = sorted(student_nodes(session.master, session.baseline))
    pubs, subs, types = topic_graph(session.master)
    recorder.close()
    exited = not launch.running
    if ok and exited:
        problem = f"roslaunch {describe_exit(launch.returncode)} while /force_mapped was recorded"

    stop_side_by_side([launch, *extra], kill=not problem)  # a clean run's record is complete: no grace needed
    return SensorLaunchObservation(
        supplied=supplied, problem=problem, nodes=nodes,
        clock="grader" if clock is not None and not clock.paced else "real time",
        types={t: k for t, k in types.items() if t not in IGNORED_TOPICS},
        force_mapped=[Message(t, k, v) for t, k, v in recorder.messages.get("/force_mapped", [])],
        pub_force=[Message(t, k, v) for t, k, v in recorder.messages.get("/pub_force", [])],
        launch=launch_facts(launch, exited))


#: The plans this exercise's sessions run: kind -> (plan type, what runs it).
SESSIONS: Dict[str, Tuple[Type[SessionPlan[Any]], Any]] = {SensorLaunchPlan.KIND: (SensorLaunchPlan, run_sensor_launch)}
