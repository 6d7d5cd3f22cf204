"""The student API: everything a student's file of the lab imports from the toolkit, in one place.

Write ``from hri_teleop.student import ...`` and only that: the names below stay where they are for a
whole major version of the student API (API_VERSION), whatever moves inside the toolkit. A name that
is renamed or withdrawn keeps working, with a DeprecationWarning naming its replacement, until the
next major version. Policy and changes: docs/student-api.md. Importing this module loads neither
rospy nor pygame; the ROS helpers are imported the first time a file asks for them.

Student API 1.2. Each name, what it is for, and the version it appeared in:

The gamepad (teleoperation.py, the handout *Task 4: Teleoperation*, Ex. 8-9)
  PadState                1.0  one snapshot of the pad: sticks and buttons by position; PadState.neutral()
  pad_events              1.0  the events between two snapshots, as the handout's pygame events
  JOYAXISMOTION           1.0  event type: a stick or trigger moved (event.axis, event.value)
  JOYBUTTONDOWN           1.0  event type: a button was pressed (event.button: south, east, west, north ...)
  JOYBUTTONUP             1.0  event type: a button was released
  normalize_analog_input  1.0  the dead-zone filter of the handout's Figure 8: (value, deadzone) -> -1..1
  open_gamepad            1.0  opens the pad: "pygame" (the lab's) or "virtual" (scripted, at home and in grading);
                               "browser" (the gamepad of the notebook's page, docs/browser-pad.md)
  TwistLimiter            1.0  ramps every twist inside the Franka's limits: step(target, dt_s) -> twist

The sensor (FSR_sensor.py)
  ADC_MAX_COUNT           1.0  1023, the largest count of the Arduino's 10-bit ADC
  FSR_SENSOR_RATE_HZ      1.0  FSR_sensor.py's publish rate when ~rate_hz is not set, Hz
  press_profile_count     1.0  the count of a simulated press of the piston at time t_s

The gripper (gripper_manager.py)
  GoalThrottle            1.0  decides which /gripper_width targets become gripper goals
  usable_width_m          1.0  a width target as the hand may be sent it (None if not a number), and why not
  MoveAction              1.0  franka_gripper's move action (for actionlib.SimpleActionClient)
  MoveGoal                1.0  franka_gripper's move goal: width (m) and speed (m/s)
  goal_status_name        1.1  actionlib's name of a goal status (SUCCEEDED, ABORTED, ...) for a log line
  GRIPPER_MAX_WIDTH_M     1.2  the hand's width fully open, m, from the lab's robot profile (0.08: the Franka Hand)

The provided nodes (parameters, errors, time)
  get_param               1.0  a ROS parameter read and type-checked; a bad one ends the node with the fix
  fail                    1.0  logs one fatal line (the cause and the fix) and ends the node with status 1
  run_node                1.0  runs a node's main: bad input -> one line and status 1, Ctrl-C -> quietly 0
  refuse_beside_hardware  1.0  a simulated node refuses to start on a master that runs the lab's hardware
  NodeClock               1.0  the node's time in s: the wall clock, or /clock when the grader owns time
  ClockError              1.0  /use_sim_time is set but nothing publishes /clock
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Dict, List, Tuple

from hri_teleop.core.checks import ADC_MAX_COUNT
from hri_teleop.core.gamepad.deadzone import normalize_analog_input
from hri_teleop.core.gamepad.events import JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP, pad_events
from hri_teleop.core.gamepad.state import PadState
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M, GoalThrottle, usable_width_m
from hri_teleop.core.limits import TwistLimiter
from hri_teleop.hardware.gamepad import open_gamepad
from hri_teleop.sim.sensor_profile import FSR_SENSOR_RATE_HZ, press_profile_count
from hri_teleop.student.deprecation import importer_stacklevel, removed_in

if TYPE_CHECKING:  # imported when first asked for (__getattr__ below): their modules import rospy
    from hri_teleop.ros.clock import ClockError, NodeClock
    from hri_teleop.ros.error_recovery import status_name as goal_status_name
    from hri_teleop.ros.franka_gripper_msgs import MoveAction, MoveGoal
    from hri_teleop.ros.params import fail, get_param, refuse_beside_hardware, run_node

#: The student API's version: the minor grows when a name is added or deprecated, the major when one goes.
API_VERSION = "1.2"
__version__ = API_VERSION

__all__ = [
    "PadState", "pad_events", "JOYAXISMOTION", "JOYBUTTONDOWN", "JOYBUTTONUP", "normalize_analog_input",
    "open_gamepad", "TwistLimiter",
    "ADC_MAX_COUNT", "FSR_SENSOR_RATE_HZ", "press_profile_count",
    "GoalThrottle", "usable_width_m", "MoveAction", "MoveGoal", "goal_status_name", "GRIPPER_MAX_WIDTH_M",
    "get_param", "fail", "run_node", "refuse_beside_hardware", "NodeClock", "ClockError",
]

#: Renamed or withdrawn names: old name -> (the name to use instead, the API version that deprecated it).
#: They keep working, with one DeprecationWarning, until the next major version (docs/student-api.md).
DEPRECATED: Dict[str, Tuple[str, str]] = {}

_CLOCK = ("ClockError", "NodeClock")
_GRIPPER_MSGS = ("MoveAction", "MoveGoal")
_STATUS = ("goal_status_name",)
_PARAMS = ("fail", "get_param", "refuse_beside_hardware", "run_node")


def _ros_name(name: str) -> Any:
    """A name whose home imports rospy, imported the first time a file asks for it."""
    if name in _CLOCK:
        from hri_teleop.ros import clock  # noqa: PLC0415 - rospy only once a file asks for a ROS helper
        return getattr(clock, name)
    if name in _STATUS:
        from hri_teleop.ros.error_recovery import status_name  # noqa: PLC0415 - imports actionlib and rospy
        return status_name
    if name in _GRIPPER_MSGS:
        from hri_teleop.ros import franka_gripper_msgs  # noqa: PLC0415 - the action classes are generated on import
        return getattr(franka_gripper_msgs, name)
    from hri_teleop.ros import params  # noqa: PLC0415 - rospy only once a file asks for a ROS helper
    return getattr(params, name)


def __getattr__(name: str) -> Any:
    if name in _CLOCK + _GRIPPER_MSGS + _STATUS + _PARAMS:
        value = _ros_name(name)
        globals()[name] = value
        return value
    if name in DEPRECATED:
        new, since = DEPRECATED[name]
        warnings.warn(f"hri_teleop.student.{name} is deprecated since student API {since}: write "
                      f"'from hri_teleop.student import {new}' instead; it goes in {removed_in(since)}",
                      DeprecationWarning, stacklevel=importer_stacklevel([__name__]))
        return globals()[new] if new in globals() else __getattr__(new)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> List[str]:
    return sorted(set(globals()) | set(__all__) | set(DEPRECATED))
