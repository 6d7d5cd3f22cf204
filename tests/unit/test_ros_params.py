"""hri_teleop.ros.params: one line and exit 1 on bad input, a traceback only for bugs."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytest.importorskip("rospy", reason="needs ROS 1's rospy (run 'make setup')")

from hri_teleop.ros.params import ParamError, check_kind

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("value, kind, expected", [
    (10, float, 10.0),
    (2.5, float, 2.5),
    (3, int, 3),
    (True, bool, True),
    ("virtual", str, "virtual"),
    (7, (int, str), 7),
])
def test_accepted_values(value, kind, expected):
    result = check_kind("~x", value, kind)
    assert result == expected and type(result) is type(expected)


@pytest.mark.parametrize("value, kind", [
    (True, float), (False, int), ("10", float), (2.5, int), (float("nan"), float),
    (float("inf"), float), (None, str), (1, str), ([1], float),
])
def test_refused_values_name_the_parameter_in_one_line(value, kind):
    with pytest.raises(ParamError) as info:
        check_kind("/node/rate_hz", value, kind, fix="set it to a rate in Hz, e.g. _rate_hz:=10")
    message = str(info.value)
    assert message.startswith("parameter /node/rate_hz is ") and "_rate_hz:=10" in message
    assert "\n" not in message


def _run(body: str) -> subprocess.CompletedProcess:
    code = "from hri_teleop.ros.params import run_node, fail\n" + textwrap.dedent(body)
    return subprocess.run([sys.executable, "-c", code], cwd=str(REPO), capture_output=True, text=True, timeout=60)


def test_a_project_error_ends_the_node_with_one_line_and_status_1():
    proc = _run("""
        from hri_teleop.core.mapping import validate_max_sensor_force
        def main():
            validate_max_sensor_force(-5)
        run_node(main)
    """)
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "/max_sensor_force" in lines[0] and "rosparam set" in lines[0], proc.stderr


def test_fail_ends_with_its_line_and_status_1():
    proc = _run("""
        def main():
            fail("parameter ~speed is -1; set it to a positive speed in m/s")
        run_node(main)
    """)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    assert "parameter ~speed is -1" in proc.stderr


def test_normal_end_and_ctrl_c_end_with_status_0():
    assert _run("run_node(lambda: 0)").returncode == 0
    proc = _run("""
        def main():
            raise KeyboardInterrupt
        run_node(main)
    """)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr


def test_a_bug_still_shows_its_traceback():
    proc = _run("""
        def main():
            return 1 / 0
        run_node(main)
    """)
    assert proc.returncode != 0 and "ZeroDivisionError" in proc.stderr and "Traceback" in proc.stderr


def test_a_publish_to_a_topic_rospy_closed_while_it_shuts_down_ends_the_node_with_status_0():
    """A stop signal shuts rospy down in a thread (ros/stop_signals.py); rospy closes the topics before it
    says it is shut down, so the loop's publish can meet a closed topic: that is the stop, not a failure."""
    done = _run("""
        import threading
        import rospy

        closing, raised = threading.Event(), threading.Event()

        def close_all(reason):  # as rospy's own pre-shutdown hook, which closes every topic
            closing.set()
            raised.wait(10)

        rospy.core.add_preshutdown_hook(close_all)

        def main():
            threading.Thread(target=rospy.signal_shutdown, args=("signal SIGINT",), daemon=True).start()
            closing.wait(10)
            assert rospy.core.is_shutdown_requested() and not rospy.is_shutdown()
            try:
                raise rospy.ROSException("publish() to a closed topic")
            finally:
                raised.set()

        run_node(main)
    """)
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr


def test_the_same_error_from_rospy_outside_a_shutdown_shows_its_traceback():
    done = _run("""
        import rospy

        def main():
            raise rospy.ROSException("publish() to a closed topic")

        run_node(main)
    """)
    assert done.returncode == 1 and "ROSException: publish() to a closed topic" in done.stderr
