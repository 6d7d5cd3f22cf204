"""The teleoperation node's twist publisher keeps every tick that meets others in one pass of its sender.

The lab's own teleoperation.py runs on a private roscore with a hook (in its own process, before the
script) that holds rospy's sender thread for the twist's first subscriber inside its first write, until
the node has published three more ticks, and then says how many of them wait in that subscriber's queue.
With ``queue_size=1`` (race 13 before its fix) only the newest waits: the robot would see a double step.
Nothing here depends on how busy the machine is: the hold ends on the node's own publishes, not on time.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from hri_teleop.core.config import load_teleop_config

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
TELEOP = REPO / "hri_lab" / "scripts" / "teleoperation.py"
TWIST = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml").twist_topic
HELD_TICKS = 3

#: Run as ``python -c HOOK TOPIC SCRIPT ARGS...``: wraps rospy's publisher of TOPIC, then runs SCRIPT as __main__.
HOOK = f"""
import runpy, sys, threading
import rospy.topics

topic, script = sys.argv[1], sys.argv[2]
sys.argv = [script] + sys.argv[3:]
Impl = rospy.topics._PublisherImpl
add_connection, publish = Impl.add_connection, Impl.publish
cond = threading.Condition()
state = {{"impl": None, "published": 0}}


def watched_publish(self, message, connection_override=None):
    if self is not state["impl"]:
        return publish(self, message, connection_override)
    with cond:  # a publish and its count together: the held sender reads both at once
        sent = publish(self, message, connection_override)
        state["published"] += 1
        cond.notify_all()
    return sent


def watched_add_connection(self, transport):
    if self.resolved_name != topic or state["impl"] is not None:
        return add_connection(self, transport)
    write, first = transport.write_data, [True]

    def held_write(data):
        if first[0]:
            first[0] = False
            queued = self.connections[-1]  # rospy's sender for this subscriber (its QueuedConnection)
            with cond:
                start = state["published"]
                cond.wait_for(lambda: state["published"] >= start + {HELD_TICKS}, 60)
                with queued._lock:
                    waiting = len(queued._queue)
                print(f"burst: {{state['published'] - start}} published while the sender was held, "
                      f"{{waiting}} queued", flush=True)
        return write(data)

    transport.write_data = held_write
    added = add_connection(self, transport)
    state["impl"] = self
    return added


Impl.add_connection, Impl.publish = watched_add_connection, watched_publish
runpy.run_path(script, run_name="__main__")
"""


def test_ticks_the_node_publishes_while_its_sender_is_busy_all_wait_for_the_robot(ros_master):
    node = ros_master.run([sys.executable, "-c", HOOK, TWIST, str(TELEOP), "_pad:=virtual", "_script_wait_s:=0"],
                          "teleoperation")
    try:
        ros_master.wait_for(lambda: bool(ros_master.publishers(TWIST)) or not node.running, 30,
                            "teleoperation to advertise its twist")
        robot = ros_master.run(["rostopic", "echo", "-n", "200", f"{TWIST}/linear/x"], "robot_stand_in")
        try:
            ros_master.wait_for(lambda: "burst: " in node.output() or not node.running, 60,
                                "the node to publish while its sender was held")
        finally:
            robot.stop()
        found = re.search(r"burst: (\d+) published while the sender was held, (\d+) queued", node.output())
        assert found, node.output()
        published, queued = int(found.group(1)), int(found.group(2))
        assert published >= HELD_TICKS and queued == published, node.output()
    finally:
        node.stop()
