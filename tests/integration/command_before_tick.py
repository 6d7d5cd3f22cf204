#!/usr/bin/env python3
"""A velocity command that reaches lab_sim before the tick it belongs to: which time does it get?

With /use_sim_time set, this node owns /clock. It moves the clock to 1 s and sends a first twist
(lab_sim answers on ~command_time_s with the time it applied it). Then it sends a second twist
while the clock still reads 1 s, waits ``~delay_s`` of wall time (a busy machine delaying the
next /clock), and only then moves the clock to 1.01 s. The second answer must be 1.01: the
command belongs to the next tick. Prints JSON: {"first": s, "second": s}.
"""

from __future__ import annotations

import json
import sys
import threading
import time
from typing import List

import rospy
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float64


def main() -> int:
    rospy.init_node("command_before_tick", disable_signals=True)
    delay_s = float(rospy.get_param("~delay_s"))
    answers: List[float] = []
    answered = threading.Condition()

    def on_answer(msg: Float64) -> None:
        with answered:
            answers.append(msg.data)
            answered.notify_all()

    clock = rospy.Publisher("/clock", Clock, queue_size=10, latch=True)
    twist = rospy.Publisher("/cartesian_velocity_controller/cmd_vel", Twist, queue_size=10)
    rospy.Subscriber("/lab_sim/command_time_s", Float64, on_answer)

    def wait_until(condition, timeout_s: float, what: str) -> None:
        deadline = time.monotonic() + timeout_s
        while not condition():
            if time.monotonic() > deadline:
                print(f"command_before_tick: {what} within {timeout_s} s", file=sys.stderr)
                sys.exit(2)
            time.sleep(0.01)

    wait_until(lambda: clock.get_num_connections() > 0 and twist.get_num_connections() > 0, 60, "lab_sim connected")
    clock.publish(Clock(clock=rospy.Time(1, 0)))
    time.sleep(0.5)  # before the first command, nothing depends on when lab_sim hears the clock
    twist.publish(Twist())
    with answered:
        if not answered.wait_for(lambda: len(answers) >= 1, 30):
            print("command_before_tick: no answer to the first twist within 30 s", file=sys.stderr)
            return 2
    twist.publish(Twist())  # the clock still reads 1 s
    time.sleep(delay_s)
    clock.publish(Clock(clock=rospy.Time(1, 10_000_000)))
    with answered:
        if not answered.wait_for(lambda: len(answers) >= 2, 30):
            print("command_before_tick: no answer to the second twist within 30 s", file=sys.stderr)
            return 2
    print(json.dumps({"first": answers[0], "second": answers[1]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
