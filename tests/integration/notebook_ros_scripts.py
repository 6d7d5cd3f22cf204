"""Processes for the notebook-ROS tests: each runs as its own node (rospy allows one per process).

    python notebook_ros_scripts.py publish-burst N RATE_HZ   # N messages on the lab's 4 topics, value i
    python notebook_ros_scripts.py publish-press PEAK        # a press profile on /pub_force up to PEAK, repeated
    python notebook_ros_scripts.py live-plot N OUT.json      # a LivePlot that redraws while N per topic arrive
    python notebook_ros_scripts.py calibrate FILE OUT.json   # CalibrationWidget: record 2 s, apply to FILE
    python notebook_ros_scripts.py twice OUT.json            # ensure_ros twice (and once more after a foreign init)

Every value the tests check is written as JSON to OUT.json.
"""

from __future__ import annotations

import json
import sys
import time


def _wait_for_subscribers(publishers, timeout_s=30.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if all(p.get_num_connections() > 0 for p in publishers):
            return
        time.sleep(0.05)
    raise SystemExit(f"no subscriber on {[p.name for p in publishers if not p.get_num_connections()]}")


def publish_burst(count: int, rate_hz: float) -> None:
    import rospy
    from geometry_msgs.msg import Twist
    from std_msgs.msg import Float32, Int16

    from hri_teleop.course.widgets.live import lab_topics

    rospy.init_node("burst", disable_signals=True)
    twist_topic = lab_topics()[-1].topic
    pubs = [rospy.Publisher("/pub_force", Int16, queue_size=1000, tcp_nodelay=True),
            rospy.Publisher("/force_mapped", Float32, queue_size=1000, tcp_nodelay=True),
            rospy.Publisher("/gripper_width", Float32, queue_size=1000, tcp_nodelay=True),
            rospy.Publisher(twist_topic, Twist, queue_size=1000, tcp_nodelay=True)]
    _wait_for_subscribers(pubs)
    time.sleep(0.3)  # the subscriber side of each connection is set up too
    period = 1.0 / rate_hz
    start = time.monotonic()
    for i in range(count):
        twist = Twist()
        twist.linear.x = float(i)
        for pub, msg in zip(pubs, (Int16(i), Float32(float(i)), Float32(float(i)), twist)):
            pub.publish(msg)
        delay = start + (i + 1) * period - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    print(f"published {count} x 4 in {time.monotonic() - start:.2f} s", flush=True)
    time.sleep(2.0)  # let the last messages leave before the connections close


def publish_press(peak: int) -> None:
    import rospy
    from std_msgs.msg import Int16

    rospy.init_node("press", disable_signals=True)
    pub = rospy.Publisher("/pub_force", Int16, queue_size=100, tcp_nodelay=True)
    _wait_for_subscribers([pub], timeout_s=60.0)
    profile = [int(peak * min(k, 100 - k) / 50) for k in range(101)]  # 0 -> peak -> 0 in 1 s at 100 Hz
    # On a schedule of its own, as the board keeps 100 Hz: a sleep of 0.01 s after each message ran slower
    # than 100 Hz by the time each publish takes, and much slower on a busy machine (149 samples in 2 s).
    start, sent = time.monotonic(), 0
    while not rospy.is_shutdown():
        for count in profile:
            pub.publish(Int16(count))
            sent += 1
            time.sleep(max(0.0, start + sent * 0.01 - time.monotonic()))


def live_plot(count: int, out: str) -> None:
    from hri_teleop.course.notebook_ros import ensure_ros
    from hri_teleop.course.widgets import LivePlot

    session = ensure_ros("live_plot_test")
    plot = LivePlot(figure="image", autostart=False, maxlen=count + 100, window_s=10.0)
    assert plot.topics is not None
    buffers = plot.topics.buffers
    draws = []
    arriving = []  # the messages received by each redraw made while they still arrived
    deadline = time.monotonic() + 60.0
    # The kernel's thread: redraw 10 times per second while rospy's threads fill the buffers.
    while time.monotonic() < deadline and any(b.received < count for b in buffers.values()):
        started = time.monotonic()
        before = sum(b.received for b in buffers.values())
        plot.redraw()
        draws.append(time.monotonic() - started)
        if 0 < before < count * len(buffers):
            arriving.append(before)
        time.sleep(max(0.0, 0.1 - draws[-1]))
    time.sleep(0.5)  # anything beyond count would be a duplicate
    plot.redraw()
    with open(out[:-len(".json")] + ".png", "wb") as fh:
        fh.write(plot.view.png())  # the last frame, for a person to look at
    result = {"node": session.node_name, "draws": len(draws), "arriving": arriving, "draw_ms_mean": 1000 * sum(draws) / max(1, len(draws)),
              "draw_ms_max": 1000 * max(draws or [0.0]), "topics": {}, "pad_cue": plot.pad_cue.value}
    for topic, buffer in buffers.items():
        times, values = buffer.snapshot()
        result["topics"][topic] = {"received": buffer.received, "first_column": [float(v) for v in values[:, 0]],
                                   "span_s": float(times[-1] - times[0]) if len(times) else 0.0}
    plot.close()
    with open(out, "w") as fh:
        json.dump(result, fh)


def calibrate(file: str, out: str) -> None:
    from hri_teleop.course.notebook_ros import ensure_ros
    from hri_teleop.course.widgets import CalibrationWidget

    ensure_ros("calibration_test")
    widget = CalibrationWidget(file, duration_s=2.0)
    started = widget.start()
    result = widget.wait(timeout_s=30.0)
    message = widget.apply()
    with open(out, "w") as fh:
        json.dump({"started": started, "result": result, "samples": widget.recorder.samples, "message": message,
                   "label": widget.maximum_label.value}, fh)
    widget.close()


def twice(out: str) -> None:
    import os

    from hri_teleop.course.notebook_ros import ensure_ros
    from hri_teleop.ros.master_api import master_call

    first = ensure_ros("twice")
    second = ensure_ros("twice")  # re-running the cell
    third = ensure_ros("another_name")  # another notebook cell asking for another name
    nodes = sorted({n for _t, names in master_call("getSystemState")[0] for n in names})
    with open(out, "w") as fh:
        json.dump({"same": first is second is third, "node": first.node_name, "nodes": nodes,
                   "started_master": first.started_master, "uri": first.master_uri,
                   "env_uri": os.environ["ROS_MASTER_URI"]}, fh)


if __name__ == "__main__":
    command, args = sys.argv[1], sys.argv[2:]
    if command == "publish-burst":
        publish_burst(int(args[0]), float(args[1]))
    elif command == "publish-press":
        publish_press(int(args[0]))
    elif command == "live-plot":
        live_plot(int(args[0]), args[1])
    elif command == "calibrate":
        calibrate(args[0], args[1])
    elif command == "twice":
        twice(args[0])
    else:
        raise SystemExit(f"unknown command {command}")
