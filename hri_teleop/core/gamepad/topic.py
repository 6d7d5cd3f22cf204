"""A pad that arrives as messages (sensor_msgs/Joy on a topic): the latest one, released once it is old.

The browser pad (``widgets.BrowserPad``) publishes the gamepad of a web page 25 times a second on the
teleoperation node's ``~virtual_joy``; a node opened with ``open_gamepad("browser")`` reads it through
:class:`TopicPadInput`. Messages that stop (a closed tab, a busy or ended kernel, a dropped link) are
input lost: the pad then reads released and unplugged, so the node's twist ramps to zero as for an
unplugged pad. No ROS here; ``hri_teleop.hardware.joy_pad`` is the subscriber around it.
"""

from __future__ import annotations

from typing import Optional, Sequence, Union

from hri_teleop.core.gamepad.layout import Layout
from hri_teleop.core.gamepad.state import GamepadError, PadState

__all__ = ["TOPIC_PAD_TIMEOUT_S", "TopicPadInput"]

#: No message for longer than this and the pad reads released, s: the lab node's input_timeout (0.5 s);
#: the browser pad publishes every 40 ms, so this is a dozen lost messages in a row.
TOPIC_PAD_TIMEOUT_S = 0.5


class TopicPadInput:
    """The pad as the latest message made it, neutral and ``connected=False`` when there is none fresh."""

    def __init__(self, layout: Layout, timeout_s: float = TOPIC_PAD_TIMEOUT_S) -> None:
        if not timeout_s > 0.0:
            raise GamepadError(f"the topic pad's timeout_s is {timeout_s!r}: give a positive number of seconds, "
                               f"e.g. {TOPIC_PAD_TIMEOUT_S}")
        self.layout = layout
        self.timeout_s = float(timeout_s)
        self._state = PadState.neutral(connected=False)
        self._received_s: Optional[float] = None
        self.messages = 0

    def receive(self, axes: Sequence[float], buttons: Sequence[Union[int, bool]], now: float) -> None:
        """One message's raw axes and buttons (the layout's order) at ``now`` (a monotonic clock, s)."""
        self._state = self.layout.state_from_raw(list(axes), list(buttons))
        self._received_s = now
        self.messages += 1

    def fresh(self, now: float) -> bool:
        """Whether the latest message is at most ``timeout_s`` old at ``now``."""
        return self._received_s is not None and 0.0 <= now - self._received_s <= self.timeout_s

    def state(self, now: float) -> PadState:
        """The latest message's pad while it is fresh, else a released, unplugged pad."""
        return self._state if self.fresh(now) else PadState.neutral(connected=False)
