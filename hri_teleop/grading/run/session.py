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
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Set, Tuple

from hri_teleop.grading.run.lockstep import (
    GRADER_NODE,
    GraderClock,
    Quiescence,
    Recorder,
    connections,
    last_value,
    node_rate_hz,
    wait_for,
    wait_until_settled,
)

__all__ = ["main", "run_plan"]

_IGNORED_TOPICS = ("/rosout", "/rosout_agg")


# -- what a student's node did ------------------------------------------------------------

def _graph(master: Any) -> Tuple[Dict[str, Set[str]], Dict[str, Set[str]], Dict[str, str]]:
    """(topic -> publisher nodes, topic -> subscriber nodes, topic -> type) from the master."""
    pubs, subs, _ = master.system_state()
    types = master.topic_types()
    return ({t: set(n) for t, n in pubs}, {t: set(n) for t, n in subs}, types)


def _student_nodes(master: Any, baseline: Set[str]) -> Set[str]:
    return {n for n in master.node_names() if n not in baseline and n != GRADER_NODE and n != "/rosout"}


def _forget_nodes(master: Any, nodes: Set[str]) -> None:
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


def _node_io(master: Any, nodes: Set[str]) -> Tuple[List[List[str]], List[List[str]]]:
    """[[topic, type], ...] the nodes subscribe and publish (rosout left out)."""
    pubs, subs, types = _graph(master)
    sub = sorted([t, types.get(t, "")] for t, n in subs.items() if n & nodes and t not in _IGNORED_TOPICS)
    pub = sorted([t, types.get(t, "")] for t, n in pubs.items() if n & nodes and t not in _IGNORED_TOPICS)
    return sub, pub


def _facts(proc: Any, nodes: Set[str], sub: List[List[str]], pub: List[List[str]], problem: str,
           exited_by_itself: bool) -> Dict[str, Any]:
    return {
        "started": bool(nodes), "nodes": sorted(nodes), "subscriptions": sub, "publications": pub,
        "exited_by_itself": exited_by_itself, "exit_code": proc.returncode, "output_tail": proc.output_tail(),
        "output_bytes": proc.output_size(), "problem": problem,
    }


# -- the session ---------------------------------------------------------------------------

class Session:
    def __init__(self, plan: Dict[str, Any]) -> None:
        from hri_teleop.grading.run.sandbox import Limits
        from hri_teleop.ros.master import PrivateMaster

        self.plan = plan
        self._t0 = time.monotonic()
        #: Wall seconds from the session's start to each named phase: where a slow check spends its time.
        self.phases: Dict[str, float] = {}
        self.dir = Path(plan["session_dir"])
        self.folder = Path(plan["student_folder"]) if plan.get("student_folder") else None
        self.limits = Limits(**plan.get("limits", {}))
        self.uid = plan.get("uid")
        self.env = dict(plan["env"])
        self.master = PrivateMaster(base_env=self.env, work_dir=self.dir / "ros")
        self.master.start()
        for key in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_LOG_DIR", "ROS_HOME"):
            os.environ[key] = self.master.env[key]
        import rospy

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
        from hri_teleop.grading.run.sandbox import StudentProcess

        assert self.folder is not None
        proc = StudentProcess(argv, self.folder, dict(self.student_env(), **(extra_env or {})),
                              self.dir / "logs" / f"{name}.log", self.limits, uid=self.uid, nested=True)
        self.started.append(proc)
        return proc

    def stop(self) -> None:
        """Every student process at once (each gets its SIGINT grace), then the grader's helpers and the master."""
        from hri_teleop.ros.master import stop_side_by_side

        stop_side_by_side(self.started)
        self.master.stop(quick=True)


def _start_problem(proc: Any, timeout_s: float, what: str) -> str:
    from hri_teleop.grading.run.sandbox import describe_exit

    if not proc.running:
        return f"{describe_exit(proc.returncode)} before {what}"
    count = proc.process_count()
    crowd = (f"; it ran {count} processes and threads at once (the limit is {proc.limits.processes}): do not "
             "fork or start threads in a loop") if count > 40 else ""
    return (f"was still running after {timeout_s:.0f} s without {what} (an endless loop before it, "
            f"or waiting for something that never comes?){crowd}")


def _wait_for_node(session: Session, proc: Any, timeout_s: float, want: Callable[[List, List], bool]
                   ) -> Tuple[Set[str], List, List, bool]:
    """Wait until the student's node(s) satisfy ``want(subs, pubs)``, it dies, or the time is up."""
    state: Dict[str, Any] = {"nodes": set(), "sub": [], "pub": []}

    def ready() -> bool:
        state["nodes"] = _student_nodes(session.master, session.baseline)
        if state["nodes"]:
            state["sub"], state["pub"] = _node_io(session.master, state["nodes"])
        return (bool(state["nodes"]) and want(state["sub"], state["pub"])) or not proc.running

    ok = wait_for(ready, timeout_s, 0.05) and proc.running
    return state["nodes"], state["sub"], state["pub"], ok


def _pick(topics: List[List[str]], wanted: str) -> Tuple[str, str]:
    """(topic, type): ``wanted`` if present, else the only other one, else ('', '')."""
    for topic, kind in topics:
        if topic == wanted:
            return topic, kind
    if len(topics) == 1:
        return topics[0][0], topics[0][1]
    return "", ""


def run_mapping_node(session: Session) -> Dict[str, Any]:
    import rospy
    from std_msgs.msg import Int16

    plan = session.plan
    runs = []
    python = plan["python"]
    for index, case in enumerate(plan["cases"]):
        if index > 0 and not any(runs[0]["responses"]):
            break  # nothing came back for the public counts: the hidden ones cannot tell more
        session.master.set_param("/max_sensor_force", case["max_sensor_force"])
        proc = session.start_student([python, plan["script"]], f"mapping_node-{index}")
        nodes, sub, pub, ok = _wait_for_node(session, proc, plan["start_timeout_s"], lambda s, p: bool(s))
        if ok and not pub:  # subscribed; give it a moment to advertise too
            nodes, sub, pub, _ = _wait_for_node(session, proc, 2.0, lambda s, p: bool(p))
        run: Dict[str, Any] = {"label": case["label"], "max_sensor_force": case["max_sensor_force"],
                               "counts": case["counts"], "responses": [], "input_topic": "", "output_topic": "",
                               "output_type": "", "connected": False}
        problem = "" if ok else _start_problem(proc, plan["start_timeout_s"], "subscribing to a topic")
        if ok:
            in_topic, in_type = _pick(sub, "/pub_force")
            out_topic, out_type = _pick(pub, "/force_mapped")
            run.update(input_topic=in_topic, input_type=in_type, output_topic=out_topic, output_type=out_type)
            if in_topic:
                publisher = rospy.Publisher(in_topic, Int16, queue_size=1000, tcp_nodelay=True)
                recorder = Recorder()
                if out_topic:
                    recorder.add(out_topic)
                connected = wait_for(lambda publisher=publisher, recorder=recorder, out_topic=out_topic:
                                     publisher.get_num_connections() > 0
                                     and (not out_topic or recorder.connected(out_topic)), 5.0)
                run["connected"] = connected
                if connected:
                    run["responses"] = _lockstep(publisher, recorder, out_topic, case["counts"], proc,
                                                 plan["response_timeout_s"])
                recorder.close()
                publisher.unregister()
            nodes2, sub2, pub2, _ = _wait_for_node(session, proc, 0.0, lambda s, p: True)
            if nodes2:
                nodes, sub, pub = nodes2, sub2, pub2
        exited = not proc.running
        if exited and not problem:
            from hri_teleop.grading.run.sandbox import describe_exit

            problem = f"{describe_exit(proc.returncode)} while counts were being published"
        proc.stop()
        run["node"] = _facts(proc, nodes, sub, pub, problem, exited)
        runs.append(run)
        _forget_nodes(session.master, _student_nodes(session.master, session.baseline))
    return {"kind": "mapping-node", "runs": runs}


def _lockstep(publisher: Any, recorder: Recorder, out_topic: str, counts: List[int], proc: Any,
              timeout_s: float) -> List[List[Any]]:
    """Publish one count, collect what comes back before the next one; returns values per count."""
    from std_msgs.msg import Int16

    responses: List[List[Any]] = []
    misses = 0  # counts that got no answer in time: after three, wait only briefly (a node that
    # never answers, or skips some counts, must not cost a second per count)
    for i, count in enumerate(counts):
        before = recorder.count(out_topic) if out_topic else 0
        recorder.event.clear()
        publisher.publish(Int16(data=int(count)))
        wait_s = (max(2.0, timeout_s) if i == 0 else timeout_s) if misses < 3 else 0.05
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline and (not out_topic or recorder.count(out_topic) == before):
            recorder.event.wait(0.005)
        if out_topic and recorder.count(out_topic) > before:
            time.sleep(0.002)  # a second message for the same count would arrive now
        else:
            misses += 1
        got = recorder.since(out_topic, before) if out_topic else []
        responses.append([[kind, value] for _, kind, value in got])
        if not proc.running:
            responses.extend([] for _ in counts[i + 1:])
            break
    return responses


def _record_sensor_on_clock(session: Session, clock: "GraderClock", recorder: Recorder, launch: Any,
                            want: int) -> None:
    """Step the clock one sensor period at a time until ``want`` values came out of /force_mapped.

    Each step waits for the tick's count on /pub_force and its mapping on /force_mapped
    (once each has spoken), so every count is paired with its own mapping, idle or busy.
    """
    plan = session.plan
    wait_until_settled(session, set(plan.get("expect_nodes", [])), launch, plan["settle_timeout_s"])
    wait_for(lambda: (recorder.connected("/pub_force") and recorder.connected("/force_mapped")
                   and connections(session, plan["mapping_node_name"], "/pub_force") > 0
                   and connections(session, plan["fsr_node"], "/pub_force", "o") >= 2
                   and connections(session, plan["mapping_node_name"], "/force_mapped", "o") >= 1)
          or not launch.running, 5.0, 0.002)
    rate_hz = node_rate_hz(session, plan["fsr_node"], plan["default_fsr_rate_hz"], "rate_hz")
    clock.start()  # the sensor's first count, with everything connected: the same in every run
    wait_for(lambda: (recorder.count("/pub_force") > 0 and recorder.count("/force_mapped") > 0) or not launch.running,
          GraderClock.STEP_TIMEOUT_S, 0.0005)
    for _ in range(int(plan["record_s"] * rate_hz)):
        if (want and recorder.count("/force_mapped") >= want) or not launch.running:
            break
        lockstep = [t for t in ("/pub_force", "/force_mapped") if recorder.count(t)] or ["/pub_force"]
        if not clock.step(rate_hz, recorder, lockstep, launch) and not clock.paced and launch.running:
            clock.paced = True


def run_sensor_launch(session: Session) -> Dict[str, Any]:
    """roslaunch the student's sensor.launch; supply what it lacks so the flow can still be judged."""
    plan = session.plan
    supplied: List[str] = []
    # Before anything reads /use_sim_time; time starts once every node is up and connected.
    clock = GraderClock(session, started=False) if plan.get("clock") == "grader" else None
    if plan.get("set_max_sensor_force") is not None:
        session.master.set_param("/max_sensor_force", plan["set_max_sensor_force"])
        supplied.append("/max_sensor_force")
    extra: List[Any] = []
    launch = session.start_student(["roslaunch", "--wait", plan["launch_file"]], "roslaunch",
                                   clock.student_env() if clock else None)
    if plan.get("run_fsr_sensor"):
        extra.append(session.master.run([plan["python"], plan["fsr_sensor"]], "grader_FSR_sensor"))
        supplied.append("FSR_sensor.py")
    if plan.get("run_mapping_node"):
        extra.append(session.start_student([plan["python"], plan["mapping_node"]], "grader_mapping_node"))
        supplied.append("mapping_node.py")
    recorder = Recorder(clock.now if clock else time.monotonic)
    ok = wait_for(lambda: bool(session.master.publishers("/force_mapped")) or not launch.running,
               plan["start_timeout_s"], 0.05) and launch.running
    problem = "" if ok else _start_problem(launch, plan["start_timeout_s"], "anything publishing /force_mapped")
    if ok:
        recorder.add("/force_mapped")
        recorder.add("/pub_force")
        wait_for(lambda: recorder.connected("/force_mapped"), 5.0)
        want = plan.get("record_messages", 0)
        if clock is not None:
            _record_sensor_on_clock(session, clock, recorder, launch, want)
        else:
            wait_for(lambda: recorder.count("/force_mapped") > 0 or not launch.running, plan["start_timeout_s"])
            # Enough messages to judge, not a fixed time: a busy machine records the same number.
            wait_for(lambda: (want and recorder.count("/force_mapped") >= want) or not launch.running,
                  plan["record_s"], 0.01)
    nodes = sorted(_student_nodes(session.master, session.baseline))
    pubs, subs, types = _graph(session.master)
    recorder.close()
    exited = not launch.running
    if ok and exited:
        from hri_teleop.grading.run.sandbox import describe_exit

        problem = f"roslaunch {describe_exit(launch.returncode)} while /force_mapped was recorded"
    from hri_teleop.ros.master import stop_side_by_side

    stop_side_by_side([launch, *extra])
    return {
        "kind": "sensor-launch", "supplied": supplied, "problem": problem, "nodes": nodes,
        "clock": "grader" if clock is not None and not clock.paced else "real time",
        "types": {t: k for t, k in types.items() if t not in _IGNORED_TOPICS},
        "force_mapped": [[t, k, v] for t, k, v in recorder.messages.get("/force_mapped", [])],
        "pub_force": [[t, k, v] for t, k, v in recorder.messages.get("/pub_force", [])],
        "launch": {"exit_code": launch.returncode, "exited_by_itself": exited, "output_tail": launch.output_tail(),
                   "output_bytes": launch.output_size()},
    }


def run_teleop_node(session: Session) -> Dict[str, Any]:
    """The student's teleoperation.py with a scripted virtual pad and a steady /force_mapped."""
    import rospy
    from std_msgs.msg import Float32

    plan = session.plan
    force_pub = rospy.Publisher("/force_mapped", Float32, queue_size=10)
    stop_force = threading.Event()

    def feed_force() -> None:
        while not stop_force.is_set():
            force_pub.publish(Float32(data=plan["force"]))
            stop_force.wait(0.05)

    feeder = threading.Thread(target=feed_force, daemon=True)
    feeder.start()
    params = [f"_{k}:={v}" for k, v in plan["gains"].items()]
    argv = [plan["python"], plan["script"], "_pad:=virtual", "_layout:=dualshock4",
            f"_pad_script:={plan['pad_script']}", *params]
    clock = GraderClock(session) if plan.get("clock") == "grader" else None
    recorder = Recorder(clock.now if clock else time.monotonic)
    record = list(plan.get("record", []))
    # Subscribed before the node starts: the pad script plays from its start. Under the grader's
    # clock the twist (the first topic) comes last, once every other topic is connected at both
    # ends: the node's first tick waits for a listener on its twist (the template's
    # wait_for_robot), and a width published before its connection was counted would be lost.
    for topic in record[1:] if clock else record:
        recorder.add(topic)
    proc = session.start_student(argv, "teleoperation", clock.student_env() if clock else None)
    nodes, sub, pub, ok = _wait_for_node(session, proc, plan["start_timeout_s"], lambda s, p: bool(p))
    problem = "" if ok else _start_problem(proc, plan["start_timeout_s"], "advertising a topic")
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
        nodes2, sub2, pub2, _ = _wait_for_node(session, proc, 0.0, lambda s, p: True)
        if nodes2:
            nodes = set(nodes) | set(nodes2)
            sub = sub + [x for x in sub2 if x not in sub]
            pub = pub + [x for x in pub2 if x not in pub]
        for topic, _kind in pub:
            recorder.add(topic)

    if ok and clock is not None:
        clock.wait_for_listener(nodes, proc, plan["start_timeout_s"])
        # The loop's first tick comes at the start time, before any step: step only after it,
        # so tick k is always at start + k periods (stepping earlier would race the node's start).
        wait_for(lambda: recorder.count(plan["record"][0]) > 0 or not proc.running, plan["start_timeout_s"], 0.0005)
        # Every topic of tick 0 before the first step (a message that arrived after it would be
        # stamped a tick late); a topic the node never publishes costs one step timeout, once.
        wait_for(lambda: all(recorder.count(t) > 0 for t in plan["record"]) or not proc.running,
              GraderClock.STEP_TIMEOUT_S, 0.0005)
        lockstep = [t for t in plan["record"] if recorder.count(t) > 0] or plan["record"][:1]
        tick = 0
        while clock.now() - started < plan["run_s"] and proc.running:
            if tick % 25 == 0:
                follow_node()
            tick += 1
            if not clock.step(float(plan["gains"]["rate"]), recorder, lockstep, proc) and proc.running:
                if clock.answered:  # it followed the clock and fell silent: it is ending (or hangs)
                    session.phase(f"silent from {clock.now() - started:.2f} s")
                    break
                session.phase(f"paced from {clock.now() - started:.2f} s")
                clock.paced = True
        proc.wait(plan["quit_grace_s"])
    elif ok:
        deadline = started + plan["run_s"]
        while time.monotonic() < deadline and proc.running:
            follow_node()
            time.sleep(0.1)
        proc.wait(plan["quit_grace_s"])
    exited = not proc.running
    exit_code = proc.returncode
    proc.stop()
    stop_force.set()
    feeder.join(1.0)
    recorder.close()
    return {
        "kind": "teleop-node", "problem": problem, "quit_in_time": exited,
        "clock": "real time" if clock is None or clock.paced else "grader", "rescued_steps": clock.rescues if clock else 0,
        "node": _facts(proc, nodes, sub, pub, problem, exited), "exit_code": exit_code,
        "messages": {t: [[round(ts - started, 4), k, v] for ts, k, v in msgs] for t, msgs in recorder.messages.items()},
    }


#: How long a step waits for the sensor chain to pass on a tick's counts (s); a chain that
#: does not within it (a student's mapping_node that drops or merges counts) is not waited for again.
CHAIN_SETTLE_S = 0.5


def run_teleop_launch_sim(session: Session) -> Dict[str, Any]:
    """roslaunch the student's teleoperation.launch with the simulated lab and a scripted operator.

    lab_sim (the grader's, trusted) plays arm, hand, object and board before the launch
    starts, so the operator's script meets a ready lab; its board counts go to the
    stand-in serial_node the student's file starts (:mod:`hri_teleop.grading.run.standins`).
    The grader's parameter file (second on roslaunch's command line, so it survives
    ``clear_params``) gives the teleoperation node the virtual pad and the script. What the
    launch file lacks (a parameter, the serial_node, mapping_node, gripper_manager) the
    grader supplies, so this judges only whether what it starts works together.
    """
    plan = session.plan
    supplied: List[str] = []
    if plan.get("set_max_sensor_force") is not None:
        session.master.set_param("/max_sensor_force", plan["set_max_sensor_force"])
        supplied.append("/max_sensor_force")
    # Before anything reads /use_sim_time; time starts once every node is up and connected.
    clock = GraderClock(session, started=False) if plan.get("clock") == "grader" else None
    lab = session.master.run([plan["python"], *plan["lab_sim"]], "grader_lab_sim")
    ready = wait_for(lambda: "/lab_sim" in session.master.subscribers(plan["twist_topic"]) or not lab.running,
                  plan["start_timeout_s"], 0.05)
    session.phase("lab_sim up")
    if not ready or not lab.running:
        out = lab.output()[-1500:]
        lab.stop()
        return {"kind": "teleop-launch-sim", "session_error": f"the simulated lab did not start: {out}"}
    now = clock.now if clock else time.monotonic
    recorder = Recorder(now)
    for topic in plan["record"]:
        recorder.add(topic)
    launch = session.start_student(["roslaunch", "--wait", plan["launch_file"], plan["params_launch"]], "roslaunch",
                                   clock.student_env() if clock else None)
    teleop = plan["teleop_node"]
    started = now()
    up = wait_for(lambda: teleop in session.master.node_names() or not launch.running, plan["start_timeout_s"], 0.05)
    session.phase("teleoperation node registered")
    problem = "" if up and launch.running else _start_problem(launch, plan["start_timeout_s"], f"starting {teleop}")
    extra: List[Any] = []
    nodes: Set[str] = set()
    teleop_pub: List[List[str]] = []
    quit_in_time = False
    if not problem:
        for name, argv in plan.get("supply", {}).items():  # now: the launch file's parameters are set
            extra.append(session.start_student([plan["python"], *argv], f"grader_{name}"))
            supplied.append(name)
        def still_up() -> bool:
            nonlocal nodes, teleop_pub, quit_in_time
            current = _student_nodes(session.master, session.baseline)
            nodes |= current - {"/lab_sim"}
            if teleop not in current or not launch.running:
                quit_in_time = teleop not in current
                return False
            teleop_pub = _node_io(session.master, {teleop})[1] or teleop_pub
            return True

        if clock is not None:
            # Time stands still until every node is up and connected: at the simulation's
            # speed a node still importing would otherwise miss seconds of the operator.
            wait_until_settled(session, set(plan.get("expect_nodes", [])), launch, plan["settle_timeout_s"])
            session.phase("graph settled")
            # Step once the node's twists reach the recorder and lab_sim: a tick published before
            # a connection is lost (to lab_sim: a velocity out of the blue, which the arm refuses).
            twist, applied = plan["twist_topic"], plan["applied_topic"]
            recorder.add(applied)
            # Both ends counted: the node starts its pad script at the first tick with a listener.
            wait_for(lambda: (recorder.connected(twist) and recorder.connected(applied)
                           and connections(session, "/lab_sim", twist) > 0
                           and connections(session, teleop, twist, "o") >= 2)
                  or not launch.running, plan["start_timeout_s"], 0.002)
            rate_hz = node_rate_hz(session, teleop, plan["default_rate_hz"])
            chain = list(plan.get("sensor_chain", []))  # board -> /pub_force -> /force_mapped
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
            while clock.now() - started < plan["run_s"]:
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
            deadline = time.monotonic() + plan["run_s"]
            while time.monotonic() < deadline and still_up():
                time.sleep(0.1)
    pubs, subs, types = _graph(session.master)
    recorder.close()
    exited = not launch.running
    from hri_teleop.ros.master import stop_side_by_side

    stop_side_by_side([launch, *extra, lab])  # their shutdowns overlap (0.7 s one after another)
    return {
        "kind": "teleop-launch-sim", "supplied": supplied, "problem": problem, "nodes": sorted(nodes),
        "quit_in_time": quit_in_time, "run_s": round(now() - started, 3), "teleop_publications": teleop_pub,
        "clock": "grader" if clock is not None and not clock.paced else "real time",
        "publishers": {t: sorted(n) for t, n in pubs.items() if t not in _IGNORED_TOPICS},
        "subscribers": {t: sorted(n) for t, n in subs.items() if t not in _IGNORED_TOPICS},
        "types": {t: k for t, k in types.items() if t not in _IGNORED_TOPICS},
        "messages": {t: [[round(ts - started, 4), k, v] for ts, k, v in msgs] for t, msgs in recorder.messages.items()
                     if t in plan["record"]},
        "launch": {"exit_code": launch.returncode, "exited_by_itself": exited, "output_tail": launch.output_tail(),
                   "output_bytes": launch.output_size()},
        "lab_sim_log": lab.output()[-1500:],
    }


def run_live_graph(session: Session) -> Dict[str, Any]:
    """The lab's reference pipeline without hardware: its nodes, topics, types and connections."""
    plan = session.plan
    launch = session.master.run(["roslaunch", "--wait", "hri_lab", "teleoperation.launch", *plan["launch_args"]],
                                "reference")
    want = set(plan["nodes"])
    ok = wait_for(lambda: want <= set(session.master.node_names()) or not launch.running, plan["start_timeout_s"], 0.1)
    if not ok or not launch.running:
        out = launch.output()[-1500:]
        launch.stop()
        return {"kind": "live-graph", "problem": f"the reference teleoperation.launch did not start: {out}"}
    previous: Any = None
    for _ in range(50):  # until two readings 0.3 s apart agree
        pubs, subs, types = _graph(session.master)
        reading = (sorted((t, sorted(n)) for t, n in pubs.items()), sorted((t, sorted(n)) for t, n in subs.items()))
        if reading == previous:
            break
        previous = reading
        time.sleep(0.3)
    launch.stop()
    return {"kind": "live-graph", "problem": "",
            "publishers": {t: sorted(n) for t, n in pubs.items()}, "subscribers": {t: sorted(n) for t, n in subs.items()},
            "types": types}


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
