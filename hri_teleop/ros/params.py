"""What every hri_lab node does with its parameters and with bad input.

The lab's rule for bad input is one line naming the cause and the fix, exit status 1, never a
traceback; written once here, not slightly differently in each node. :func:`get_param` reads and
type-checks a parameter (:class:`ParamError`), :func:`fail` logs the line as fatal and exits 1, and
:func:`run_node` runs a node's main so that an ``HriTeleopError`` ends it through ``fail``, Ctrl-C
or rospy's shutdown ends it quietly with 0, and a bug keeps its traceback.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, NoReturn, Optional, Tuple, Union

import rosgraph.names
import rospkg
import rospy

from hri_teleop.core.checks import is_finite_number, is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.modes import HARDWARE_NODES
from hri_teleop.ros.master import started_here
from hri_teleop.ros.master_api import MasterApiError, master_uri, running_nodes
from hri_teleop.ros.stop_signals import finish_stop

_MISSING = object()

Kind = Union[type, Tuple[type, ...]]

# Node-script exit status for bad input (the shell and roslaunch show it).
EXIT_BAD_INPUT = 1


class ParamError(HriTeleopError, ValueError):
    """A ROS parameter is missing or has the wrong type."""


class NodeExit(SystemExit):
    """Raised by ``fail`` to end a node after its one fatal line has been logged."""


def _kind_name(kind: Kind) -> str:
    kinds = kind if isinstance(kind, tuple) else (kind,)
    names = {bool: "true/false", int: "an integer", float: "a number", str: "a string",
             dict: "a dictionary", list: "a list"}
    return " or ".join(names.get(k, k.__name__) for k in kinds)


def check_kind(name: str, value: Any, kind: Kind, fix: str = "") -> Any:
    """``value`` if it is of ``kind`` (an int counts as a float, a bool never as a number).

    Floats are returned as ``float``; a float that is not finite is refused.
    """
    kinds = kind if isinstance(kind, tuple) else (kind,)
    ok = False
    if isinstance(value, bool):
        ok = bool in kinds
    elif is_int(value):
        ok = int in kinds or float in kinds
        if ok and int not in kinds:
            value = float(value)
    elif isinstance(value, float):
        ok = float in kinds and is_finite_number(value)
    else:
        ok = isinstance(value, tuple(k for k in kinds if k not in (bool, int, float)))
    if not ok:
        hint = f"; {fix}" if fix else f"; set it to {_kind_name(kind)}"
        raise ParamError(f"parameter {name} is {value!r} ({type(value).__name__}), expected {_kind_name(kind)}{hint}")
    return value


def get_param(name: str, default: Any = _MISSING, *, kind: Optional[Kind] = None, fix: str = "") -> Any:
    """The parameter ``name`` (``~x`` private, ``/x`` global), checked against ``kind``.

    Missing and no default -> ``ParamError`` naming the parameter and ``fix`` (or a
    generic ``rosparam set`` hint). A default is returned as is (not type-checked).
    """
    if not rospy.has_param(name):
        if default is _MISSING:
            resolved = rospy.resolve_name(name)
            hint = fix or f"set it, e.g. `rosparam set {resolved} <value>` or in the launch file"
            raise ParamError(f"parameter {resolved} is not set; {hint}")
        return default
    value = rospy.get_param(name)
    if kind is not None:
        value = check_kind(rospy.resolve_name(name), value, kind, fix)
    return value


def get_name_param(name: str, default: str, *, namespace: bool = False) -> str:
    """The string parameter ``name`` (``~x``) as a ROS graph name: stripped, and with ``namespace`` its
    trailing ``/`` dropped; not a legal name -> :class:`ParamError` naming it and ``default`` as the example."""
    value = str(get_param(name, default, kind=str)).strip()
    if namespace:
        value = value.rstrip("/")
    if not value or not rosgraph.names.is_legal_name(value):
        raise ParamError(f"parameter {rospy.resolve_name(name)} is {value!r}, not a ROS name; use letters, digits, "
                         f"_ and /, e.g. {default}")
    return value


def private_params(exclude: Iterable[str] = ()) -> Dict[str, Any]:
    """All of this node's private parameters as a dict, minus the keys in ``exclude``."""
    values = rospy.get_param("~", {})
    if not isinstance(values, dict):
        return {}
    skip = set(exclude)
    return {k: v for k, v in values.items() if k not in skip}


def fail(message: str, exit_code: int = EXIT_BAD_INPUT) -> NoReturn:
    """Log ``message`` once as fatal and end the process with ``exit_code``.

    Call it from the main thread. From a callback thread use ``fail_from_callback``.
    """
    _log_fatal(message)
    raise NodeExit(exit_code)


def refuse_beside_hardware(what: str) -> None:
    """End this simulated node with one fatal line when its master runs real hardware it did not start.

    The notebooks never start a simulation on the lab's master; this is the node's own guard
    for a command typed there by hand (``roslaunch hri_lab teleoperation.launch sim:=true``).
    Masters the toolkit started (demos, tests, the grader: ``$HRI_OWN_MASTER``) are not refused.
    """
    uri = master_uri()
    if started_here(uri):
        return
    try:
        hardware = running_nodes(among=list(HARDWARE_NODES), uri=uri)
    except MasterApiError:
        return
    hardware = [name for name in hardware if name != rospy.get_name()]
    if hardware:
        fail(f"refused to start {what}: this master runs real hardware ({', '.join(hardware)}); a simulation "
             "beside it would publish on the real robot's and board's topics. Run it on a master of its own "
             "(at home: roscore in a fresh terminal, or make demo)")


def _log_fatal(message: str) -> None:
    line = " ".join(str(message).split("\n"))
    if rospy.core.is_initialized():
        rospy.logfatal(line)
        return
    print(f"[FATAL] {line}", file=sys.stderr, flush=True)


_exit_code: Optional[int] = None


def fail_from_callback(message: str, exit_code: int = EXIT_BAD_INPUT) -> None:
    """Like ``fail`` from a subscriber/timer thread: log, shut rospy down, remember the code.

    ``sys.exit`` in a callback thread would only end that thread; ``run_node`` returns the
    remembered code once rospy has shut down.
    """
    global _exit_code
    if _exit_code is None:
        _exit_code = exit_code
        _log_fatal(message)
    rospy.signal_shutdown(str(message))


def is_project_error(exc: BaseException) -> bool:
    """Errors raised on purpose by hri_teleop: they carry a one-line cause and fix."""
    return isinstance(exc, HriTeleopError)


def run_node(main: Callable[[], Optional[int]]) -> None:
    """Run ``main`` and exit: 0 on normal end, 1 (one fatal line) on bad input."""
    code: int = 0
    try:
        result = main()
        code = int(result or 0)
    except NodeExit as exc:
        code = int(exc.code if isinstance(exc.code, int) else EXIT_BAD_INPUT)
    except (KeyboardInterrupt, rospy.ROSInterruptException):
        code = 0
    except rospy.ROSException:
        # rospy closes the topics before it says it is shut down: a stop signal handled in a thread
        # (hri_teleop.ros.stop_signals) can close one under the loop's publish. That is the stop.
        if not rospy.core.is_shutdown_requested():
            raise
        code = 0
    except Exception as exc:
        if not is_project_error(exc):
            raise
        _log_fatal(str(exc))
        code = EXIT_BAD_INPUT
    if _exit_code is not None:
        code = _exit_code
    finish_stop()  # a shutdown a stop signal started in a thread ends before the process does
    if not rospy.is_shutdown():
        rospy.signal_shutdown("node finished")
    sys.exit(code)


def package_file(relative: str, script_file: str, package: str = "hri_lab") -> str:
    """A file of the ``hri_lab`` package, e.g. ``config/teleop.yaml`` ('' if not found).

    Why: a node's default config lives in its package; roslaunch runs the installed
    package (found with rospkg) and ``rosrun``/tests run the checkout, where the file sits
    beside the script's folder (``script_file`` is the node's ``__file__``).
    """
    candidates = []
    try:
        candidates.append(Path(rospkg.RosPack().get_path(package)) / relative)
    except Exception:  # noqa: BLE001 - rospkg.ResourceNotFound, or no ROS_PACKAGE_PATH
        pass
    candidates.append(Path(script_file).resolve().parents[1] / relative)
    for path in candidates:
        if path.is_file():
            return str(path)
    return ""
