"""A node's SIGINT and SIGTERM handled outside the signal handler: rospy's own handler can deadlock.

rospy's handler runs rospy's whole shutdown in the main thread, at whatever line the signal
interrupted. Inside ``Publisher.publish`` that thread holds a lock the shutdown then waits for:
the node hangs, and every later SIGINT or SIGTERM runs into the same wait (a lab_sim outlived
its test by two hours). Here the handler only sets an event; a thread shuts rospy down; the loop
ends at its next ``is_shutdown()`` (or meets a topic rospy closed: ``run_node`` takes that as the
stop). A second signal ends the process at once.
"""

from __future__ import annotations

import os
import signal
import threading
from typing import Any, Callable, List, Optional, Tuple

__all__ = ["init_node", "stop_on_signals", "finish_stop"]

#: Each installed watch: its event (a signal came) and the thread that then shuts rospy down.
_WATCHES: List[Tuple[threading.Event, threading.Thread]] = []


def stop_on_signals(shutdown: Optional[Callable[[str], None]] = None) -> threading.Event:
    """Install the handlers (main thread only); returns the event the first signal sets.

    ``shutdown(reason)`` runs in a thread of its own (default: ``rospy.signal_shutdown``).
    """
    if shutdown is None:
        import rospy  # noqa: PLC0415 - only a node's process asks for it

        shutdown = rospy.signal_shutdown
    stop = threading.Event()
    received: List[str] = []

    def watch() -> None:
        stop.wait()
        shutdown(f"signal {received[0] if received else '?'}")

    def handler(signum: int, _frame: Any) -> None:
        if stop.is_set():  # the second one: no more waiting for a clean stop
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        received.append(signal.Signals(signum).name)
        stop.set()

    watcher = threading.Thread(target=watch, name="stop_on_signals", daemon=True)
    watcher.start()
    _WATCHES.append((stop, watcher))
    signal.signal(signal.SIGINT, handler)
    signal.signal(signal.SIGTERM, handler)
    return stop


def finish_stop(timeout_s: float = 5.0) -> None:
    """Wait (at most ``timeout_s``) for a shutdown a signal started: the node's registrations are
    gone from the master before its process ends, as when rospy's handler ran it."""
    for stop, watcher in _WATCHES:
        if stop.is_set():
            watcher.join(timeout_s)


def init_node(name: str, **kwargs: Any) -> threading.Event:
    """``rospy.init_node`` without rospy's signal handlers, then :func:`stop_on_signals`."""
    import rospy  # noqa: PLC0415 - only a node's process asks for it

    rospy.init_node(name, disable_signals=True, **kwargs)
    return stop_on_signals(rospy.signal_shutdown)
