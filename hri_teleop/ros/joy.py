"""A pad's state as sensor_msgs/Joy, in its layout's raw order: what /joy and ~virtual_joy carry.

The teleoperation node publishes the pad it reads on /joy, and widgets.BrowserPad drives the
node's ~virtual_joy; both write the same message from a layout and a state, so it is written here.
"""

from __future__ import annotations

from typing import Any

import rospy
from sensor_msgs.msg import Joy

from hri_teleop.core.gamepad.layout import Layout
from hri_teleop.core.gamepad.state import PadState

__all__ = ["joy_message"]


def joy_message(layout: Layout, state: PadState) -> Any:
    """``state`` as a Joy stamped now, its axes and buttons in ``layout``'s raw indices."""
    axes, buttons = layout.raw_from_state(state)
    msg = Joy(axes=[float(a) for a in axes], buttons=[int(b) for b in buttons])
    msg.header.stamp = rospy.Time.now()
    return msg
