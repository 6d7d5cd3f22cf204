"""Ticks that meet in one pass of rospy's sender thread all reach the subscriber, in order.

rospy hands a publisher's messages to one sender thread per subscriber (its QueuedConnection). The test
holds that thread inside its write of the first tick, publishes the next ones meanwhile (a loop catching
up after a stall), then lets it go: with a queue of one the middle ticks were dropped. The subscriber is a
stand-in transport; no master, no network, no wait on the clock: each step waits for the one before.
"""

from __future__ import annotations

import threading
from typing import List

import pytest
import rospy.topics
from geometry_msgs.msg import Twist
from rospy.impl.transport import OUTBOUND, Transport

from hri_teleop.ros.commands import command_publisher, command_queue_size

LONG_S = 60.0  # only a hung sender thread waits this long: the test then fails instead of hanging


class HeldSubscriber(Transport):
    """A subscriber's transport whose first write waits until the test lets it go."""

    def __init__(self, last: int) -> None:
        super().__init__(OUTBOUND, "held-subscriber")
        self.endpoint_id = "held-subscriber"
        self.received: List[int] = []
        self.writing_first = threading.Event()
        self.release = threading.Event()
        self.got_last = threading.Event()
        self._last = last
        self.publisher_thread = threading.current_thread()  # the test's: the control loop's stand-in
        self.synchronous = False

    def write_data(self, data: bytes) -> bool:
        message = Twist()
        message.deserialize(data[4:])  # after its length
        tick = int(message.linear.x)
        if threading.current_thread() is self.publisher_thread:  # no sender thread: nothing to hold
            self.synchronous = True
            self.writing_first.set()
            self.received.append(tick)
            return True
        if not self.received:
            self.writing_first.set()
            assert self.release.wait(LONG_S), "the test never let the sender go"
        self.received.append(tick)
        if tick == self._last:
            self.got_last.set()
        return True


def _twist(tick: int) -> Twist:
    message = Twist()
    message.linear.x = float(tick)
    return message


@pytest.mark.parametrize("rate_hz, burst", [(50.0, 3), (50.0, 51), (10.0, 11), (2.0, 3)])
def test_ticks_published_while_the_sender_is_busy_all_reach_the_subscriber_in_order(rate_hz, burst, monkeypatch):
    """``burst`` ticks, the first held in the sender while the rest (up to one second of ticks) are published."""
    monkeypatch.setattr(rospy.topics, "is_initialized", lambda: True)  # publish() asks; no node, no master needed
    publisher = command_publisher(f"/held_burst_{int(rate_hz)}_{burst}", Twist, rate_hz)
    subscriber = HeldSubscriber(last=burst - 1)
    try:
        publisher.impl.add_connection(subscriber)
        publisher.publish(_twist(0))
        assert subscriber.writing_first.wait(LONG_S)
        assert not subscriber.synchronous, "published synchronously: the control loop would wait for a slow subscriber"
        for tick in range(1, burst):   # the loop catching up: all in one pass of the sender
            publisher.publish(_twist(tick))
        subscriber.release.set()
        assert subscriber.got_last.wait(LONG_S)
        assert subscriber.received == list(range(burst))
    finally:
        subscriber.release.set()
        subscriber.close()  # the subscriber hangs up (its sender thread ends), then the publisher goes
        publisher.unregister()


@pytest.mark.parametrize("rate_hz, size", [(50.0, 50), (50.2, 51), (49.9, 50), (1.0, 1), (0.5, 1), (0.01, 1)])
def test_the_queue_holds_one_second_of_ticks_and_at_least_one(rate_hz, size):
    assert command_queue_size(rate_hz) == size
