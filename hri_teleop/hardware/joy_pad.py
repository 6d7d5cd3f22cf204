"""The browser's gamepad as a node's pad: ``open_gamepad("browser")`` reads sensor_msgs/Joy on ``~virtual_joy``.

``widgets.BrowserPad`` (a notebook cell) reads the gamepad of the web page and publishes it 25 times a
second on ``/teleoperation/virtual_joy``; a node that opens this pad (the student's teleoperation.py
with ``_pad:=browser``) reads it as it would read a pad plugged in. Messages that stop are input lost:
the pad reads released and unplugged (:class:`~hri_teleop.core.gamepad.topic.TopicPadInput`), and the
node's twist ramps to zero. The node's ``~rumble`` goes back to the page through the widget. Never
beside the real robot (:class:`BrowserJoyPad`).
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, List, Optional, Union

import rospy
from sensor_msgs.msg import Joy

from hri_teleop.core.gamepad.layout import Layout, as_layout
from hri_teleop.core.gamepad.state import GamepadError, PadState
from hri_teleop.core.gamepad.topic import TOPIC_PAD_TIMEOUT_S, TopicPadInput
from hri_teleop.core.modes import HARDWARE_NODES

__all__ = ["BROWSER_PAD_TOPIC", "HARDWARE_CHECK_S", "BrowserJoyPad", "hardware_beside"]

#: Where the pad's messages arrive: the node's private topic, as for the lab's node with pad:=virtual.
BROWSER_PAD_TOPIC = "~virtual_joy"
#: How often the pad asks the master whether the real robot or board runs beside it, s (franka_control
#: registers seconds before its velocity controller listens: the pad reads unplugged long before).
HARDWARE_CHECK_S = 0.5


def hardware_beside() -> List[str]:
    """The lab's hardware nodes registered on the node's master (rospy's own link to it)."""
    try:
        code, _message, state = rospy.get_master().getSystemState()
    except Exception:  # noqa: BLE001 - a master that does not answer now: the node's own loop notices
        return []
    if code != 1:
        return []
    names = {node for section in state for _topic, nodes in section for node in nodes}
    return sorted(names & set(HARDWARE_NODES))


def _refusal(hardware: List[str]) -> str:
    return (f"the browser pad does not drive the real robot: this master runs the lab's hardware "
            f"({', '.join(hardware)}); in the lab your node reads the lab's gamepad (pad 'pygame')")


class BrowserJoyPad:
    """A pad whose state arrives as sensor_msgs/Joy on ``topic`` (default ``~virtual_joy``), in ``layout``'s order.

    Never beside the real robot: on a master that runs the lab's hardware (franka_control, franka_gripper,
    the board's serial_node), whoever started it, the pad refuses to open, and if the hardware appears later
    it reads unplugged from then on. In the lab the student's node reads the lab's gamepad.
    """

    stale_input_watch = False  # a page's pad may rightly hold a value bit for bit

    def __init__(self, layout: Union[Layout, str, None] = None, *, topic: str = BROWSER_PAD_TOPIC,
                 timeout_s: float = TOPIC_PAD_TIMEOUT_S, clock: Callable[[], float] = time.monotonic,
                 hardware: Callable[[], List[str]] = hardware_beside,
                 log: Optional[Callable[[str], None]] = None) -> None:
        found = hardware()
        if found:
            raise GamepadError(_refusal(found))
        self._layout = as_layout(layout)
        self.name = "browser pad"
        self.layout_reason = "the layout the browser pad publishes in"
        self._clock = clock
        self._hardware = hardware
        self._log = log or rospy.logwarn
        self._lock = threading.Lock()
        self.input = TopicPadInput(self._layout, timeout_s)
        self.refused = ""
        self.rumbles: List[float] = []  # the node asks for its rumble here; the widget reads ~rumble
        self._closed = threading.Event()
        self._subscriber: Any = rospy.Subscriber(topic, Joy, self.on_joy, queue_size=1, tcp_nodelay=True)
        self._watch = threading.Thread(target=self._watch_hardware, name="browser pad: hardware", daemon=True)
        self._watch.start()

    @property
    def layout(self) -> Layout:
        return self._layout

    @property
    def topic(self) -> str:
        return str(self._subscriber.resolved_name)

    def on_joy(self, msg: Any) -> None:
        """One sensor_msgs/Joy from the page (rospy's thread)."""
        with self._lock:
            self.input.receive(msg.axes, msg.buttons, self._clock())

    def _watch_hardware(self) -> None:
        while not self._closed.wait(HARDWARE_CHECK_S):
            found = self._hardware()
            if found and not self.refused:
                self.refused = _refusal(found)
                self._log(self.refused + ": the pad reads unplugged from now on")

    def poll(self) -> PadState:
        """The latest message's pad while fresh; released and unplugged when the messages stopped, or refused."""
        if self.refused:
            return PadState.neutral(connected=False)
        with self._lock:
            return self.input.state(self._clock())

    def rumble(self, intensity: float, duration_s: float = 0.0) -> None:
        """Kept for the record only: the node publishes its ``~rumble``, which the browser pad plays."""
        self.rumbles = self.rumbles[-99:] + [float(intensity)]

    def close(self) -> None:
        """Stop listening; safe to call twice."""
        self._closed.set()
        if self._subscriber is not None:
            self._subscriber.unregister()
            self._subscriber = None
