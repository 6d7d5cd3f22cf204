"""Publishers for robot commands: every tick's command reaches each subscriber, in order.

rospy hands a publisher's messages to one sender thread per subscriber. With ``queue_size=1`` it
keeps only the newest: a late tick followed at once by the next (the loop catching up on a busy
PC) loses the older one, and the robot sees a double step. A queue of one second of ticks loses
nothing unless a sender stalls for that long, and a stalled subscriber still cannot block the
control loop (as synchronous publishing, ``queue_size=None``, would).
"""

from __future__ import annotations

import math
from typing import Any

import rospy


def command_queue_size(rate_hz: float) -> int:
    """How many commands a subscriber's queue holds: one second of ticks at ``rate_hz`` (at least 1)."""
    return max(1, int(math.ceil(rate_hz)))


def command_publisher(topic: str, data_class: Any, rate_hz: float) -> rospy.Publisher:
    """A publisher for a command sent once per tick at ``rate_hz``: no tick dropped, none reordered."""
    return rospy.Publisher(topic, data_class, queue_size=command_queue_size(rate_hz))
