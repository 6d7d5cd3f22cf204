"""A student's loop paced by time.sleep, under the grader's clock: one pass per tick of /clock,
however long the grader takes between ticks; time.sleep outside the student's files stays wall time."""

from __future__ import annotations

import json
import sys
import textwrap

import pytest

pytestmark = pytest.mark.ros

TICKS = 20
WALL_GAP_S = 0.05  # between ticks: five 10 ms sleeps of wall time

STUDENT = textwrap.dedent("""
    import time
    import rospy
    from std_msgs.msg import Int32
    import helper  # a library outside the student's folder

    rospy.init_node("sleeper")
    helper.pause(0.2)  # wall time: the clock does not move yet, and this must return
    pub = rospy.Publisher("/passes", Int32, queue_size=100, latch=True)
    for _ in range(10):  # the student's own wait before publishing anything: wall time too
        time.sleep(0.02)
    n = 0
    pub.publish(Int32(n))
    while not rospy.is_shutdown():
        time.sleep(0.01)
        n += 1
        pub.publish(Int32(n))
""")

HELPER = "import time\n\ndef pause(s):\n    time.sleep(s)\n"

DRIVER = textwrap.dedent(f"""
    import json, sys, threading, time
    import rospy
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import Int32

    rospy.init_node("driver", disable_signals=True)
    pub = rospy.Publisher("/clock", Clock, queue_size=None, latch=True)
    pub.publish(Clock(clock=rospy.Time(1, 0)))
    got = []
    ready = threading.Event()

    def passed(msg):
        got.append(msg.data)
        ready.set()

    rospy.Subscriber("/passes", Int32, passed, queue_size=1000)
    if not ready.wait(60):
        print(json.dumps({{"error": "no first pass"}}))
        sys.exit(0)
    for k in range(1, {TICKS} + 1):
        time.sleep({WALL_GAP_S})
        pub.publish(Clock(clock=rospy.Time(1, k * 10**7)))
    deadline = time.monotonic() + 10
    while len(got) <= {TICKS} and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.3)  # any pass more than the ticks would come now
    print(json.dumps({{"passes": len(got) - 1}}))
""")


def _run(tmp_path, ros_master, clock_env: bool) -> int:
    from hri_teleop.grading.run.lockstep import GraderClock

    folder = tmp_path / ("graded" if clock_env else "plain")
    lib = tmp_path / "lib"
    folder.mkdir()
    lib.mkdir(exist_ok=True)
    (folder / "student.py").write_text(STUDENT)
    (lib / "helper.py").write_text(HELPER)
    (tmp_path / "driver.py").write_text(DRIVER)
    ros_master.set_param("/use_sim_time", True)
    pythonpath = ":".join(p for p in (str(lib), ros_master.env.get("PYTHONPATH", "")) if p)
    env = GraderClock.student_env(folder, pythonpath) if clock_env else {"PYTHONPATH": pythonpath}
    student = ros_master.run([sys.executable, str(folder / "student.py")], f"student_{folder.name}", env)
    driver = ros_master.run([sys.executable, str(tmp_path / "driver.py")], f"driver_{folder.name}")
    try:
        assert driver.wait(120) == 0, driver.output()[-2000:]
        result = json.loads(driver.output().strip().splitlines()[-1])
    finally:
        driver.stop()
        student.stop()
    assert "passes" in result, (result, student.output()[-2000:])
    return int(result["passes"])


def test_a_time_sleep_loop_passes_once_per_tick_of_the_graders_clock(tmp_path, ros_master):
    assert _run(tmp_path, ros_master, clock_env=True) == TICKS


def test_without_the_graders_site_hook_the_same_loop_runs_on_the_wall_clock(tmp_path, ros_master):
    """The control: the loop ignores /clock and passes about five times per tick."""
    assert _run(tmp_path, ros_master, clock_env=False) > 2 * TICKS
