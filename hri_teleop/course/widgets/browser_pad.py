"""A gamepad read by the browser drives the teleoperation node (widgets.BrowserPad): in a container, on a server.

Such a kernel (the course's container on macOS or Windows, JupyterHub, the lab PC reached from a laptop)
cannot open a pad plugged into the laptop, but the page can (the Gamepad API). The page (browser_pad.js) sends
the pad 25 times a second; the kernel publishes it on the node's ``~virtual_joy``, where the student's node with
pad ``"browser"`` (``hri_teleop.hardware.joy_pad``) or the lab's with pad:=virtual reads it, released once the page
falls silent (:class:`~hri_teleop.core.gamepad.browser.BrowserInput`); the node's ``~rumble`` goes back to the
pad's motors or a bar on screen. ``node=None``: a pad for the kernel alone. Browsers, pads: docs/browser-pad.md.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path
from typing import Any, Callable, Optional, Tuple

import anywidget
import traitlets

from hri_teleop.core.gamepad import PadState, RumbleRequests
from hri_teleop.core.gamepad.browser import HEARTBEAT_TIMEOUT_S, BrowserInput
from hri_teleop.core.gamepad.layout import as_layout
from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.course.widgets._base import Ticker, WidgetError, lab_teleop_config, replace_in_cell

__all__ = ["BrowserPad", "BrowserGamepad", "PUBLISH_RATE_HZ", "SEND_PERIOD_MS", "RUMBLE_SILENCE_S", "pad_line"]

#: Joy messages a second to the node: 12 within its input_timeout (0.5 s), 2 within the heartbeat.
PUBLISH_RATE_HZ = 25.0
#: How often the page sends the pad, ms (25 a second: a stick moved reaches the kernel within 40 ms).
SEND_PERIOD_MS = 40
#: The node's ~rumble silent this long counts as 0, s (it publishes every tick, 50 a second).
RUMBLE_SILENCE_S = 0.5
#: How often the kernel echoes a reading's number back, for the page's round-trip time, s.
ECHO_PERIOD_S = 0.5
#: How often the widget asks whether anything listens on the node's ~virtual_joy, s.
LISTENER_CHECK_S = 1.0


def _read_esm() -> str:
    return Path(__file__).with_name("browser_pad.js").read_text(encoding="utf-8")


def pad_line(state: PadState) -> str:
    """The pad as one line of text for the page: both sticks (+1 right/up), triggers and held buttons."""
    sticks = "  ".join(f"{side} ({state.axis(side + '_x'):+.2f}, {state.axis(side + '_y'):+.2f})"
                       for side in ("left", "right"))
    held = ", ".join(name for name, down in state.buttons.items() if down)
    return f"{sticks}  L2 {state.axis('l2'):.2f}  R2 {state.axis('r2'):.2f}  held: {held or '-'}"


class BrowserPad(anywidget.AnyWidget):
    """The browser's gamepad as the teleoperation node's virtual pad; the node's rumble back to the pad.

    The student's node reads it with ``_pad:=browser`` (the notebooks: ``PAD = "browser"``, which shows
    it through ``lab.browser_pad(PAD)``), the lab's node with ``pad:=virtual``; show
    ``widgets.BrowserPad()`` as a cell's last expression, press a button on the pad. ``node``: the
    teleoperation node's name (None: no ROS, a pad for this kernel, :class:`BrowserGamepad`); ``config``/``layout``: the node's teleop config or
    layout (the Joy's order; default: the lab's); ``timeout_s``: the heartbeat (no usable reading
    for this long and the node gets a released pad); ``clock``: the kernel's monotonic clock (tests).
    :meth:`close` stops it and releases the pad.
    """

    _esm = _read_esm()
    reading = traitlets.Dict().tag(sync=True)          # page -> kernel: {sent_s, visible, pad, seq}
    rumble = traitlets.Dict().tag(sync=True)           # kernel -> page: {strong, weak, duration_ms, seq}
    status = traitlets.Unicode("").tag(sync=True)
    status_error = traitlets.Bool(False).tag(sync=True)
    pad_line = traitlets.Unicode("").tag(sync=True)
    echo_seq = traitlets.Int(-1).tag(sync=True)
    send_period_ms = traitlets.Int(SEND_PERIOD_MS).tag(sync=True)

    def __init__(self, node: Optional[str] = "/teleoperation", *, config: Any = None, layout: Any = None,
                 timeout_s: float = HEARTBEAT_TIMEOUT_S, publish_rate_hz: float = PUBLISH_RATE_HZ,
                 session: Any = None, autostart: bool = True, clock: Callable[[], float] = time.monotonic) -> None:
        if node is not None and (not isinstance(node, str) or not node.startswith("/") or node.endswith("/")):
            raise WidgetError(f"node must be the teleoperation node's full name, e.g. '/teleoperation', got {node!r}")
        if not 0.0 < float(publish_rate_hz) <= 200.0:
            raise WidgetError(f"publish_rate_hz must be in (0, 200] Hz, got {publish_rate_hz!r}; e.g. {PUBLISH_RATE_HZ}")
        super().__init__()
        self.node = node
        self._clock = clock
        self.layout_ = as_layout(layout if layout is not None else lab_teleop_config(config).layout)
        self.input = BrowserInput(timeout_s)
        self.published = 0
        self._lock = threading.Lock()
        self._rumble_in: Optional[Tuple[float, float]] = None  # (value, arrival on the clock)
        self._requests = RumbleRequests()
        self._rumble_seq = 0
        self._echoed_s = -ECHO_PERIOD_S
        self._listeners_checked_s = -LISTENER_CHECK_S
        self._listened = False
        self._joy_pub: Any = None
        self._rumble_sub: Any = None
        self.observe(self._on_reading, names="reading")
        self.ticker = Ticker(self.tick, 1.0 / float(publish_rate_hz), name="browser pad", thread=True)
        replace_in_cell(self)
        if node is None:  # a pad for this kernel only: no ROS
            self._say("waiting for the browser page (press a button on the pad)")
            if autostart:
                self.ticker.start()
            return
        session = session if session is not None else ensure_ros(quiet=True)
        if not session:
            self._say(session.problem, error=True)
            return
        import rospy  # noqa: PLC0415 - only ROS cells need it
        from sensor_msgs.msg import Joy  # noqa: PLC0415 - as rospy
        from std_msgs.msg import Float32  # noqa: PLC0415 - as rospy

        from hri_teleop.ros.joy import joy_message  # noqa: PLC0415 - as rospy

        self._joy_message = joy_message
        self._joy_pub = rospy.Publisher(f"{node}/virtual_joy", Joy, queue_size=1, tcp_nodelay=True)
        self._rumble_sub = rospy.Subscriber(f"{node}/rumble", Float32, self.on_rumble, queue_size=1,
                                            tcp_nodelay=True)
        self._say("waiting for the browser page (press a button on the pad)")
        if autostart:
            self.ticker.start()

    # -- from the page and the node (the kernel's thread, rospy's thread) ---------------------
    def _on_reading(self, change: Any) -> None:
        now = self._clock()
        message = change["new"]
        with self._lock:
            reading = self.input.receive(message, now)
        if reading is not None and now - self._echoed_s >= ECHO_PERIOD_S and isinstance(message.get("seq"), int):
            self._echoed_s = now
            self.echo_seq = message["seq"]

    def on_rumble(self, msg: Any) -> None:
        """The node's ~rumble (std_msgs/Float32, 0..1; rospy's thread): kept for the next tick."""
        self._rumble_in = (float(msg.data), self._clock())

    def poll_state(self) -> PadState:
        """The pad as the kernel has it now: released once the page fell silent (any thread)."""
        now = self._clock()
        with self._lock:
            return self.input.state(now)

    def set_rumble(self, intensity: float) -> None:
        """The rumble to play (0..1) when no node sends one (``node=None``): passed on at the next tick."""
        self._rumble_in = (min(1.0, max(0.0, float(intensity))), self._clock())

    # -- the loop (a thread of its own: it goes on while a cell runs) ------------------------
    def tick(self) -> PadState:
        """Publish the pad's state to the node (released when the page is silent) and pass the rumble on."""
        now = self._clock()
        with self._lock:
            state = self.input.state(now)
            problem = self.input.problem(now)
            reading = self.input.reading
        if self._joy_pub is not None:
            self._joy_pub.publish(self._joy_message(self.layout_, state))
            self.published += 1
            if now - self._listeners_checked_s >= LISTENER_CHECK_S:
                self._listeners_checked_s = now
                self._listened = self._joy_pub.get_num_connections() > 0
        self._send_rumble(now)
        line = pad_line(state)
        if self.pad_line != line:
            self.pad_line = line
        if problem:
            self._say(problem, error=True)
        elif self._joy_pub is not None and not self._listened:
            self._say(f"gamepad {reading.pad_id!r} is read, but nothing listens on {self.node}/virtual_joy: start "
                      "your node with the browser pad (PAD = \"browser\" in the notebook's start cell; in a terminal "
                      "rosrun hri_lab teleoperation.py _pad:=browser)", error=True)
        else:
            self._say(f"gamepad {reading.pad_id!r} " + (f"drives {self.node}" if self.node else "is read by this notebook")
                      + "; rumble "
                      + ("on the pad and on screen" if reading.haptics else "on screen only (the browser cannot "
                         "rumble this pad)"))
        return state

    def _send_rumble(self, now: float) -> None:
        latest = self._rumble_in
        value = latest[0] if latest is not None and now - latest[1] <= RUMBLE_SILENCE_S else 0.0
        request = self._requests.update(value, now)
        if request is None:
            return
        intensity, duration_s = request
        self._rumble_seq += 1
        # One value from the node: both motors alike (the heavy one carries most of the feel).
        self.rumble = {"strong": intensity, "weak": intensity, "duration_ms": round(duration_s * 1000.0),
                       "seq": self._rumble_seq}

    def _say(self, line: str, error: bool = False) -> None:
        if self.status != line:
            self.status = line
        if self.status_error != error:
            self.status_error = error

    def close(self) -> None:
        """Stop publishing (one released pad first, so the node stops now, not after its timeout)."""
        ticker = getattr(self, "ticker", None)  # None: __init__ refused its arguments (ipywidgets closes on __del__)
        if ticker is None:
            return
        ticker.stop()
        if self._joy_pub is not None:
            with self._lock:
                self.input.heartbeat.reset()
            self.tick()
            self._joy_pub.unregister()
            self._joy_pub = None
        if self._rumble_sub is not None:
            self._rumble_sub.unregister()
            self._rumble_sub = None
        super().close()


class BrowserGamepad:
    """The browser's gamepad as a pad for this kernel (the :class:`Gamepad` protocol), without ROS.

    ``widget`` is the :class:`BrowserPad` (``node=None``) to show; :meth:`poll` gives its pad, released
    once the page falls silent; :meth:`rumble` plays on the page's pad and bar. The controller view
    (Ex. 8) reads it with ``ControllerView(source="browser")``.
    """

    name = "browser pad"

    def __init__(self, layout: Any = None, config: Any = None, **kwargs: Any) -> None:
        self.widget = BrowserPad(None, layout=layout, config=config, **kwargs)

    @property
    def layout(self) -> Any:
        return self.widget.layout_

    def poll(self) -> PadState:
        return self.widget.poll_state()

    def rumble(self, intensity: float, duration_s: float = 0.0) -> None:
        self.widget.set_rumble(intensity)

    def close(self) -> None:
        self.widget.close()
