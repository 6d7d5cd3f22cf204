"""Live plots of the lab's topics: /pub_force, /force_mapped, /gripper_width and the twist.

rospy calls each subscriber's callback in a thread of its own, at up to 100 Hz per topic; one
that waited for matplotlib (tens of ms a frame) would make messages pile up and be dropped. So a
callback only converts the message to floats (:func:`numeric_fields`) and appends them under a
lock to a bounded :class:`TopicBuffer`, and the plot snapshots the buffers a few times a second
on a :class:`~hri_teleop.course.widgets._base.Ticker` in the kernel's own thread.
"""

from __future__ import annotations

import operator
import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Deque, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import ipywidgets as widgets
import numpy as np
from matplotlib.figure import Figure

from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.course.widgets._base import (
    FigureView,
    Ticker,
    WidgetError,
    lab_teleop_config,
    message_html,
    replace_in_cell,
)

__all__ = ["TopicSpec", "TopicBuffer", "numeric_fields", "field_getter", "rate_hz", "view_end_s", "lab_topics",
           "LiveTopics", "LivePlot", "DEFAULT_MAXLEN", "RUMBLE_OK_TOPIC", "pad_cue_html"]

#: The teleoperation node's latched start check of the pad's rumble (std_msgs/Bool).
RUMBLE_OK_TOPIC = "/teleoperation/rumble_ok"


def pad_cue_html(rumble_ok: Optional[bool]) -> str:
    """The visible cue for the node's rumble check: red when the pad refused, nothing before a check."""
    if rumble_ok is None:
        return ""
    if rumble_ok:
        return message_html("pad rumble: accepted (force feedback works)")
    return message_html("the pad refuses rumble: no force feedback at this station. The teleoperation node's log "
                        "says why; try a USB cable or another pad", error=True)


#: Samples kept per topic: 50 s at the lab's 100 Hz, a few hundred kB in all.
DEFAULT_MAXLEN = 5000

_NUMERIC = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
            "float32", "float64"}


@dataclass(frozen=True)
class TopicSpec:
    """A topic to plot: its name, message type and, optionally, fixed y limits and a y label."""

    topic: str
    type: str
    ylim: Optional[Tuple[float, float]] = None
    ylabel: str = ""


def lab_topics(config: Any = None) -> List[TopicSpec]:
    """The lab's four topics (the topics of docs/lab-facts.md); the twist topic comes from the teleop config."""
    twist = lab_teleop_config(config).twist_topic
    return [
        TopicSpec("/pub_force", "std_msgs/Int16", (-20.0, 1043.0), "ADC count"),
        TopicSpec("/force_mapped", "std_msgs/Float32", (-0.05, 1.05), "0..1"),
        TopicSpec("/gripper_width", "std_msgs/Float32", (-0.002, 0.082), "m"),
        TopicSpec(twist, "geometry_msgs/Twist", None, "m/s, rad/s"),
    ]


def numeric_fields(message_class: Any, prefix: str = "") -> Tuple[str, ...]:
    """Dotted names of every numeric scalar in a genpy message class, in declaration order.

    Nested messages are followed (``linear.x``); arrays, strings, times and ``header``
    are left out: they do not plot as one line.
    """
    names: List[str] = []
    slots = getattr(message_class, "__slots__", ())
    types = getattr(message_class, "_slot_types", ())
    for slot, kind in zip(slots, types):
        if slot == "header" or "[" in kind:
            continue
        if kind in _NUMERIC:
            names.append(prefix + slot)
        elif "/" in kind:
            nested = _message_class(kind)
            if nested is not None:
                names.extend(numeric_fields(nested, prefix + slot + "."))
    return tuple(names)


def _message_class(type_name: str) -> Any:
    try:
        from roslib.message import get_message_class  # noqa: PLC0415 - ROS only when needed
    except ImportError:
        return None
    return get_message_class(type_name)


def field_getter(fields: Sequence[str]) -> Callable[[Any], Tuple[float, ...]]:
    """A fast function message -> tuple of floats for the dotted ``fields``."""
    if not fields:
        raise WidgetError("a plotted message needs at least one numeric field; pick a topic with numbers")
    if len(fields) == 1:  # attrgetter of one field returns the value itself, not a tuple
        one = operator.attrgetter(fields[0])
        return lambda msg: (float(one(msg)),)
    get = operator.attrgetter(*fields)
    return lambda msg: tuple(float(v) for v in get(msg))


class TopicBuffer:
    """A thread-safe ring buffer of (time_s, values): appends from callbacks, snapshots for plots."""

    def __init__(self, fields: Sequence[str], maxlen: int = DEFAULT_MAXLEN) -> None:
        if int(maxlen) < 1:
            raise WidgetError(f"maxlen must be >= 1 sample, got {maxlen!r}; e.g. {DEFAULT_MAXLEN}")
        self.fields = tuple(fields)
        self.maxlen = int(maxlen)
        self._lock = threading.Lock()
        self._samples: Deque[Tuple[float, Tuple[float, ...]]] = deque(maxlen=self.maxlen)
        self.received = 0  # every message ever appended, also those the ring has forgotten

    def append(self, time_s: float, values: Tuple[float, ...]) -> None:
        with self._lock:
            self._samples.append((time_s, values))
            self.received += 1

    def __len__(self) -> int:
        with self._lock:
            return len(self._samples)

    def clear(self) -> None:
        with self._lock:
            self._samples.clear()

    def snapshot(self) -> Tuple[np.ndarray, np.ndarray]:
        """(times shape (n,), values shape (n, len(fields))) as copies, safe to use without the lock."""
        with self._lock:
            samples = list(self._samples)
        if not samples:
            return np.zeros(0), np.zeros((0, len(self.fields)))
        times = np.fromiter((t for t, _ in samples), dtype=float, count=len(samples))
        values = np.array([v for _, v in samples], dtype=float).reshape(len(samples), len(self.fields))
        return times, values


#: A plot whose topics all went quiet for longer than this share of its window stops scrolling.
QUIET_SHARE = 0.25


def view_end_s(last_s: Optional[float], now_s: float, window_s: float) -> float:
    """The time the plot's right edge shows: now while messages come, and once every topic has been
    quiet for longer than a quarter of the window (a node that quit, a scripted pad that ended), a
    quarter window after the last message, so the run stays in view instead of scrolling out."""
    if last_s is None or now_s - last_s <= QUIET_SHARE * window_s:
        return now_s
    return last_s + QUIET_SHARE * window_s


def rate_hz(times_s: np.ndarray, now_s: float, span_s: float = 1.0) -> float:
    """Messages per second over the last ``span_s`` seconds before ``now_s``."""
    if span_s <= 0:
        raise WidgetError(f"span_s must be > 0 s, got {span_s!r}")
    recent = np.count_nonzero(times_s > now_s - span_s)
    return float(recent) / span_s


TopicsArg = Union[None, Sequence[Union[str, TopicSpec]], Mapping[str, str]]


def _specs(topics: TopicsArg, uri: Optional[str] = None) -> List[TopicSpec]:
    if topics is None:
        return lab_topics()
    known = {spec.topic: spec for spec in lab_topics()}
    if isinstance(topics, Mapping):
        return [known[t] if t in known and known[t].type == kind else TopicSpec(t, kind) for t, kind in topics.items()]
    specs: List[TopicSpec] = []
    types: Optional[Dict[str, str]] = None
    for item in topics:
        if isinstance(item, TopicSpec):
            specs.append(item)
        elif item in known:
            specs.append(known[item])
        else:
            if types is None:
                from hri_teleop.ros.master_api import master_call  # noqa: PLC0415 - for a topic not known here only

                types = dict(master_call("getTopicTypes", uri=uri))
            if item not in types:
                raise WidgetError(f"topic {item} is not published yet, so its type is unknown; start its publisher "
                                  f"first or pass the type, e.g. {{'{item}': 'std_msgs/Float32'}}")
            specs.append(TopicSpec(item, types[item]))
    return specs


class LiveTopics:
    """Subscribers that fill one :class:`TopicBuffer` per topic (needs a ROS node: :func:`ensure_ros`)."""

    def __init__(self, topics: TopicsArg = None, *, maxlen: int = DEFAULT_MAXLEN, queue_size: int = 1000,
                 clock: Callable[[], float] = time.monotonic) -> None:
        import rospy  # noqa: PLC0415 - only ROS cells need it

        self.specs = _specs(topics)
        self.buffers: Dict[str, TopicBuffer] = {}
        self._subscribers: List[Any] = []
        self._clock = clock
        for spec in self.specs:
            message_class = _message_class(spec.type)
            if message_class is None:
                raise WidgetError(f"unknown message type {spec.type} for {spec.topic}; check the spelling "
                                  "(package/Message) and that the package is installed")
            fields = numeric_fields(message_class)
            buffer = TopicBuffer(fields, maxlen)
            self.buffers[spec.topic] = buffer
            getter = field_getter(fields)
            self._subscribers.append(rospy.Subscriber(
                spec.topic, message_class, self._callback, callback_args=(buffer, getter),
                queue_size=queue_size, tcp_nodelay=True))

    def _callback(self, msg: Any, args: Tuple[TopicBuffer, Callable[[Any], Tuple[float, ...]]]) -> None:
        # rospy's receive thread: convert and append, nothing else (see the module doc).
        buffer, getter = args
        buffer.append(self._clock(), getter(msg))

    def connected(self) -> Dict[str, int]:
        """Publishers each subscription is connected to (0: nobody publishes it yet)."""
        return {spec.topic: sub.get_num_connections() for spec, sub in zip(self.specs, self._subscribers)}

    def close(self) -> None:
        """Unsubscribe; the buffers keep what they hold."""
        for sub in self._subscribers:
            sub.unregister()
        self._subscribers.clear()


class LivePlot(widgets.VBox):
    """One panel per topic over the last ``window_s`` seconds, redrawn every ``interval_s``.

    ``topics``: None for the lab's four, a list of names or :class:`TopicSpec`, or a
    ``{topic: type}`` mapping. ``session``: an :func:`~hri_teleop.course.notebook_ros.ensure_ros`
    session (made here if None). Without ROS it shows one line saying what to install.
    ``plot.topics.buffers`` holds the data; :meth:`stop` pauses, :meth:`close` ends it.
    ``rumble_ok_topic`` (the teleoperation node's latched start check; '' for none): a pad
    that refused rumble is said in red above the plots (``pad_cue``).
    """

    def __init__(self, topics: TopicsArg = None, *, window_s: float = 10.0, interval_s: float = 0.5,
                 maxlen: int = DEFAULT_MAXLEN, session: Any = None, figure: str = "auto",
                 autostart: bool = True, rumble_ok_topic: str = RUMBLE_OK_TOPIC) -> None:
        if not 0.0 < float(window_s) <= 3600.0:
            raise WidgetError(f"window_s must be in (0, 3600] s, got {window_s!r}; e.g. 10")
        self.window_s = float(window_s)
        self.status = widgets.HTML()
        self.pad_cue = widgets.HTML()
        self._rumble_ok: Optional[bool] = None  # from rospy's thread; shown by redraw
        self._rumble_ok_sub: Any = None
        self.topics: Optional[LiveTopics] = None
        self.view: Optional[FigureView] = None
        self.ticker = Ticker(self.redraw, interval_s, name="live plot")
        session = session if session is not None else ensure_ros(quiet=True)
        if not session:
            self.status.value = message_html(session.problem, error=True)
            super().__init__([self.status])
            return
        self.topics = LiveTopics(topics, maxlen=maxlen)
        if rumble_ok_topic:
            import rospy  # noqa: PLC0415 - ROS only when needed (as _message_class)
            from std_msgs.msg import Bool  # noqa: PLC0415 - as rospy

            self._rumble_ok_sub = rospy.Subscriber(rumble_ok_topic, Bool, self._on_rumble_ok, queue_size=1)
        specs = self.topics.specs
        height_in = 1.9 * len(specs) + 0.4
        fig = Figure(figsize=(9.0, height_in), dpi=80)
        # A fixed layout: constrained_layout would re-solve it on every frame (about a third of the draw time).
        fig.subplots_adjust(left=0.09, right=0.98, top=1.0 - 0.35 / height_in, bottom=0.55 / height_in, hspace=0.5)
        axes = fig.subplots(len(specs), 1, sharex=True, squeeze=False)[:, 0]
        self._lines: Dict[str, List[Any]] = {}
        self._axes: Dict[str, Any] = {}
        for ax, spec in zip(axes, specs):
            fields = self.topics.buffers[spec.topic].fields
            styles = ["-"] * len(fields)
            if "Twist" in spec.type:  # Twist, TwistStamped: linear solid, angular dashed
                styles = ["--" if "angular" in name else "-" for name in fields]
            self._lines[spec.topic] = [ax.plot([], [], ls, lw=1.2, label=name)[0] for name, ls in zip(fields, styles)]
            self._axes[spec.topic] = ax
            ax.set_xlim(-self.window_s, 0.0)
            if spec.ylim:
                ax.set_ylim(*spec.ylim)
            ax.set_ylabel(spec.ylabel or spec.type.split("/")[-1], fontsize=8)
            ax.grid(True, alpha=0.3)
            if len(fields) > 1:
                ax.legend(fontsize=7, loc="upper left", ncol=min(6, len(fields)))
        axes[-1].set_xlabel("time (s, 0 = now)")
        self._bottom_axes = axes[-1]
        self.view = FigureView(fig, figure)
        self.status.value = message_html(session.describe())
        super().__init__([self.status, self.pad_cue, self.view.widget])
        replace_in_cell(self)
        self.redraw()
        if autostart:
            self.start()

    def start(self) -> None:
        """(Re)start redrawing."""
        self.ticker.start()

    def stop(self) -> None:
        """Stop redrawing; the subscribers keep filling the buffers."""
        self.ticker.stop()

    def _on_rumble_ok(self, msg: Any) -> None:
        self._rumble_ok = bool(msg.data)

    def redraw(self, now_s: Optional[float] = None) -> None:
        """Draw the last ``window_s`` seconds of every buffer (and the pad's rumble check)."""
        if self.topics is None or self.view is None:
            return
        self.pad_cue.value = pad_cue_html(self._rumble_ok)
        now = time.monotonic() if now_s is None else now_s
        snapshots = {spec.topic: self.topics.buffers[spec.topic].snapshot() for spec in self.topics.specs}
        last = max((float(times[-1]) for times, _values in snapshots.values() if len(times)), default=None)
        end = view_end_s(last, now, self.window_s)
        for spec in self.topics.specs:
            buffer = self.topics.buffers[spec.topic]
            times, values = snapshots[spec.topic]
            keep = (times > end - self.window_s) & (times <= end)
            x = times[keep] - end
            for column, line in enumerate(self._lines[spec.topic]):
                line.set_data(x, values[keep, column])
            ax = self._axes[spec.topic]
            ax.set_title(f"{spec.topic} ({spec.type})  {rate_hz(times, now):.0f} Hz, {buffer.received} messages",
                         fontsize=9, loc="left")
            if spec.ylim is None and keep.any():
                low, high = float(values[keep].min()), float(values[keep].max())
                pad = max(0.05, 0.1 * (high - low))
                ax.set_ylim(low - pad, high + pad)
        self._bottom_axes.set_xlabel("time (s, 0 = now)" if end == now else
                                     f"time (s, 0 = {now - end:.0f} s ago: nothing new since, so the plot stopped)")
        self.view.redraw()

    def close(self) -> None:
        """Stop redrawing and unsubscribe."""
        self.ticker.stop()
        if self._rumble_ok_sub is not None:
            self._rumble_ok_sub.unregister()
            self._rumble_ok_sub = None
        if self.topics is not None:
            self.topics.close()
        super().close()
