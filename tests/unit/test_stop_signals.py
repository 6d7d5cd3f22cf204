"""A node's stop signals: the shutdown runs outside the handler, so a signal that lands while the main
thread holds a lock the shutdown needs (inside Publisher.publish) does not hang the node."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap

import pytest

pytest.importorskip("rospy")

SCRIPT = textwrap.dedent("""
    import os, signal, sys, threading, time
    import rospy
    from hri_teleop.ros.stop_signals import stop_on_signals

    held = threading.Lock()  # as the publisher's lock: held by the main thread while it sends
    ran = threading.Event()

    def hook():
        with held:
            ran.set()

    rospy.on_shutdown(hook)
    if sys.argv[1] == "ours":
        stop_on_signals()
    else:
        rospy.core.register_signals()  # what rospy.init_node installs by default
    with held:
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(20):
            time.sleep(0.01)  # the handler runs in this thread, between two of these
    print("stopped" if ran.wait(10) and rospy.is_shutdown() else "hung", flush=True)
""")


def _run(which: str, timeout_s: float) -> str:
    try:
        return subprocess.run([sys.executable, "-c", SCRIPT, which], capture_output=True, text=True,
                              timeout=timeout_s).stdout.strip()
    except subprocess.TimeoutExpired:
        return "timed out"


def test_a_signal_while_the_main_thread_holds_the_shutdowns_lock_still_stops_the_node():
    assert _run("ours", 60) == "stopped"


def test_with_rospys_own_handler_the_same_signal_hangs_the_node():
    """The control: rospy runs its shutdown inside the handler, in the thread holding the lock."""
    assert _run("rospy", 8) == "timed out"


def test_a_second_signal_ends_a_node_whose_shutdown_hangs():
    script = textwrap.dedent("""
        import os, signal, threading, time
        from hri_teleop.ros.stop_signals import stop_on_signals

        stop_on_signals(lambda reason: threading.Event().wait())  # a shutdown that never ends
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.2)
        print("still here", flush=True)
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(30)
        print("not ended", flush=True)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert done.stdout.split("\n")[0] == "still here"
    assert "not ended" not in done.stdout
    assert done.returncode == -signal.SIGTERM


def test_the_node_ends_only_once_the_shutdown_a_signal_started_has_finished():
    """run_node waits for it: a node's registrations leave the master before its process ends."""
    script = textwrap.dedent("""
        import os, signal, time
        from hri_teleop.ros.params import run_node
        from hri_teleop.ros.stop_signals import stop_on_signals

        def slow_shutdown(reason):
            time.sleep(0.5)
            print("shut down after", reason, flush=True)

        def main():
            stop = stop_on_signals(slow_shutdown)
            os.kill(os.getpid(), signal.SIGTERM)
            stop.wait(10)
            return 0  # the loop ends at once; the shutdown is still running in its thread

        run_node(main)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "shut down after signal SIGTERM"
