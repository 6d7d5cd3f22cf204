#!/usr/bin/env python3
"""A test's own /clock, in lock step with the nodes it drives: rates judged on simulated time.

With /use_sim_time set, the nodes under test (lab_sim.py, FSR_sensor.py) tick on /clock. This
node moves the clock by ``~step_s``, ``~steps`` times, and after each step waits until every
process under ``~pids`` (and their children) waits for something, as the grader does
(:class:`hri_teleop.grading.run.lockstep.Quiescence`). Each tick thus runs whole, however busy
the machine is, and what the nodes publish per simulated second does not depend on it.

It records ``~topics`` (comma-separated) and writes ``~log`` (JSON): per topic a list of
[clock_s when received, header stamp in s or null]. Exit 0; 2 with one line when a step
never got quiet (a node that busy-loops: the rates would be the machine's again).
"""

from __future__ import annotations

import json
import sys
import threading
import time
from typing import Any, Dict, List, Optional

import roslib.message
import rospy
from rosgraph_msgs.msg import Clock

from hri_teleop.grading.run.lockstep import Quiescence

START_NS = 10**9  # the first reading, 1 s: ROS time 0 means "no clock yet" to a node


def main() -> int:
    rospy.init_node("clock_stepper", disable_signals=True)
    step_ns = int(round(float(rospy.get_param("~step_s")) * 1e9))
    steps = int(rospy.get_param("~steps"))
    roots = [int(p) for p in str(rospy.get_param("~pids")).split(",") if p]
    topics = [t for t in str(rospy.get_param("~topics")).split(",") if t]
    listeners = int(rospy.get_param("~listeners"))  # the nodes that subscribe /clock (this one too)
    now_ns = START_NS
    lock = threading.Lock()
    messages: Dict[str, List[List[Optional[float]]]] = {t: [] for t in topics}

    def received(msg: Any, topic: str) -> None:
        kind = msg._connection_header.get("type", "")
        cls = roslib.message.get_message_class(kind)
        stamp: Optional[float] = None
        if cls is not None and cls._has_header:
            typed = cls()
            typed.deserialize(msg._buff)
            stamp = typed.header.stamp.to_sec()
        with lock:
            messages[topic].append([now_ns / 1e9, stamp])

    subs = [rospy.Subscriber(t, rospy.AnyMsg, received, callback_args=t, queue_size=10000, tcp_nodelay=True)
            for t in topics]
    # Synchronous publishing (no queue thread): once publish() returns, the tick is on its way.
    pub = rospy.Publisher("/clock", Clock, queue_size=None, latch=True, tcp_nodelay=True)  # type: ignore[arg-type]

    def publish() -> None:
        pub.publish(Clock(clock=rospy.Time(now_ns // 10**9, now_ns % 10**9)))

    deadline = time.monotonic() + 60.0  # hang guard: the nodes were up before this started
    while not all(s.get_num_connections() > 0 for s in subs) or pub.get_num_connections() < listeners:
        if time.monotonic() > deadline:
            print(f"clock_stepper: not connected within 60 s (topics {topics}, {listeners} /clock listeners)", file=sys.stderr)
            return 2
        time.sleep(0.01)
    quiet = Quiescence(roots)
    publish()
    quiet.wait()
    for _ in range(steps):
        now_ns += step_ns
        publish()
        if not quiet.wait():
            print(f"clock_stepper: the nodes under {roots} never all waited within {quiet.TIMEOUT_S} s "
                  f"after the step to {now_ns / 1e9:.3f} s", file=sys.stderr)
            return 2
    time.sleep(0.3)  # the last ticks' messages on their way here (tests judge a window well before them)
    with lock:
        record = {"start_s": START_NS / 1e9, "step_s": step_ns / 1e9, "steps": steps, "messages": messages}
    with open(str(rospy.get_param("~log")), "w") as fh:
        json.dump(record, fh)
    return 0


if __name__ == "__main__":
    sys.exit(main())
