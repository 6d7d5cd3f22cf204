"""Live-plot buffers: bounded, thread-safe, and fed by a getter derived from the message class."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, load_teleop_config
from hri_teleop.course.widgets import live
from hri_teleop.course.widgets.live import TopicBuffer, field_getter, lab_topics, numeric_fields, rate_hz


class _Vector3:
    __slots__ = ("x", "y", "z")
    _slot_types = ("float64", "float64", "float64")

    def __init__(self, x=0.0, y=0.0, z=0.0):
        self.x, self.y, self.z = x, y, z


class _Int16:
    __slots__ = ("data",)
    _slot_types = ("int16",)

    def __init__(self, data=0):
        self.data = data


def test_int16_and_float32_plot_their_data_field():
    assert numeric_fields(_Int16) == ("data",)
    assert field_getter(("data",))(_Int16(512)) == (512.0,)


def test_arrays_strings_and_headers_are_left_out():
    class Mixed:
        __slots__ = ("header", "name", "position", "effort", "count")
        _slot_types = ("std_msgs/Header", "string", "float64[]", "float32", "uint8")

    assert numeric_fields(Mixed) == ("effort", "count")


def test_a_twist_plots_its_six_components_when_ros_messages_are_available():
    geometry_msgs = pytest.importorskip("geometry_msgs.msg")
    fields = numeric_fields(geometry_msgs.Twist)
    assert fields == ("linear.x", "linear.y", "linear.z", "angular.x", "angular.y", "angular.z")
    msg = geometry_msgs.Twist()
    msg.linear.x, msg.angular.z = 0.1, -0.3
    assert field_getter(fields)(msg) == (0.1, 0.0, 0.0, 0.0, 0.0, -0.3)


def test_the_ring_buffer_keeps_the_newest_maxlen_samples_and_counts_all():
    buffer = TopicBuffer(("data",), maxlen=100)
    for i in range(250):
        buffer.append(float(i), (float(i),))
    times, values = buffer.snapshot()
    assert len(buffer) == 100 and buffer.received == 250
    assert times[0] == 150.0 and values[-1, 0] == 249.0 and values.shape == (100, 1)


def test_an_empty_buffer_snapshots_to_empty_arrays_of_the_right_width():
    times, values = TopicBuffer(("a", "b")).snapshot()
    assert times.shape == (0,) and values.shape == (0, 2)


def test_appends_from_many_threads_while_snapshotting_lose_nothing():
    buffer = TopicBuffer(("v",), maxlen=100000)
    stop = threading.Event()

    def writer(offset):
        for i in range(5000):
            buffer.append(time.monotonic(), (float(offset + i),))

    def reader():
        while not stop.is_set():
            times, values = buffer.snapshot()
            assert len(times) == len(values)

    snapshotter = threading.Thread(target=reader)
    snapshotter.start()
    writers = [threading.Thread(target=writer, args=(k * 10000,)) for k in range(4)]
    for w in writers:
        w.start()
    for w in writers:
        w.join()
    stop.set()
    snapshotter.join()
    _, values = buffer.snapshot()
    assert buffer.received == 20000
    assert sorted(values[:, 0]) == sorted(float(k * 10000 + i) for k in range(4) for i in range(5000))


def test_rate_counts_the_last_second():
    times = np.arange(0.0, 10.0, 0.01)
    assert rate_hz(times, now_s=10.0) == pytest.approx(100.0, abs=1.0)
    assert rate_hz(times, now_s=30.0) == 0.0


def test_the_lab_topics_are_the_contract_and_the_twist_topic_comes_from_the_config():
    specs = {spec.topic: spec.type for spec in lab_topics()}
    assert specs["/pub_force"] == "std_msgs/Int16"
    assert specs["/force_mapped"] == "std_msgs/Float32"
    assert specs["/gripper_width"] == "std_msgs/Float32"
    assert specs[DEFAULT_TWIST_TOPIC] == "geometry_msgs/Twist"


def test_another_twist_topic_in_the_teleop_config_is_followed(tmp_path):
    config = tmp_path / "teleop.yaml"
    config.write_text("twist_topic: /my_controller/cmd_vel\n")
    assert lab_topics(load_teleop_config(config))[-1].topic == "/my_controller/cmd_vel"


class _Session:
    """A kernel's ROS session as LivePlot asks it: present, and a line to show."""

    def __bool__(self) -> bool:
        return True

    def describe(self) -> str:
        return "a test session"


class _Topics:
    """LiveTopics without ROS: one buffer per spec, filled by the test."""

    def __init__(self, topics, maxlen=live.DEFAULT_MAXLEN):
        self.specs = list(topics)
        self.buffers = {spec.topic: live.TopicBuffer(("data",), maxlen) for spec in self.specs}

    def close(self):
        pass


def _plotted_points(plot):
    return {topic: len(lines[0].get_xdata()) for topic, lines in plot._lines.items()}


def test_a_run_that_ended_stays_in_view_after_the_window_has_passed(monkeypatch):
    monkeypatch.setattr(live, "LiveTopics", _Topics)
    specs = [live.TopicSpec("/gripper_width", "std_msgs/Float32", (0.0, 0.08), "m")]
    plot = live.LivePlot(specs, window_s=20.0, session=_Session(), figure="image", autostart=False, rumble_ok_topic="")
    buffer = plot.topics.buffers["/gripper_width"]
    for i in range(150):  # a 3 s run at 50 Hz, from t = 100 s
        buffer.append(100.0 + i * 0.02, (0.08 - i * 1e-4,))
    plot.redraw(now_s=103.5)  # while it runs: 0 = now
    assert _plotted_points(plot) == {"/gripper_width": 150}
    plot.redraw(now_s=160.0)  # long after: the run is still drawn, and the axis says so
    assert _plotted_points(plot) == {"/gripper_width": 150}
    xdata = plot._lines["/gripper_width"][0].get_xdata()
    assert -20.0 < min(xdata) and max(xdata) <= 0.0
    assert "nothing new since" in plot._bottom_axes.get_xlabel()
    plot.redraw(now_s=161.0)
    plot.topics.buffers["/gripper_width"].append(161.0, (0.05,))  # messages again: it scrolls with them
    plot.redraw(now_s=161.5)
    assert plot._bottom_axes.get_xlabel() == "time (s, 0 = now)"
    plot.close()


def test_the_plot_scrolls_while_messages_come_and_stops_a_quarter_window_after_the_last():
    assert live.view_end_s(None, 50.0, 20.0) == 50.0
    assert live.view_end_s(45.0, 50.0, 20.0) == 50.0  # quiet 5 s: a quarter of the window
    assert live.view_end_s(45.0, 50.1, 20.0) == 50.0  # quiet longer: stopped at last + 5 s
    assert live.view_end_s(45.0, 500.0, 20.0) == 50.0
