"""Sessions of single nodes (Ex. 5, 9) and of Ex. 6-7's sensor launch.

Ex. 5's mapping node runs in lockstep, Ex. 9's teleoperation node with a scripted virtual pad, and
Ex. 6-7's sensor launch is recorded on the grader's clock.
"""

from __future__ import annotations

import functools
import threading
import time
from typing import Any, List

from hri_teleop.grading.run.lockstep import (
    GraderClock,
    Recorder,
    connections,
    node_rate_hz,
    wait_for,
    wait_until_settled,
)
from hri_teleop.grading.run.records import (
    MappingNodeObservation,
    MappingNodePlan,
    MappingRun,
    Message,
    Response,
    SensorLaunchObservation,
    SensorLaunchPlan,
    TeleopNodeObservation,
    TeleopNodePlan,
    Topic,
)
from hri_teleop.grading.run.ros_session import (
    IGNORED_TOPICS,
    Session,
    forget_nodes,
    launch_facts,
    node_facts,
    pick_topic,
    recorded_since,
    start_problem,
    student_nodes,
    topic_graph,
    wait_for_node,
)
from hri_teleop.grading.run.sandbox import describe_exit
from hri_teleop.ros.master import stop_side_by_side

__all__ = ["COUNT_TYPES", "count_message", "run_mapping_node", "run_sensor_launch", "run_teleop_node"]


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
        extra.append(session.start_student([session.python, plan.mapping_node], "grader_mapping_node"))
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
        lockstep = [t for t in plan.record if recorder.count(t) > 0] or plan.record[:1]
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
