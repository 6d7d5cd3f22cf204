"""A student's time.sleep under the grader's /clock, one sleep at a time, on a clock the test steps.

rospy is stood in for by what the wrapper reads of it: whether the node runs, the time on /clock, the
condition /clock's updates notify, and how many messages each of the process' topics has sent. Each
``wait`` of the wrapper on that condition is one step of a script: the next /clock value arriving, or
rospy shutting down (which notifies nobody). A sleep that would wait past the script fails the test; no
test measures a duration.
"""

from __future__ import annotations

import sys
import threading
import time
from types import SimpleNamespace
from typing import Any, Callable, Dict, List, Optional, Union

import pytest

from hri_teleop.grading.run import clock_sleep
from hri_teleop.grading.run.clock_sleep import ROOT_ENV, install

MS = 10**6
SHUTDOWN = "shutdown"


class FakeRospy:
    """The parts of rospy the wrapper reads; ``steps``: what happens at each wait (a /clock value or SHUTDOWN)."""

    def __init__(self) -> None:
        self.now_ns = 1_000 * MS
        self.initialized = True
        self.shut_down = False
        self.wallclock = False
        self.sent: Dict[str, int] = {"/cmd_vel": 0, "/rosout": 0}
        self.steps: List[Union[int, str]] = []
        self.waits: List[Optional[float]] = []
        self.core = SimpleNamespace(is_initialized=lambda: self.initialized, is_shutdown=lambda: self.shut_down)
        self.rostime = SimpleNamespace(is_wallclock=lambda: self.wallclock, get_rostime_cond=lambda: self,
                                       get_rostime=lambda: SimpleNamespace(to_nsec=lambda: self.now_ns))
        self.impl = SimpleNamespace(registration=SimpleNamespace(get_topic_manager=self._manager))

    def _manager(self) -> Any:
        return SimpleNamespace(pubs={name: SimpleNamespace(seq=seq) for name, seq in self.sent.items()})

    # the condition /clock's updates notify
    def __enter__(self) -> "FakeRospy":
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def wait(self, timeout: Optional[float] = None) -> bool:
        self.waits.append(timeout)
        if not self.steps:
            raise AssertionError(f"the sleep still waits at {self.now_ns / MS:g} ms and the clock has no further tick")
        step = self.steps.pop(0)
        if step == SHUTDOWN:
            self.shut_down = True
            if timeout is None:
                raise AssertionError("the sleep waits for ever: rospy's shutdown notifies no one")
            return False
        self.now_ns = int(step)
        return True


@pytest.fixture
def node(tmp_path, monkeypatch):
    """(rospy as the wrapper sees it, the student's ``pause(seconds)``, the wall-clock sleeps made)."""
    fake = FakeRospy()
    wall: List[float] = []
    original = time.sleep
    monkeypatch.setitem(sys.modules, "rospy", fake)
    monkeypatch.setattr(clock_sleep.time, "sleep", wall.append)
    assert install({ROOT_ENV: str(tmp_path / "student")})
    student = tmp_path / "student" / "node.py"
    student.parent.mkdir()
    student.write_text("import time\ndef pause(seconds):\n    return time.sleep(seconds)\n")
    namespace: Dict[str, Any] = {}
    exec(compile(student.read_text(), str(student), "exec"), namespace)
    yield fake, namespace["pause"], wall
    time.sleep = original


def _publishing(fake: FakeRospy, pause: Callable[[float], None]) -> None:
    """The thread's first sleep (wall clock: nothing published yet), then one message on its topic."""
    pause(0.001)
    fake.sent["/cmd_vel"] += 1


def test_a_sleep_after_the_node_published_ends_when_the_clock_reaches_its_end(node):
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_004 * MS, 1_009 * MS, 1_010 * MS, 1_011 * MS]
    pause(0.010)
    assert wall == [0.001]                 # the first sleep only: this one followed /clock
    assert fake.now_ns == 1_010 * MS       # ended at the tick that reached 1000 + 10 ms, not before nor after
    assert fake.steps == [1_011 * MS]


def test_a_sleep_that_follows_the_clock_waits_with_a_bound_so_a_shutdown_ends_it(node):
    """rospy's shutdown sets a flag and notifies no one: a wait without a timeout would never return."""
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_004 * MS, SHUTDOWN]
    pause(0.010)
    assert fake.shut_down and fake.steps == []
    assert all(timeout is not None for timeout in fake.waits)


def test_the_next_sleep_counts_from_the_last_wake_up_on_the_clock_not_from_when_it_is_asked(node):
    """rospy.Rate's rule: a loop that woke at 1010 ms and worked until the clock said 1013 ms sleeps until
    1020 ms, not 1023 ms (and not from when its first sleep was asked)."""
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_010 * MS]
    pause(0.010)                            # asked at 1000 ms, woke at the tick of 1010 ms
    fake.now_ns = 1_013 * MS                # the loop's work, while the clock stepped on
    fake.sent["/cmd_vel"] += 1
    fake.steps = [1_016 * MS, 1_020 * MS, 1_023 * MS]
    pause(0.010)
    assert fake.now_ns == 1_020 * MS and fake.steps == [1_023 * MS]
    assert wall == [0.001]


def test_the_wake_up_is_the_sleeps_end_on_the_clock_even_when_the_tick_came_late(node):
    """Woken by a tick past its end (1015 ms for an end of 1010 ms), the loop's next sleep still ends at 1020 ms."""
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_015 * MS]
    pause(0.010)
    fake.sent["/cmd_vel"] += 1
    fake.steps = [1_020 * MS, 1_025 * MS]
    pause(0.010)
    assert fake.now_ns == 1_020 * MS and fake.steps == [1_025 * MS]


def test_a_clock_that_goes_back_during_a_sleep_ends_it(node):
    """The grader starts a new run: /clock restarts from 0 and the old deadline would never come."""
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_004 * MS, 2 * MS, 5 * MS]
    pause(0.010)
    assert fake.now_ns == 2 * MS and fake.steps == [5 * MS]


def test_messages_on_rosout_alone_do_not_make_a_sleep_wait_for_the_clock(node):
    """A node that only logs has published nothing the grader steps the clock for: its wait keeps the wall clock."""
    fake, pause, wall = node
    pause(0.001)
    fake.sent["/rosout"] += 3
    pause(0.25)
    assert wall == [0.001, 0.25] and fake.waits == []


def test_a_thread_that_published_nothing_since_its_last_sleep_keeps_the_wall_clock(node):
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [1_010 * MS]
    pause(0.010)
    pause(0.5)                              # waiting for a subscriber, say: nothing sent since the last sleep
    assert wall == [0.001, 0.5]


def test_a_sleep_before_any_clock_message_keeps_the_wall_clock(node):
    """/clock at 0: the grader has not stepped yet (a node waiting for its subscribers)."""
    fake, pause, wall = node
    fake.now_ns = 0
    _publishing(fake, pause)
    pause(0.02)
    assert wall == [0.001, 0.02] and fake.waits == []


def test_a_sleep_at_the_first_nanosecond_of_the_clock_follows_it(node):
    fake, pause, wall = node
    fake.now_ns = 1
    _publishing(fake, pause)
    fake.steps = [10 * MS + 1]
    pause(0.010)
    assert wall == [0.001] and fake.now_ns == 10 * MS + 1


@pytest.mark.parametrize("state", ["not initialized", "wallclock", "shut down"])
def test_without_a_running_node_on_sim_time_sleep_keeps_the_wall_clock(node, state):
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.initialized = state != "not initialized"
    fake.wallclock = state == "wallclock"
    fake.shut_down = state == "shut down"
    pause(0.3)
    assert wall == [0.001, 0.3] and fake.waits == []


@pytest.mark.parametrize("seconds", [-1.0, -1e-9, float("nan"), None, [0.1]])
def test_a_duration_time_sleep_itself_refuses_goes_to_time_sleep(node, seconds):
    fake, pause, wall = node
    _publishing(fake, pause)
    pause(seconds)
    assert len(wall) == 2 and (wall[1] is seconds or wall[1] != wall[1]) and fake.waits == []


def test_a_zero_sleep_after_publishing_ends_at_once_on_the_clock(node):
    fake, pause, wall = node
    _publishing(fake, pause)
    pause(0.0)
    assert wall == [0.001] and fake.waits == []


def test_a_file_beside_the_students_folder_whose_name_starts_alike_keeps_the_wall_clock(node, tmp_path):
    """The student's folder is .../student: .../student2/node.py is not below it."""
    fake, pause, wall = node
    other = tmp_path / "student2" / "node.py"
    other.parent.mkdir()
    other.write_text("import time\ndef pause(seconds):\n    return time.sleep(seconds)\n")
    namespace: Dict[str, Any] = {}
    exec(compile(other.read_text(), str(other), "exec"), namespace)
    namespace["pause"](0.001)
    fake.sent["/cmd_vel"] += 1
    namespace["pause"](0.010)
    assert wall == [0.001, 0.010] and fake.waits == []


def test_each_thread_counts_its_own_messages_and_wake_ups(node):
    """The main loop published and slept; another thread's first sleep keeps the wall clock."""
    fake, pause, wall = node
    _publishing(fake, pause)
    other: List[BaseException] = []

    def worker() -> None:
        try:
            pause(0.2)
        except BaseException as exc:  # noqa: BLE001 - handed to the test thread
            other.append(exc)

    thread = threading.Thread(target=worker)
    thread.start()
    thread.join()
    assert other == [] and wall == [0.001, 0.2]


@pytest.mark.parametrize("seconds, end_ns", [(1.0, 2_000 * MS), (2.5, 3_500 * MS), (0.000_000_001, 1_000 * MS + 1)])
def test_a_sleep_ends_at_its_exact_nanosecond_on_the_clock(node, seconds, end_ns):
    fake, pause, wall = node
    _publishing(fake, pause)
    fake.steps = [end_ns - 1, end_ns, end_ns + 1]
    pause(seconds)
    assert fake.now_ns == end_ns and fake.steps == [end_ns + 1]


def test_the_clock_env_without_a_pythonpath_is_the_site_folder_alone(tmp_path):
    env = clock_sleep.student_clock_env(tmp_path)
    assert env == {ROOT_ENV: str(tmp_path.resolve()), "PYTHONPATH": str(clock_sleep.SITE_DIR)}
