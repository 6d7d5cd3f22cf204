"""ArmView: the Panda in 3D in a notebook (meshcat in an iframe, posed by pinocchio from the joints).

It shows one joint configuration, follows ``/joint_states`` live (drawn at most 30 times a second
on a :class:`~hri_teleop.course.widgets._base.Ticker`) or replays a trial's bag with a slider. The
meshcat server is the kernel's child (``ros.master.ManagedProcess``): stopped when the widget is
closed or the kernel exits. The URDF and meshes are example-robot-data's (``sim.kinematics``).
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import tempfile
import threading
import time
import warnings
from collections import deque
from functools import lru_cache
from pathlib import Path
from typing import Any, Deque, Dict, List, Optional, Sequence, Tuple, Union

import ipywidgets as widgets
import numpy as np
import numpy.typing as npt

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.joints import FINGER_JOINT_NAMES, JOINT_NAMES, READY_POSE_RAD
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.course.widgets._base import Ticker, WidgetError, message_html, replace_in_cell
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master import ManagedProcess

__all__ = ["ArmView", "ArmViewError", "MeshcatServer", "MeshcatWindow", "JOINT_STATES_TOPIC", "FINGER_JOINTS",
           "joint_config", "read_joint_states", "replay_frames", "ready_config", "live_status"]

JOINT_STATES_TOPIC = "/joint_states"
#: The Franka Hand's joints in joint_states: each finger moves half of the hand's opening.
FINGER_JOINTS = FINGER_JOINT_NAMES
#: Redraws per second at most (live and replay): what the lab's joint_states carry (30 Hz).
MAX_DRAW_HZ = 30.0
#: After this long without a joint state the widget says what to start.
SILENCE_S = 2.0
_ROOT = "panda"
_HAND_GEOMETRY = "panda_hand_0"
#: Where the camera is (m, base frame): front right, above; meshcat's camera looks at the base.
_CAMERA_M = (1.0, -0.8, 0.7)
Vector = npt.NDArray[np.float64]
BagSource = Union[str, Path, Any, Sequence[Any]]


class ArmViewError(WidgetError):
    """The 3D view cannot be built or drawn (one line: the cause and the fix)."""


# --------------------------------------------------------------------------- joints by name


def joint_config(names: Sequence[str], positions: Sequence[float], previous: npt.ArrayLike
                 ) -> Tuple[Vector, Tuple[str, ...]]:
    """The nine joints (seven of the arm, two fingers) of one joint_states message, taken by name.

    Joints the message lacks keep their ``previous`` value; the arm joints among them are
    returned as missing (the fingers are often published apart: franka_gripper's joint_states).
    One finger alone stands for both.
    """
    q = np.array(previous, dtype=float)
    if q.shape != (9,):
        raise ArmViewError(f"previous must hold 9 joint values (7 arm joints, 2 fingers), got {len(q)}")
    index = {str(name): i for i, name in enumerate(names)}
    missing = []
    for j, name in enumerate(JOINT_NAMES):
        i = index.get(name)
        if i is not None and i < len(positions) and math.isfinite(float(positions[i])):
            q[j] = float(positions[i])
        else:
            missing.append(name)
    fingers = [float(positions[index[n]]) for n in FINGER_JOINTS
               if n in index and index[n] < len(positions) and math.isfinite(float(positions[index[n]]))]
    if fingers:
        q[7:] = (fingers[0], fingers[-1])
    return q, tuple(missing)


def read_joint_states(bag_path: Union[str, Path], topic: str = JOINT_STATES_TOPIC
                      ) -> Tuple[Vector, Vector, Tuple[str, ...]]:
    """(times in s from the first message, joints (n, 9), arm joints missing in any message) of a bag's topic."""
    messages = read_topics(Path(bag_path), [topic])[topic]
    times = np.array([t for t, _msg in messages], dtype=float)
    q = np.empty((len(messages), 9))
    current = ready_config()
    missing: Dict[str, None] = {}
    for k, (_t, msg) in enumerate(messages):
        current, lacks = joint_config(msg.name, msg.position, current)
        q[k] = current
        missing.update(dict.fromkeys(lacks))
    return (times - times[0] if len(times) else times), q, tuple(missing)


def replay_frames(times_s: Vector, rate_hz: float = MAX_DRAW_HZ) -> npt.NDArray[np.intp]:
    """For frames ``rate_hz`` apart over the recording: the index of the newest message at each frame."""
    if len(times_s) == 0:
        return np.zeros(0, dtype=np.intp)
    steps = np.arange(0.0, float(times_s[-1]) + 0.5 / rate_hz, 1.0 / rate_hz)
    out: npt.NDArray[np.intp] = np.maximum(np.searchsorted(times_s, steps, side="right") - 1, 0)
    return out


def ready_config(width_m: float = GRIPPER_MAX_WIDTH_M) -> Vector:
    """The ready pose with the hand ``width_m`` open, as the nine joints of the description."""
    return np.array([*READY_POSE_RAD, width_m / 2.0, width_m / 2.0], dtype=float)


# --------------------------------------------------------------------------- the meshcat server and its client


class MeshcatServer:
    """meshcat's server as a child process (:mod:`._meshcat_server`); :meth:`stop` ends it.

    A :class:`~hri_teleop.ros.master.ManagedProcess`: in a session of its own (a kernel
    interrupt does not reach it) and stopped at the kernel's exit with the nodes; it ends by
    itself when the kernel dies without its exit hooks.
    """

    def __init__(self, timeout_s: float = 20.0) -> None:
        self._folder = Path(tempfile.mkdtemp(prefix="hri-meshcat-"))
        # The file, not -m: no package import (0.6 s); -I: its folder's modules on no path.
        self.process = ManagedProcess([sys.executable, "-I", "-u", str(Path(__file__).with_name("_meshcat_server.py"))],
                                      dict(os.environ), self._folder / "meshcat.log")
        self.zmq_url = self.web_url = ""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline and self.process.running:
            lines = dict(line.split("=", 1) for line in self.process.output().splitlines()
                         if line.startswith(("zmq_url=", "web_url=")))
            if "web_url" in lines:
                self.zmq_url, self.web_url = lines["zmq_url"], lines["web_url"]
                return
            time.sleep(0.02)
        last = (self.process.output().strip().splitlines() or ["no output"])[-1]
        self.stop()
        raise ArmViewError(f"the 3D view's meshcat server did not start within {timeout_s:.0f} s ({last}); "
                           "check that meshcat is installed (`make setup`) and run the cell again")

    @property
    def running(self) -> bool:
        return self.process.running

    def stop(self) -> None:
        self.process.stop(timeout_s=3.0)
        shutil.rmtree(self._folder, ignore_errors=True)


class MeshcatWindow:
    """meshcat's client end (what ``meshcat.Visualizer`` sends through), with timeouts and a record.

    ``transforms`` holds the last matrix sent to each path and ``objects`` every path an
    object was set at: what the view drew, readable without a browser. One lock: the
    kernel's thread and a ticker thread (outside a kernel) may both draw.
    """

    def __init__(self, zmq_url: str, web_url: str, timeout_s: float = 5.0) -> None:
        import zmq  # noqa: PLC0415 - with meshcat, only when a 3D view is built

        self.zmq_url, self.web_url = zmq_url, web_url
        self._zmq = zmq
        self._timeout_ms = int(timeout_s * 1000)
        self._context = zmq.Context()
        self._socket: Any = self._context.socket(zmq.REQ)
        for option, value in ((zmq.LINGER, 0), (zmq.RCVTIMEO, self._timeout_ms), (zmq.SNDTIMEO, self._timeout_ms)):
            self._socket.setsockopt(option, value)
        self._socket.connect(zmq_url)
        self._lock = threading.Lock()
        self.problem = ""
        self.transforms: Dict[str, Vector] = {}
        self.objects: List[str] = []
        self.sent = 0

    def send(self, command: Any) -> None:
        import umsgpack  # type: ignore[import-untyped]  # noqa: PLC0415 - meshcat's own dependency, as zmq

        data = command.lower()
        with self._lock:
            if self._socket is None:
                raise ArmViewError(self.problem or "the 3D view is closed; make a new one: widgets.ArmView()")
            try:
                self._socket.send_multipart([data["type"].encode(), data["path"].encode(), umsgpack.packb(data)])
                self._socket.recv()
            except self._zmq.ZMQError as exc:  # zmq.Again: the server did not answer in time
                self.problem = (f"the 3D view's meshcat server stopped answering ({exc}); run the cell again "
                                "for a new view")
                self._close_socket()
                raise ArmViewError(self.problem) from None
            self.sent += 1
        if data["type"] == "set_transform":
            self.transforms[data["path"]] = np.array(data["matrix"], dtype=float).reshape(4, 4).T
        elif data["type"] == "set_object":
            self.objects.append(data["path"])

    def _close_socket(self) -> None:
        if self._socket is not None:
            self._socket.close(linger=0)
            self._socket = None
        self._context.term()

    def close(self) -> None:
        with self._lock:
            if self._socket is not None:
                self._close_socket()


@lru_cache(maxsize=1)
def _panda_models() -> Tuple[Any, Any]:
    """The Panda's model (nine joints) and visual geometry from example-robot-data: parsed once per kernel."""
    import pinocchio as pin  # noqa: PLC0415 - pinocchio (0.2 s) only when a 3D view is built

    from hri_teleop.sim.kinematics import panda_package_dir, panda_urdf  # noqa: PLC0415 - imports pinocchio

    urdf = str(panda_urdf())
    try:
        model = pin.buildModelFromUrdf(urdf)
        visual = pin.buildGeomFromUrdf(model, urdf, pin.GeometryType.VISUAL, package_dirs=[str(panda_package_dir())])
    except (RuntimeError, ValueError) as exc:
        raise ArmViewError(f"pinocchio cannot read the Panda's URDF or meshes ({exc}); reinstall "
                           "example-robot-data with `make setup`") from None
    return model, visual


# --------------------------------------------------------------------------- the widget


class ArmView(widgets.VBox):
    """The Panda in 3D: :meth:`show` a configuration, follow :meth:`live` joint states, :meth:`replay` a bag.

    Starts at the ready pose with the hand open. Without pinocchio, meshcat or a free port
    it is one line saying what is missing. ``view.window.transforms`` holds what was last
    sent for each link; :meth:`close` stops the live view and the meshcat server.
    """

    def __init__(self, q: Sequence[float] = READY_POSE_RAD, *, width_m: float = GRIPPER_MAX_WIDTH_M,
                 height_px: int = 420) -> None:
        started = time.monotonic()
        self.status = widgets.HTML()
        self.frame = widgets.HTML()
        self.play = widgets.Play(min=0, max=0, step=1, interval=int(1000 / MAX_DRAW_HZ), description="play")
        self.slider = widgets.IntSlider(min=0, max=0, description="frame", continuous_update=True,
                                        layout=widgets.Layout(width="60%"))
        self.clock = widgets.Label()
        self.trial = widgets.Dropdown(description="trial", layout=widgets.Layout(width="60%"))
        widgets.jslink((self.play, "value"), (self.slider, "value"))
        self.controls = widgets.VBox([self.trial, widgets.HBox([self.play, self.slider, self.clock])],
                                     layout=widgets.Layout(display="none"))
        super().__init__([self.status, self.frame, self.controls])
        self.q = ready_config(width_m)
        self.server: Optional[MeshcatServer] = None
        self.window: Optional[MeshcatWindow] = None
        self._viz: Any = None
        self._tcp_frame = -1
        self._lock = threading.Lock()
        self._latest: Optional[Tuple[float, Sequence[str], Sequence[float]]] = None
        self._received = 0
        self._drawn_seq = 0
        self._receive_times: Deque[float] = deque(maxlen=200)
        self._draw_times: Deque[float] = deque(maxlen=200)
        self._subscriber: Any = None
        self._topic = JOINT_STATES_TOPIC
        self._live_since = 0.0
        self._missing: Tuple[str, ...] = ()
        self._shown_status = 0.0
        # A thread, not the kernel's loop: the view moves on while a cell waits (node.wait()); it
        # touches only this widget's state, under _draw_lock, and meshcat's socket, under the window's.
        self._ticker = Ticker(self.tick, 1.0 / MAX_DRAW_HZ, name="arm view", thread=True)
        self._draw_lock = threading.RLock()
        self._replay: Optional[Tuple[Vector, Vector, npt.NDArray[np.intp]]] = None
        self._bags: Dict[str, Path] = {}
        self.slider.observe(self._on_frame, "value")
        self.trial.observe(self._on_trial, "value")
        try:
            self._build(height_px)
        except (HriTeleopError, ImportError, OSError) as exc:  # ArmViewError, MasterError, KinematicsError
            self._fail(_one_line(exc))
        self.build_s = time.monotonic() - started
        replace_in_cell(self)
        if self._viz is not None:
            self.show(q, width_m=width_m)
            self._say(f"the Panda ({len(self.window.objects) if self.window else 0} links); 3D view at "
                      f"{self.server.web_url if self.server else ''} (drag to turn, scroll to zoom)")

    # -- building and closing

    def _build(self, height_px: int) -> None:
        try:
            with warnings.catch_warnings():  # meshcat's server module imports a deprecated zmq.eventloop
                warnings.simplefilter("ignore", DeprecationWarning)
                import meshcat  # noqa: PLC0415 - meshcat and pinocchio only when a 3D view is built
                from pinocchio.visualize import MeshcatVisualizer  # noqa: PLC0415 - as meshcat
        except ImportError as exc:
            raise ArmViewError(f"the 3D view needs pinocchio and meshcat ({exc}); run `make setup` "
                               "(or pip install pin meshcat example-robot-data)") from None
        self.server = MeshcatServer()  # starts while the URDF is parsed
        model, visual = _panda_models()
        self.window = MeshcatWindow(self.server.zmq_url, self.server.web_url)
        viewer = meshcat.Visualizer(window=self.window)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            self._viz = MeshcatVisualizer(model, None, visual)
            self._viz.initViewer(viewer=viewer)
            self._viz.loadViewerModel(rootNodeName=_ROOT)
        if not self.window.objects:  # pinocchio warns instead of raising when a mesh does not load
            reason = str(caught[0].message).replace("\n", " ") if caught else "no link was sent"
            raise ArmViewError(f"the Panda's meshes did not load into the 3D view ({reason}); reinstall "
                               "example-robot-data with `make setup`")
        from hri_teleop.sim.kinematics import TCP_FRAME  # noqa: PLC0415 - pinocchio is loaded by now

        self._tcp_frame = model.getFrameId(TCP_FRAME)
        x, y, z = _CAMERA_M
        viewer["/Cameras/default/rotated/<object>"].set_property("position", [x, z, -y])  # three.js: y up
        self.frame.value = (f'<iframe src="{self.server.web_url}" title="3D view of the Panda" '
                            f'style="width: 100%; height: {int(height_px)}px; border: none"></iframe>')

    def _fail(self, line: str) -> None:
        self._viz = None
        self._shut_down()
        self.frame.value = ""
        self._say(line, error=True)

    def _shut_down(self) -> None:
        self.stop()
        if self.window is not None:
            self.window.close()
        if self.server is not None:
            self.server.stop()

    def close(self) -> None:
        """Stop following, unsubscribe, stop the meshcat server; the widget disappears."""
        self._shut_down()
        super().close()

    # -- drawing

    @property
    def drawn(self) -> bool:
        """True while the 3D view works (built and its server answering)."""
        return self._viz is not None

    def show(self, q: Sequence[float], width_m: Optional[float] = None) -> "ArmView":
        """Draw the arm at the seven joint angles ``q`` (rad), the hand ``width_m`` open (default: as it is)."""
        values = [float(v) for v in q] if isinstance(q, (list, tuple, np.ndarray)) else []
        if len(values) != 7 or not all(math.isfinite(v) for v in values):
            raise ArmViewError(f"show() needs the 7 joint angles of the arm in rad, got {q!r}; e.g. "
                               "widgets.ArmView().show(READY_POSE_RAD)")
        config = self.q.copy()
        config[:7] = values
        if width_m is not None:
            if not (math.isfinite(float(width_m)) and 0.0 <= float(width_m) <= GRIPPER_MAX_WIDTH_M + 1e-9):
                raise ArmViewError(f"width_m must be 0 .. {GRIPPER_MAX_WIDTH_M} m (the Franka Hand), got {width_m!r}")
            config[7:] = float(width_m) / 2.0
        self._draw(config)
        return self

    def _draw(self, config: Vector) -> None:
        with self._draw_lock:
            self.q = np.asarray(config, dtype=float)
            if self._viz is None:
                return
            try:
                self._viz.display(self.q)
            except ArmViewError as exc:
                self._fail(str(exc))
                return
            self._draw_times.append(time.monotonic())

    def hand_position_m(self) -> Tuple[float, float, float]:
        """Where forward kinematics puts the hand's TCP (between the fingertips) in the drawn pose, in m."""
        import pinocchio as pin  # noqa: PLC0415 - loaded already when a view was built

        with self._draw_lock:
            if self._viz is None:
                raise ArmViewError("the 3D view is not drawn (see its line); fix that first")
            pin.updateFramePlacement(self._viz.model, self._viz.data, self._tcp_frame)
            p = self._viz.data.oMf[self._tcp_frame].translation
            return float(p[0]), float(p[1]), float(p[2])

    def hand_transform(self) -> Vector:
        """The 4 x 4 transform last sent to meshcat for the hand (identity before the first draw)."""
        if self.window is None:
            return np.eye(4)
        path = f"/meshcat/{_ROOT}/visuals/{_HAND_GEOMETRY}"
        return self.window.transforms.get(path, np.eye(4))

    def draw_rate_hz(self, span_s: float = 1.0) -> float:
        """Redraws per second over the last ``span_s`` seconds."""
        return _rate(self._draw_times, span_s)

    def _say(self, line: str, error: bool = False) -> None:
        value = message_html(line, error)
        if self.status.value != value:
            self.status.value = value

    # -- live

    def live(self, topic: str = JOINT_STATES_TOPIC, session: Any = None) -> "ArmView":
        """Follow ``topic`` (sensor_msgs/JointState) through the kernel's ROS node; returns the view."""
        self.stop()
        if self._viz is None:
            return self
        session = session if session is not None else ensure_ros(quiet=True)
        if not session:
            self._say(session.problem, error=True)
            return self
        import rospy  # noqa: PLC0415 - only ROS cells need it
        from sensor_msgs.msg import JointState  # noqa: PLC0415 - as rospy

        self._topic = topic
        with self._lock:
            self._latest, self._received, self._drawn_seq = None, 0, 0
        self._receive_times.clear()
        self._live_since = time.monotonic()
        self._subscriber = rospy.Subscriber(topic, JointState, self.on_joint_state, queue_size=1, tcp_nodelay=True)
        self._say(f"waiting for {topic} ...")
        self._ticker.start()
        return self

    def on_joint_state(self, msg: Any) -> None:
        """The subscriber's callback (rospy's receive thread): keeps the newest message; :meth:`tick` draws it."""
        now = time.monotonic()
        with self._lock:
            self._latest = (now, msg.name, msg.position)
            self._received += 1
            self._receive_times.append(now)

    def tick(self) -> None:
        """Draw the newest joint state if a new one arrived; refresh the line twice a second (the ticker's call)."""
        with self._lock:
            latest, seq = self._latest, self._received
        now = time.monotonic()
        if latest is not None and seq != self._drawn_seq:
            self._drawn_seq = seq
            config, self._missing = joint_config(latest[1], latest[2], self.q)
            self._draw(config)
        subscriber = self._subscriber
        if self._viz is None or now - self._shown_status < 0.5:
            return
        self._shown_status = now
        try:
            hand = self.hand_position_m()
        except ArmViewError:
            return  # closed meanwhile: the line says why
        self._say(*live_status(
            self._topic, now - self._live_since, None if latest is None else now - latest[0],
            subscriber.get_num_connections() if subscriber is not None else 0, self._missing,
            _rate(self._receive_times, 1.0, now), self.draw_rate_hz(), hand))

    def stop(self) -> None:
        """Stop following live joint states and playing a replay (the view stays)."""
        self._ticker.stop()
        if self._subscriber is not None:
            self._subscriber.unregister()
            self._subscriber = None
        self.play.playing = False

    # -- replay

    def replay(self, source: BagSource, topic: str = JOINT_STATES_TOPIC) -> "ArmView":
        """Replay a recorded trial: a bag's path, a trial of ``experiment`` (its sidecar), or a list of them."""
        self.stop()
        if self._viz is None:
            return self
        self._topic = topic
        self._bags = _bags(source)
        self.controls.layout.display = ""
        self.trial.layout.display = "" if len(self._bags) > 1 else "none"
        if not self._bags:
            self.controls.layout.display = "none"
            what = "no trials to replay yet" if isinstance(source, (list, tuple)) else f"nothing to replay in {source}"
            self._say(f"{what}: record or rehearse a trial first, or give a trial's bag", error=True)
            return self
        names = list(self._bags)
        self.trial.unobserve(self._on_trial, "value")
        self.trial.options = names
        self.trial.value = names[0]
        self.trial.observe(self._on_trial, "value")
        self._load(names[0])
        return self

    def _on_trial(self, change: Dict[str, Any]) -> None:
        if change.get("new"):
            self._load(str(change["new"]))

    def _load(self, name: str) -> None:
        path = self._bags[name]
        self.play.playing = False
        try:
            times, q, missing = read_joint_states(path, self._topic)
        except (HriTeleopError, ImportError) as exc:
            self._replay = None
            self._set_frames(0)
            self._say(_one_line(exc), error=True)
            return
        if len(times) == 0:
            self._replay = None
            self._set_frames(0)
            self._say(f"{path.name}: no {self._topic} in this bag (recorded before trials kept the joints?); "
                      "record the trial again to replay the arm", error=True)
            return
        frames = replay_frames(times)
        self._replay = (times, q, frames)
        self._set_frames(len(frames))
        self._show_frame(0)
        lacks = f"; it lacks {', '.join(missing)} (drawn at the ready pose)" if missing else ""
        self._say(f"{path.name}: {len(times)} joint states over {times[-1]:.1f} s; press play or drag the "
                  f"slider{lacks}", error=bool(missing))

    def _set_frames(self, n: int) -> None:
        self.slider.value = 0
        self.slider.max = max(0, n - 1)
        self.play.max = max(0, n - 1)
        self.clock.value = ""

    def _on_frame(self, change: Dict[str, Any]) -> None:
        self._show_frame(int(change["new"]))

    def _show_frame(self, frame: int) -> None:
        if self._replay is None:
            return
        times, q, frames = self._replay
        k = int(frames[min(max(frame, 0), len(frames) - 1)])
        self._draw(q[k])
        self.clock.value = f"{min(frame / MAX_DRAW_HZ, float(times[-1])):.1f} / {times[-1]:.1f} s"


def live_status(topic: str, waited_s: float, age_s: Optional[float], publishers: int, missing: Sequence[str],
                received_hz: float, drawn_hz: float, hand_m: Sequence[float]) -> Tuple[str, bool]:
    """The live view's one line (and whether it is a problem): silence says what to start, else the rates.

    ``waited_s``: since the subscription; ``age_s``: of the newest message (None: none yet).
    """
    if age_s is None:
        if waited_s < SILENCE_S:
            return f"waiting for {topic} ...", False
        if publishers:
            return f"{topic}: a publisher is connected but nothing arrived in {waited_s:.0f} s; is it paused?", True
        return (f"nothing on {topic} for {waited_s:.0f} s: start the robot (at home lab.start_robot(), in the lab "
                "franka_control); the view follows as soon as joints arrive"), True
    if age_s > SILENCE_S:
        return f"{topic} silent for {age_s:.0f} s (the robot's node stopped?); the arm stays where it was last", True
    if missing:
        return f"{topic} lacks {', '.join(missing)}: drawn at their last angles; is it the Panda's joint_states?", True
    x, y, z = hand_m
    return (f"live {topic}: {received_hz:.0f} Hz received, {drawn_hz:.0f} Hz drawn; hand at ({x:.3f}, {y:.3f}, "
            f"{z:.3f}) m"), False


def _rate(times: Deque[float], span_s: float, now: Optional[float] = None) -> float:
    now = time.monotonic() if now is None else now
    return sum(1 for t in list(times) if t > now - span_s) / span_s


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _bags(source: BagSource) -> Dict[str, Path]:
    """Bags by label: a path (a bag, a trial's sidecar, a folder of trials), a trial (``.sidecar``), or a list."""
    items: List[Any] = list(source) if isinstance(source, (list, tuple)) else [source]
    found: Dict[str, Path] = {}
    for item in items:
        sidecar = getattr(item, "sidecar", None)
        path = Path(sidecar if sidecar is not None else item)
        if path.is_dir():
            found.update({bag.name: bag for bag in sorted(path.glob("*.bag"))})
            continue
        if path.suffix in (".yaml", ".yml"):
            path = path.with_suffix(".bag")
        meta = getattr(item, "meta", None)
        label = f"{path.name}: {meta.label}" if meta is not None and hasattr(meta, "label") else path.name
        found[label] = path
    return found
