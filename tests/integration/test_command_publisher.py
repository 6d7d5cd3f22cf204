"""A command publisher hands every tick to each subscriber in order, even ticks published back to back.

The lab's teleoperation node publishes its twist with it. A loop catching up after a stall publishes
two ticks before rospy's sender thread runs; with ``queue_size=1`` the older was dropped and the robot
(and a test judging the recording) saw a double step.
"""

from __future__ import annotations

import re
import sys

import pytest

from hri_teleop.ros.commands import command_queue_size

pytestmark = pytest.mark.ros

TICKS = 50  # no more than the queue holds at 50 Hz: then none may be lost, however late the sender runs
#: Publishes TICKS twists (linear.x = 0, 1, ...) once the echo listens, in bursts of five back to back
#: (a loop catching up) a tick apart, then waits to be stopped.
PUBLISHER = f"""
import sys, threading, time, rospy
from geometry_msgs.msg import Twist
from hri_teleop.ros.commands import command_publisher
rospy.init_node("burst", disable_signals=True)
pub = command_publisher("/burst_cmd", Twist, rate_hz=float(sys.argv[1]))
while pub.get_num_connections() == 0:
    rospy.sleep(0.01)
sys.setswitchinterval(1.0)  # the sender thread waits for the GIL, as on a busy PC
for k in range({TICKS}):
    msg = Twist()
    msg.linear.x = float(k)
    pub.publish(msg)
    if k % 5 == 4:
        time.sleep(0.02)
print("published", flush=True)
threading.Event().wait()
"""


@pytest.mark.parametrize("rate_hz, size", [(50.0, 50), (50.2, 51), (0.5, 1), (1.0, 1)])
def test_the_queue_holds_one_second_of_ticks_and_at_least_one(rate_hz, size):
    assert command_queue_size(rate_hz) == size


def test_ticks_published_back_to_back_all_reach_the_subscriber_in_order(ros_master):
    echo = ros_master.run(["rostopic", "echo", "/burst_cmd/linear/x"], "burst_echo")
    pub = ros_master.run([sys.executable, "-c", PUBLISHER, "50"], "burst")
    try:
        def seen():
            return [float(v) for v in re.findall(r"^(-?\d+\.\d+)$", echo.output(), re.M)]

        # the publisher says so after its last publish() returned, which may be after the echo printed it
        ros_master.wait_for(lambda: ("published" in pub.output() and float(TICKS - 1) in seen()) or not pub.running,
                            60, "the publisher to finish and its last tick to arrive")
        assert "published" in pub.output(), pub.output()
        assert seen() == [float(k) for k in range(TICKS)]
    finally:
        pub.stop()
        echo.stop()
