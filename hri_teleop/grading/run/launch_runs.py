"""Sessions of whole pipelines: Ex. 12-13's launch in the simulated lab, and Ex. 15's reference graph.

Ex. 12-13's teleoperation launch runs with the simulated lab and a scripted operator; the lab's
reference pipeline gives the graph Ex. 15 is judged against.
"""

from __future__ import annotations

import time
from typing import Any, Dict, List, Optional, Sequence, Set, Tuple

from hri_teleop.grading.run.lockstep import (
    GraderClock,
    Quiescence,
    Recorder,
    connections,
    last_value,
    node_rate_hz,
    wait_for,
    wait_until_settled,
)
from hri_teleop.grading.run.records import (
    TeleopLaunchSimObservation,
    TeleopLaunchSimPlan,
    Topic,
)
from hri_teleop.grading.run.ros_session import (
    IGNORED_TOPICS,
    Session,
    launch_facts,
    node_io,
    recorded_since,
    start_problem,
    student_nodes,
    topic_graph,
)
from hri_teleop.ros.master import stop_side_by_side

__all__ = ["run_teleop_launch_sim", "CHAIN_SETTLE_S"]


CHAIN_SETTLE_S = 0.5


def run_teleop_launch_sim(session: Session, plan: TeleopLaunchSimPlan) -> TeleopLaunchSimObservation:
    """roslaunch the student's teleoperation.launch with the simulated lab and a scripted operator.

    lab_sim (the grader's, trusted) plays arm, hand, object and board before the launch
    starts, so the operator's script meets a ready lab; its board counts go to the
    stand-in serial_node the student's file starts (:mod:`hri_teleop.grading.run.standins`).
    The grader's parameter file (second on roslaunch's command line, so it survives
    ``clear_params``) gives the teleoperation node the virtual pad and the script. What the
    launch file lacks (a parameter, the serial_node, mapping_node, gripper_manager) the
    grader supplies, so this judges only whether what it starts works together.
    """
    supplied: List[str] = []
    if plan.set_max_sensor_force is not None:
        session.master.set_param("/max_sensor_force", plan.set_max_sensor_force)
        supplied.append("/max_sensor_force")
    # Before anything reads /use_sim_time; time starts once every node is up and connected.
    clock = GraderClock(session, started=False) if plan.clock == "grader" else None
    now = clock.now if clock else time.monotonic
    recorder: Optional[Recorder] = None
    launch: Any = None

    def start_launch() -> Tuple[Recorder, Any]:
        rec = Recorder(now)  # before the launch: nothing it publishes is missed
        for topic in plan.record:
            rec.add(topic)
        return rec, session.start_student(["roslaunch", "--wait", plan.launch_file, plan.params_launch],
                                          "roslaunch", clock.student_env(session.folder) if clock else None)

    lab = session.master.run([session.python, *plan.lab_sim], "grader_lab_sim")
    # On the grader's clock time stands still until everything is connected, so the launch starts
    # beside lab_sim (1 s sooner); in real time the operator's script must meet a ready lab.
    if clock is not None:
        recorder, launch = start_launch()
    ready = wait_for(lambda: "/lab_sim" in session.master.subscribers(plan.twist_topic) or not lab.running,
                  plan.start_timeout_s, 0.05)
    session.phase("lab_sim up")
    if not ready or not lab.running:
        out = lab.output()[-1500:]
        if recorder is not None:
            recorder.close()
        stop_side_by_side([p for p in (lab, launch) if p is not None])
        return TeleopLaunchSimObservation(session_error=f"the simulated lab did not start: {out}")
    if recorder is None:
        recorder, launch = start_launch()
    teleop = plan.teleop_node
    started = now()
    up = wait_for(lambda: teleop in session.master.node_names() or not launch.running, plan.start_timeout_s, 0.05)
    session.phase("teleoperation node registered")
    problem = "" if up and launch.running else start_problem(launch, plan.start_timeout_s, f"starting {teleop}")
    extra: List[Any] = []
    nodes: Set[str] = set()
    teleop_pub: List[Topic] = []
    quit_in_time = False
    if not problem:
        for name, argv in plan.supply.items():  # now: the launch file's parameters are set
            extra.append(session.start_student([session.python, *argv], f"grader_{name}"))
            supplied.append(name)
        def still_up() -> bool:
            nonlocal nodes, teleop_pub, quit_in_time
            current = student_nodes(session.master, session.baseline)
            nodes |= current - {"/lab_sim"}
            if teleop not in current or not launch.running:
                quit_in_time = teleop not in current
                return False
            teleop_pub = node_io(session.master, {teleop})[1] or teleop_pub
            return True

        if clock is not None:
            # Time stands still until every node is up and connected: at the simulation's
            # speed a node still importing would otherwise miss seconds of the operator.
            wait_until_settled(session, set(plan.expect_nodes), launch, plan.settle_timeout_s)
            session.phase("graph settled")
            # Step once the node's twists reach the recorder and lab_sim: a tick published before
            # a connection is lost (to lab_sim: a velocity out of the blue, which the arm refuses).
            twist, applied = plan.twist_topic, plan.applied_topic
            recorder.add(applied)
            # Both ends counted: the node starts its pad script at the first tick with a listener.
            wait_for(lambda: (recorder.connected(twist) and recorder.connected(applied)
                           and connections(session, "/lab_sim", twist) > 0
                           and connections(session, teleop, twist, "o") >= 2)
                  or not launch.running, plan.start_timeout_s, 0.002)
            rate_hz = node_rate_hz(session, teleop, plan.default_rate_hz)
            chain = list(plan.sensor_chain)  # board -> /pub_force -> /force_mapped
            for topic in chain:
                recorder.add(topic)
            chain_ok = [bool(chain)]

            def chain_settled() -> bool:
                """Every board count of this tick came out of the chain's last topic (one message
                per count at each link): the node's next tick sees this tick's force in every run."""
                counts = [recorder.count(t) for t in chain]
                return all(c >= counts[0] for c in counts[1:])

            # Each step waits for the tick's twist and for lab_sim's word that it applied it at
            # this tick's time: the next step must not reach lab_sim before this command.
            # Then until every process has done this tick's work: a gripper goal on its way to
            # lab_sim or a force to the node's callback would otherwise land a tick late now and then.
            quiet = Quiescence([p.popen.pid for p in (launch, lab, *extra)])

            def applied_now() -> bool:
                if last_value(recorder, applied, 0.0) < clock.now() - 1e-6:
                    return False
                if chain_ok[0] and not wait_for(chain_settled, CHAIN_SETTLE_S, 0.0002):
                    chain_ok[0] = False  # a link that drops or merges messages: stop waiting for it
                quiet.wait()
                return True

            session.phase("connected")
            clock.start()  # tick 0, with everything connected: the same first tick in every run
            wait_for(lambda: (recorder.count(twist) > 0 and applied_now()) or not launch.running,
                  GraderClock.STEP_TIMEOUT_S, 0.0005)
            tick = 0
            while clock.now() - started < plan.run_s:
                if tick % 10 == 0:
                    if not still_up():
                        break
                    quiet.refresh()
                tick += 1
                if not clock.step(rate_hz, recorder, [twist], launch, applied_now) and not clock.paced:
                    if not still_up():
                        break
                    clock.paced = True
            session.phase("steps done")
        else:
            deadline = time.monotonic() + plan.run_s
            while time.monotonic() < deadline and still_up():
                time.sleep(0.1)
    pubs, subs, types = topic_graph(session.master)
    recorder.close()
    exited = not launch.running

    # Everything judged is recorded: a run that started cleanly ends at once (its nodes' clean
    # shutdown took 0.7 s); one with a start problem gets its grace, for the output it explains.
    stop_side_by_side([launch, *extra, lab], kill=not problem)
    publishers, subscribers = topic_connections(pubs, subs, IGNORED_TOPICS)
    return TeleopLaunchSimObservation(
        supplied=supplied, problem=problem, nodes=sorted(nodes), quit_in_time=quit_in_time,
        run_s=round(now() - started, 3), teleop_publications=teleop_pub,
        clock="grader" if clock is not None and not clock.paced else "real time",
        publishers=publishers, subscribers=subscribers,
        types={t: k for t, k in types.items() if t not in IGNORED_TOPICS},
        messages=recorded_since(recorder, started, plan.record), launch=launch_facts(launch, exited),
        lab_sim_log=lab.output()[-1500:])


def topic_connections(pubs: Dict[str, Set[str]], subs: Dict[str, Set[str]], ignored: Sequence[str] = ()
                 ) -> Tuple[Dict[str, List[str]], Dict[str, List[str]]]:
    """(topic -> sorted publishers, topic -> sorted subscribers), the ``ignored`` topics left out."""
    return ({t: sorted(n) for t, n in pubs.items() if t not in ignored},
            {t: sorted(n) for t, n in subs.items() if t not in ignored})
