"""The calibration widget ends its subscription once, whoever ends it first: the ticker's
refresh and wait() (or close()) can get there at the same time, and rospy fails a second
unregister of the same subscriber (CI saw it)."""

from __future__ import annotations

import threading
import time
import types

from hri_teleop.course.widgets.calibration import CalibrationWidget


class _SlowSubscriber:
    """Like rospy's: a second unregister is an AssertionError; the first takes a while."""

    def __init__(self) -> None:
        self.calls = 0

    def unregister(self) -> None:
        self.calls += 1
        if self.calls > 1:
            raise AssertionError("cannot release topic impl as impl [/pub_force] does not exist")
        time.sleep(0.2)


def test_two_threads_ending_the_recording_unregister_once():
    widget = CalibrationWidget(session=types.SimpleNamespace(problem=""), interval_s=60.0)
    subscriber = _SlowSubscriber()
    widget._subscriber = subscriber
    errors: list = []

    def end() -> None:
        try:
            widget.refresh()  # not recording: ends the subscription
        except AssertionError as exc:
            errors.append(exc)

    threads = [threading.Thread(target=end) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    widget.close()
    assert errors == [] and subscriber.calls == 1
