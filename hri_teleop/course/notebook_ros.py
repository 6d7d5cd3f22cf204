"""ROS inside a Jupyter kernel: one node per kernel, and a private roscore when none is reachable.

:func:`ensure_ros` initialises rospy once per kernel (a re-run cell gets the same session),
starts a private roscore at home and points the kernel's ``ROS_MASTER_URI`` at it (so ``!rostopic``
in a cell sees it too), and stops it with the kernel. Without rospy it says what to install and
returns a false session, so the ROS-free widgets keep working.
"""

from __future__ import annotations

import atexit
import os
import sys
import weakref
from dataclasses import dataclass, field
from typing import Any, List, Optional

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.modes import LAB, ModeError, ignored_setting, mode_from_env
from hri_teleop.core.modes import describe as describe_mode
from hri_teleop.course.master_mode import master_mode
from hri_teleop.ros.master import OWN_MASTER_ENV, MasterError, PrivateMaster, interrupt_nodes, stop_all
from hri_teleop.ros.master_api import master_reachable, master_uri

__all__ = ["NotebookRosError", "NO_ROSPY_MESSAGE", "RosSession", "ensure_ros", "current_session"]

#: What a kernel without rospy prints (one line: the cause and the fix).
NO_ROSPY_MESSAGE = "rospy is not installed: run `make setup` or install ROS Noetic (see README)"


class NotebookRosError(HriTeleopError, RuntimeError):
    """ROS is not usable in this kernel (one line: the cause and the fix)."""


@dataclass
class RosSession:
    """The kernel's ROS connection; false (``bool(session)``) when ROS is not usable.

    ``problem`` is the one-line reason when it is not; ``started_master`` says whether
    this kernel started (and will stop) the roscore at ``master_uri``.
    """

    available: bool
    problem: str = ""
    master_uri: str = ""
    node_name: str = ""
    started_master: bool = False
    mode: str = "home"
    _master: Any = field(default=None, repr=False, compare=False)

    def __bool__(self) -> bool:
        return self.available

    def describe(self) -> str:
        """One line for the notebook: where the node runs, or why ROS is not available."""
        if not self.available:
            return f"ROS: {self.problem}"
        if self.started_master:
            return (f"ROS ({self.mode} mode): node {self.node_name} on a private roscore at {self.master_uri} (it "
                    f"stops with the kernel); in a terminal: export ROS_MASTER_URI={self.master_uri}")
        return (f"ROS: node {self.node_name} on the master at {self.master_uri}, not started by this notebook; "
                f"{describe_mode(self.mode, own_master=False)}")


_SESSION: Optional[RosSession] = None
_FINALIZERS: List[Any] = []


def current_session() -> Optional[RosSession]:
    """The session :func:`ensure_ros` made in this kernel, or None before the first success."""
    return _SESSION


def _import_rospy() -> Any:
    try:
        import rospy  # noqa: PLC0415 - deliberately lazy: ROS-free notebooks must not need it
    except ImportError:
        if os.path.exists("/opt/ros/noetic/setup.sh"):  # the lab PCs: ROS is there, the kernel lacks its shell
            raise NotebookRosError("rospy is not importable in this kernel: pick the kernel 'Python 3 (hri-teleop, "
                                   "ROS)' (`make lab` registers it) or source /opt/ros/noetic/setup.bash before "
                                   "starting Jupyter") from None
        raise NotebookRosError(NO_ROSPY_MESSAGE) from None
    return rospy


def _stop_master(master: Any) -> None:
    try:
        master.stop()
    except Exception:  # noqa: BLE001 - at exit there is nobody left to tell
        pass


def _shutdown_at_exit() -> None:
    """Kernel stops: the nodes it started side by side, then the roscore it started, killed.

    The nodes get their SIGINT first and shut down while rospy does (0.6 s: it waits for
    its XML-RPC server's poll), with the master still up for the kernel's node to unregister.
    Registered once rospy is imported (see _start), so it runs before rospy's own exit hook
    and ros.master's. A notebook restart or nbgrader's next notebook waits for this:
    about 0.7 s, 2.2 s when everything was stopped cleanly one after another.
    """
    interrupt_nodes()
    rospy = sys.modules.get("rospy")
    if rospy is not None and _SESSION is not None and _SESSION.available:
        try:
            rospy.signal_shutdown("kernel stopped")
        except Exception:  # noqa: BLE001 - stopping anyway: the nodes below still stop
            pass
    stop_all()
    for finalizer in list(_FINALIZERS):
        # detach(), not finalizer(): once weakref's own exit hook has run, calling a finalizer does nothing
        info = finalizer.detach()
        if info is not None:
            _, func, args, _kwargs = info
            func(*args)  # the master is stopped already: this removes its folder


def _start(node_name: str, anonymous: bool, start_master: bool, timeout_s: float) -> RosSession:
    try:
        mode = mode_from_env(os.environ)
    except ModeError as exc:
        raise NotebookRosError(str(exc)) from None
    rospy = _import_rospy()
    if rospy.core.is_initialized():
        # Somebody (a student's cell) already called rospy.init_node: use that node.
        return RosSession(True, master_uri=master_uri(), node_name=rospy.get_name(), mode=master_mode().mode)
    uri = master_uri()
    master = None
    if not master_reachable(uri):
        if mode == LAB:
            # In the lab a private roscore would leave the student's nodes away from the robot.
            raise NotebookRosError(f"lab mode: no ROS master at {uri}: start the lab's roscore/launch first "
                                   "(at home, set HRI_MODE=home)")
        if not start_master:
            raise NotebookRosError(f"no ROS master at {uri}: start roscore (or the lab's launch file) in a "
                                   "terminal, or call ensure_ros(start_master=True)")
        master = PrivateMaster(base_env=os.environ)
        try:
            master.start(timeout_s=timeout_s)
        except MasterError as exc:
            raise NotebookRosError(f"could not start a private roscore: {exc}") from None
        uri = master.uri
        os.environ["ROS_MASTER_URI"] = uri
        os.environ[OWN_MASTER_ENV] = master.env[OWN_MASTER_ENV]  # this kernel's children know it is its own
        os.environ.setdefault("ROS_LOG_DIR", master.env["ROS_LOG_DIR"])
    if not (os.environ.get("ROS_HOSTNAME") or os.environ.get("ROS_IP")):
        os.environ["ROS_HOSTNAME"] = "127.0.0.1"  # as tools/env.sh: works without a resolvable hostname
    try:
        rospy.init_node(node_name, anonymous=anonymous, disable_signals=True)
    except Exception as exc:  # noqa: BLE001 - rospy.ROSException, ROSInitException, socket errors
        if master is not None:
            _stop_master(master)
        raise NotebookRosError(f"rospy.init_node({node_name!r}) failed: {exc}".replace("\n", " ")) from None
    state = master_mode(uri)
    note = ignored_setting(os.environ, state.own)
    if note:
        print(note)
    session = RosSession(True, master_uri=uri, node_name=rospy.get_name(), started_master=master is not None,
                         mode=state.mode, _master=master)
    if master is not None:
        finalizer = weakref.finalize(session, _stop_master, master)
        finalizer.atexit = False  # at exit _shutdown_at_exit stops it, after rospy's last log line
        _FINALIZERS.append(finalizer)
    return session


def ensure_ros(node_name: str = "hri_notebook", *, anonymous: bool = True, start_master: bool = True,
               required: bool = False, quiet: bool = False, timeout_s: float = 20.0) -> RosSession:
    """This kernel's ROS node, created on the first call and returned again on every later one.

    * A master reachable at ``$ROS_MASTER_URI`` (the lab's launch, a roscore in a terminal)
      is used; otherwise, with ``start_master``, a private roscore is started on a free
      port and ``ROS_MASTER_URI`` of this kernel points at it until the kernel stops.
    * rospy is initialised once (``anonymous`` appends a unique suffix to ``node_name``);
      later calls return the same session, whatever their arguments.
    * Without rospy, roscore or a master, it prints one line (the cause and the fix) and
      returns a false session -- or raises :class:`NotebookRosError` with ``required=True``.

    ``quiet`` suppresses the one-line report.
    """
    global _SESSION
    if _SESSION is not None:
        return _SESSION
    try:
        session = _start(node_name, anonymous, start_master, timeout_s)
    except NotebookRosError as exc:
        if required:
            raise
        failed = RosSession(False, problem=str(exc))
        if not quiet:
            print(failed.describe(), file=sys.stderr)
        return failed
    _SESSION = session
    # After rospy's exit hook and ros.master's (its private roscore started first), so it runs before both.
    atexit.unregister(_shutdown_at_exit)
    atexit.register(_shutdown_at_exit)
    if not quiet:
        print(session.describe())
    return session
