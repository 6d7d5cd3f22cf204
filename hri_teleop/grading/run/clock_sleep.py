"""Under grading, time.sleep in a student's own code follows the grader's /clock.

A loop paced by time.sleep ignores /clock: on a busy machine it ran more or fewer times per tick
than the grader stepped, and a graded width drifted. The grader puts :data:`SITE_DIR` on the
student process' PYTHONPATH; its sitecustomize calls :func:`install`, which wraps time.sleep for
calls from files under the student's folder (:func:`follows_clock` says when; other waits keep
the wall clock). The wait ends as rospy.Rate's would (:func:`deadline_ns`): no tick is skipped.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, Mapping, Optional

__all__ = ["ROOT_ENV", "SITE_DIR", "deadline_ns", "follows_clock", "install", "student_clock_env"]

#: The student's folder, absolute: time.sleep called from a file below it follows /clock.
ROOT_ENV = "HRI_CLOCK_SLEEP_ROOT"
#: The folder whose sitecustomize installs the wrapper in every Python process of the student.
SITE_DIR = Path(__file__).resolve().with_name("clock_site")


def deadline_ns(now_ns: int, last_wake_ns: Optional[int], duration_ns: int) -> int:
    """When a sleep of ``duration_ns`` asked at ``now_ns`` ends on the grader's clock.

    From the thread's last wake-up while that is at most one duration ago (rospy.Rate's rule: a
    tick that reached the node before it slept is not waited for again), else from now.
    """
    if last_wake_ns is not None and last_wake_ns <= now_ns <= last_wake_ns + duration_ns:
        return last_wake_ns + duration_ns
    return now_ns + duration_ns


def follows_clock(published: Optional[int], published_at_last_sleep: Optional[int]) -> bool:
    """Whether a sleep waits for the grader's clock: only if the process published since this
    thread last slept. The grader steps the clock once a node published; a wait before that (for
    a subscriber, say) would wait for a tick that never comes, so it keeps the wall clock."""
    return published is not None and published_at_last_sleep is not None and published > published_at_last_sleep


def student_clock_env(folder: Path, pythonpath: str = "") -> Dict[str, str]:
    """The variables that turn the wrapper on in a student's processes below ``folder``:
    :data:`SITE_DIR` first on ``pythonpath``."""
    parts = [str(SITE_DIR)] + [p for p in pythonpath.split(os.pathsep) if p and p != str(SITE_DIR)]
    return {ROOT_ENV: str(Path(folder).resolve()), "PYTHONPATH": os.pathsep.join(parts)}


class _Sleeper:
    """The wrapper's state: the root, the files known to be below it, each thread's last wake-up."""

    def __init__(self, root: str, original: Callable[[float], None]) -> None:
        self.root = os.path.realpath(root) + os.sep
        self.original = original
        self.below: Dict[str, bool] = {}
        self.local = threading.local()

    def from_student(self, filename: str) -> bool:
        known = self.below.get(filename)
        if known is None:
            known = os.path.realpath(os.path.abspath(filename)).startswith(self.root)
            self.below[filename] = known
        return known

    def sleep(self, seconds: float) -> None:  # pragma: no mutate block (make mutants: nothing may wrap this frame)
        """time.sleep: judged by the file of the function that called it (this frame's caller)."""
        return self.sleep_from(sys._getframe(1).f_code.co_filename, seconds)

    def sleep_from(self, filename: str, seconds: float) -> None:
        """time.sleep(``seconds``) called from a function of ``filename``."""
        rospy: Any = sys.modules.get("rospy")
        if (rospy is None or not self.from_student(filename)
                or not rospy.core.is_initialized() or rospy.rostime.is_wallclock() or rospy.core.is_shutdown()):
            return self.original(seconds)
        published, before = _published(rospy), getattr(self.local, "published", None)
        self.local.published = published
        now_ns = rospy.rostime.get_rostime().to_nsec()
        try:
            duration_ns = int(float(seconds) * 1e9)
        except (TypeError, ValueError, OverflowError):  # not a number, nan, inf: time.sleep's own error
            return self.original(seconds)
        if duration_ns < 0 or now_ns == 0 or not follows_clock(published, before):
            return self.original(seconds)  # time.sleep's own error; no clock yet; nothing to wait for
        until_ns = deadline_ns(now_ns, getattr(self.local, "last_wake_ns", None), duration_ns)
        cond = rospy.rostime.get_rostime_cond()
        with cond:  # read under the lock that /clock's update notifies with: no update is missed
            while not rospy.core.is_shutdown():
                now = rospy.rostime.get_rostime().to_nsec()
                if now >= until_ns or now < now_ns:  # reached, or the clock went back (a new run)
                    break
                cond.wait(0.5)
        self.local.last_wake_ns = until_ns
        return None


def _published(rospy: Any) -> Optional[int]:
    """Messages this process has sent on its topics (/rosout aside); None if rospy does not say."""
    try:
        manager = rospy.impl.registration.get_topic_manager()
        return sum(int(impl.seq) for name, impl in list(manager.pubs.items()) if name != "/rosout")
    except (AttributeError, TypeError, ValueError):
        return None


def install(env: Mapping[str, str] = os.environ) -> bool:
    """Wrap time.sleep when ``env`` names the student's folder; True if it is wrapped now."""
    root = env.get(ROOT_ENV, "")
    if not root:
        return False
    if isinstance(getattr(time.sleep, "__self__", None), _Sleeper):
        return True
    sleeper = _Sleeper(root, time.sleep)
    time.sleep = sleeper.sleep  # type: ignore[assignment]
    return True
