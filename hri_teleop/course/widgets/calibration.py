"""Calibration (handout Ex. 11): the largest /pub_force while the piston is pressed, kept for good.

By hand, Ex. 11 is ``rostopic echo``, a scrolling number, ``rosparam set`` and an edited launch
file: three places for a typo. Here: record, see the maximum, apply it: ``/max_sensor_force`` is
set on the parameter server and written into the student's launch or YAML file
(:func:`hri_teleop.core.paramfile.write_max_sensor_force`). The value's rule is
:func:`hri_teleop.hardware.real.calibrate.calibration_max`, shared with the serial calibration.
"""

from __future__ import annotations

import math
import threading
import time
from typing import Any, Callable, Optional

import ipywidgets as widgets

from hri_teleop.core.checks import is_int
from hri_teleop.core.mapping import ADC_MAX_COUNT
from hri_teleop.core.paramfile import PARAM_NAME, ParamFileError, write_max_sensor_force
from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.course.widgets._base import Ticker, WidgetError, message_html, replace_in_cell
from hri_teleop.hardware.real.calibrate import CalibrateError, calibration_max

__all__ = ["MaxRecorder", "CalibrationWidget"]


class MaxRecorder:
    """The running maximum of counts fed while recording; thread-safe, constant memory.

    ``duration_s`` None records until :meth:`stop`. Counts that are not integers in
    0..1023 are counted in ``rejected`` and otherwise ignored.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._started_s: Optional[float] = None
        self._deadline_s: Optional[float] = None
        self._recording = False
        self.samples = 0
        self.rejected = 0
        self.maximum: Optional[int] = None

    def start(self, now_s: float, duration_s: Optional[float] = None) -> None:
        """Forget the last recording and record from ``now_s`` (for ``duration_s`` s, or until stop)."""
        if duration_s is not None and not (0.0 < float(duration_s) < math.inf):
            raise WidgetError(f"duration_s must be a positive time in s, or None (until stopped), got {duration_s!r}")
        with self._lock:
            self._started_s = float(now_s)
            self._deadline_s = None if duration_s is None else float(now_s) + float(duration_s)
            self._recording = True
            self.samples = 0
            self.rejected = 0
            self.maximum = None

    def feed(self, count: Any, now_s: float) -> bool:
        """Take one count received at ``now_s``; True if it was recorded."""
        with self._lock:
            if not self._recording:
                return False
            if self._deadline_s is not None and now_s > self._deadline_s:
                self._recording = False
                return False
            if not is_int(count, numpy=True) or not 0 <= count <= ADC_MAX_COUNT:
                self.rejected += 1
                return False
            value = int(count)
            self.samples += 1
            if self.maximum is None or value > self.maximum:
                self.maximum = value
            return True

    def stop(self) -> None:
        with self._lock:
            self._recording = False

    def recording(self, now_s: float) -> bool:
        """True while recording (a duration that has run out ends it)."""
        with self._lock:
            if self._recording and self._deadline_s is not None and now_s > self._deadline_s:
                self._recording = False
            return self._recording

    def elapsed_s(self, now_s: float) -> float:
        with self._lock:
            if self._started_s is None:
                return 0.0
            end = now_s if self._deadline_s is None else min(now_s, self._deadline_s)
            return max(0.0, end - self._started_s)

    def result(self) -> int:
        """The calibration value; CalibrateError (one line) when nothing usable was recorded."""
        with self._lock:
            maximum = self.maximum
        return calibration_max([] if maximum is None else [maximum])


class CalibrationWidget(widgets.VBox):
    """Record the largest ``/pub_force``, then set ``/max_sensor_force`` and write it into ``file``.

    ``file``: the student's teleoperation.launch / sensor.launch or a YAML file (may also be
    typed into the widget). ``duration_s`` 0 or None records until *stop* is pressed.
    Programmatic use: :meth:`start`, :meth:`stop`, :meth:`apply`.
    """

    def __init__(self, file: Any = None, *, duration_s: Optional[float] = 10.0, topic: str = "/pub_force",
                 session: Any = None, interval_s: float = 0.2,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.topic = topic
        self.recorder = MaxRecorder()
        self._clock = clock
        self._subscriber: Any = None
        self._subscriber_lock = threading.Lock()  # the ticker's thread and wait()/close() both end it
        self.file = widgets.Text(value="" if file is None else str(file), description="file",
                                 placeholder="path of your teleoperation.launch, sensor.launch or YAML file",
                                 layout=widgets.Layout(width="640px"))
        self.duration = widgets.BoundedFloatText(value=float(duration_s or 0.0), min=0.0, max=600.0, step=1.0,
                                                 description="seconds", tooltip="0: until stop is pressed",
                                                 layout=widgets.Layout(width="180px"))
        self.start_button = widgets.Button(description="record", button_style="primary", icon="circle")
        self.stop_button = widgets.Button(description="stop", icon="stop", disabled=True)
        self.apply_button = widgets.Button(description=f"apply /{PARAM_NAME}", button_style="success",
                                           disabled=True, layout=widgets.Layout(width="auto"))
        self.progress = widgets.FloatProgress(min=0.0, max=1.0, description="recording")
        self.maximum_label = widgets.HTML()
        self.status = widgets.HTML()
        self.ticker = Ticker(self.refresh, interval_s, name="calibration")
        session = session if session is not None else ensure_ros(quiet=True)
        self.session = session
        if not session:
            self.status.value = message_html(session.problem, error=True)
            super().__init__([self.status])
            return
        self.start_button.on_click(lambda _b: self._guarded(self.start))
        self.stop_button.on_click(lambda _b: self._guarded(self.stop))
        self.apply_button.on_click(lambda _b: self._guarded(self.apply))
        self.status.value = message_html(f"press the piston level with the housing a few times while it records "
                                         f"{topic}")
        super().__init__([widgets.HBox([self.duration, self.start_button, self.stop_button]),
                          widgets.HBox([self.progress, self.maximum_label]),
                          widgets.HBox([self.file, self.apply_button]), self.status])
        replace_in_cell(self)

    def _guarded(self, action: Callable[[], Any]) -> None:
        try:
            message = action()
        except (CalibrateError, ParamFileError, WidgetError) as exc:
            self.status.value = message_html(str(exc), error=True)
            return
        if isinstance(message, str):
            self.status.value = message_html(message)

    def _callback(self, msg: Any) -> None:
        self.recorder.feed(msg.data, self._clock())  # rospy's thread: nothing but the max

    def start(self, duration_s: Optional[float] = None) -> str:
        """Record from now for ``duration_s`` s (default: the widget's; 0 or None: until :meth:`stop`)."""
        import rospy  # noqa: PLC0415 - ROS only when a recording starts
        from std_msgs.msg import Int16  # noqa: PLC0415 - as rospy

        seconds = self.duration.value if duration_s is None else duration_s
        self.recorder.start(self._clock(), seconds or None)
        with self._subscriber_lock:
            if self._subscriber is None:
                self._subscriber = rospy.Subscriber(self.topic, Int16, self._callback, queue_size=1000,
                                                    tcp_nodelay=True)
        self.start_button.disabled = True
        self.stop_button.disabled = False
        self.apply_button.disabled = True
        self.ticker.start()
        self.refresh()
        return f"recording {self.topic}" + (f" for {seconds:g} s" if seconds else " until stop is pressed")

    def stop(self) -> str:
        """Stop recording now; returns what was recorded."""
        self.recorder.stop()
        self.refresh()
        return self._summary()

    def _summary(self) -> str:
        r = self.recorder
        if r.maximum is None:
            return f"no {self.topic} message arrived: is the board (or its simulation) running?"
        return f"{r.samples} samples, maximum {r.maximum}" + (f" ({r.rejected} out of range)" if r.rejected else "")

    def refresh(self) -> None:
        """Show progress and the running maximum; ends the recording's subscription when it is over."""
        now = self._clock()
        recording = self.recorder.recording(now)
        seconds = self.duration.value
        self.progress.value = min(1.0, self.recorder.elapsed_s(now) / seconds) if seconds else (
            1.0 if recording else 0.0)
        self.progress.bar_style = "info" if recording else ""
        self.maximum_label.value = f"<b>max {self.topic}: {self.recorder.maximum}</b> ({self.recorder.samples} samples)"
        if not recording and self.ticker.running:
            self.ticker.stop()
        if not recording:
            self._unsubscribe()
            self.start_button.disabled = False
            self.stop_button.disabled = True
            self.apply_button.disabled = self.recorder.maximum in (None, 0)

    def wait(self, timeout_s: float = 60.0) -> int:
        """Block until a timed recording ends (scripts and tests; a notebook needs no wait); the result."""
        deadline = time.monotonic() + timeout_s
        while self.recorder.recording(self._clock()) and time.monotonic() < deadline:
            time.sleep(0.02)
        self.recorder.stop()
        self.refresh()
        return self.recorder.result()

    def apply(self, value: Optional[int] = None, file: Any = None) -> str:
        """Set ``/max_sensor_force`` to ``value`` (default: the recording's) and write it into ``file``.

        ``file`` defaults to the widget's file field; empty: only the parameter is set.
        Raises CalibrateError / ParamFileError (one line) -- the file is checked before the
        parameter is set, so a refused file changes nothing.
        """
        import rospy  # noqa: PLC0415 - ROS only when the value is applied

        count = self.recorder.result() if value is None else calibration_max([value])
        path = str(file if file is not None else self.file.value).strip()
        written = ""
        if path:
            edits = write_max_sensor_force(path, count)
            written = "; wrote it to " + ", ".join(f"{path}:{e.line} ({e.what} {e.old} -> {e.new})" for e in edits)
        rospy.set_param("/" + PARAM_NAME, count)
        return f"/{PARAM_NAME} = {count} on the parameter server{written}"

    def _unsubscribe(self) -> None:
        """End the recording's subscription once, whoever gets here first (rospy fails a second
        unregister of the same subscriber: CI saw the ticker's refresh and wait() race)."""
        with self._subscriber_lock:
            subscriber, self._subscriber = self._subscriber, None
        if subscriber is not None:
            subscriber.unregister()

    def close(self) -> None:
        self.ticker.stop()
        self.recorder.stop()
        self._unsubscribe()
        super().close()
