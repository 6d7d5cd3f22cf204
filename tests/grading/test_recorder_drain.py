"""The grader's recorder keeps everything an ended node sent (lockstep.Recorder.drain): a node that
publishes and exits at once has its last messages still unread in the recorder's socket, and a
close before they are read would lose some of them, a different number in every run."""

from __future__ import annotations

import json
import sys
import textwrap

import pytest

pytestmark = pytest.mark.ros

BURST = 200

# Publishes BURST messages in one go, written to the socket as they are published
# (queue_size=None), then ends: its last messages reach the recorder after it has gone.
PUBLISHER = textwrap.dedent(f"""
    import time
    import rospy
    from std_msgs.msg import Int32

    rospy.init_node("burst")
    pub = rospy.Publisher("/burst", Int32, queue_size=None)
    while pub.get_num_connections() == 0:
        time.sleep(0.005)
    for n in range({BURST}):
        pub.publish(Int32(n))
""")

# The grader's side. Its callback (the recorder's clock) holds every message after the first until
# the publisher has ended, so the rest of the burst is still unread in the socket then, in every run.
RECORDER = textwrap.dedent("""
    import json, sys, threading, time
    import rospy
    import rosgraph
    from hri_teleop.grading.run.lockstep import Recorder, wait_for

    gone = threading.Event()
    calls = []

    def gated_clock():
        calls.append(1)
        if len(calls) > 1:
            gone.wait(60)
        return time.monotonic()

    rospy.init_node("recorder", disable_signals=True)
    recorder = Recorder(gated_clock)
    recorder.add("/burst")
    master = rosgraph.Master("/recorder")

    def publishers():
        return [n for t, nodes in master.getSystemState()[0] if t == "/burst" for n in nodes]

    wait_for(lambda: bool(publishers()), 60.0, 0.005)
    wait_for(lambda: recorder.count("/burst") > 0, 60.0, 0.001)
    wait_for(lambda: not publishers(), 60.0, 0.001)  # the publisher has ended
    if sys.argv[1] == "drain":
        gone.set()
        drained = recorder.drain(Recorder.DRAIN_TIMEOUT_S)
        recorder.close()
    else:  # as run_teleop_node did: the close at once
        drained = None
        recorder.close()
        gone.set()
    count = recorder.count("/burst")
    time.sleep(0.2)  # nothing more is recorded after the close
    values = [v for _t, _k, v in recorder.messages["/burst"]]
    print(json.dumps({"drained": drained, "count": count, "after_close": recorder.count("/burst"), "values": values}))
""")


def _record(tmp_path, ros_master, mode: str) -> dict:
    (tmp_path / "publisher.py").write_text(PUBLISHER)
    (tmp_path / "recorder.py").write_text(RECORDER)
    recorder = ros_master.run([sys.executable, str(tmp_path / "recorder.py"), mode], f"recorder_{mode}")
    publisher = ros_master.run([sys.executable, str(tmp_path / "publisher.py")], f"publisher_{mode}")
    try:
        assert recorder.wait(120) == 0, recorder.output()[-2000:]
        assert publisher.wait(30) == 0, publisher.output()[-2000:]
    finally:
        recorder.stop()
        publisher.stop()
    return json.loads(recorder.output().strip().splitlines()[-1])


def test_drain_keeps_every_message_a_node_sent_before_it_ended(tmp_path, ros_master):
    result = _record(tmp_path, ros_master, "drain")
    assert result["drained"] is True
    assert result["values"] == list(range(BURST))
    assert result["after_close"] == result["count"] == BURST


def test_closing_without_the_drain_loses_the_ended_nodes_last_messages(tmp_path, ros_master):
    """The control: what run_teleop_node did before (the close right after the node ended)."""
    result = _record(tmp_path, ros_master, "close")
    assert result["values"] == [0]  # the one read before the node ended: the rest was lost
    assert result["after_close"] == result["count"] == 1  # the message held at the close was not recorded
