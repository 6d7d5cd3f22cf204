"""ROS time for the lab's nodes: wall clock in the lab, /clock when the autograder owns the time.

With ``/use_sim_time`` set, rospy's time stands still until /clock speaks and then moves
only when it does. A node that sleeps on the wall clock would run ahead of it; one that
waits for ROS time before the clock has started would wait for ever. These helpers wait
on ROS time, and bound every wait on the wall clock so a clock that stops (its owner
ended) never hangs a node.
"""

from __future__ import annotations

import threading
import time
from typing import Optional

import rospy

from hri_teleop.core.errors import HriTeleopError

__all__ = ["ClockError", "NodeClock", "uses_sim_time"]

#: How often a wait on simulated time looks at the clock, s of wall time.
POLL_S = 0.0005
#: A time this close to the target counts as reached, s: a schedule summed in floats
#: (1.0 + 0.02 + 0.02 ...) and a clock kept in whole nanoseconds differ in the last bits.
TOLERANCE_S = 1e-6


class ClockError(HriTeleopError, RuntimeError):
    """/use_sim_time is set but nothing publishes /clock (one line with the fix)."""


def uses_sim_time() -> bool:
    """Whether this node runs on /clock (the parameter /use_sim_time)."""
    return bool(rospy.get_param("/use_sim_time", False))


class NodeClock:
    """A node's time in s: time.monotonic() on the wall clock, rospy.get_time() on /clock.

    The mode is read once (``sim_time`` None: from /use_sim_time), as rospy does at
    init_node; every later call is local.
    """

    def __init__(self, sim_time: Optional[bool] = None) -> None:
        self.sim_time = uses_sim_time() if sim_time is None else bool(sim_time)

    def now(self) -> float:
        return rospy.get_time() if self.sim_time else time.monotonic()

    def wait_started(self, timeout_s: float = 60.0) -> float:
        """The first reading, once /clock has given one (at once on the wall clock)."""
        if not self.sim_time:
            return self.now()
        for _ in range(max(1, int(timeout_s / 0.005))):
            now: float = rospy.get_time()
            if now > 0.0 or rospy.is_shutdown():
                return now
            time.sleep(0.005)  # wall clock on purpose: ROS time does not move yet
        raise ClockError(f"/use_sim_time is true but nothing published /clock for {timeout_s:.0f} s; start "
                         "what owns the clock first, or set /use_sim_time false")

    def reached(self, target_s: float) -> bool:
        return self.now() >= target_s - TOLERANCE_S

    def sleep_until(self, target_s: float, wake: Optional[threading.Event] = None, stall_s: float = 5.0) -> bool:
        """Wait until now() reaches ``target_s`` or ``wake`` is set (True if woken; the event is not cleared).

        On /clock the wait also ends when the clock has not moved for ``stall_s`` of wall
        time (whoever owned it stopped) or rospy shuts down.
        """
        if not self.sim_time:
            remaining = target_s - time.monotonic()
            if remaining <= 0.0:
                return False
            if wake is None:
                time.sleep(remaining)
                return False
            return wake.wait(remaining)
        last, still_since = rospy.get_time(), time.monotonic()
        while not rospy.is_shutdown():
            now = rospy.get_time()
            if now >= target_s - TOLERANCE_S:
                return False
            if now != last:
                last, still_since = now, time.monotonic()
            elif time.monotonic() - still_since > stall_s:
                return False
            if wake is not None:
                if wake.wait(POLL_S):
                    return True
            else:
                time.sleep(POLL_S)
        return False
