"""time.sleep under the grader's clock: when a sleep ends, whose calls are wrapped, and the site hook."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.grading.run import clock_sleep
from hri_teleop.grading.run.clock_sleep import ROOT_ENV, SITE_DIR, deadline_ns, install, student_clock_env

MS = 10**6


def test_a_first_sleep_ends_one_duration_from_now():
    assert deadline_ns(5_000 * MS, None, 10 * MS) == 5_010 * MS


def test_a_sleep_asked_at_the_instant_of_the_last_wake_up_ends_one_duration_after_it():
    assert deadline_ns(5_000 * MS, 5_000 * MS, 10 * MS) == 5_010 * MS


def test_a_sleep_asked_one_whole_duration_after_the_last_wake_up_ends_at_once():
    """The tick this sleep waits for reached the node before it slept: it is not waited for again."""
    assert deadline_ns(5_010 * MS, 5_000 * MS, 10 * MS) == 5_010 * MS


def test_a_sleep_asked_more_than_one_duration_after_the_last_wake_up_starts_from_now():
    assert deadline_ns(5_010 * MS + 1, 5_000 * MS, 10 * MS) == 5_020 * MS + 1


def test_a_clock_that_went_back_starts_the_sleep_from_now():
    assert deadline_ns(4_999 * MS, 5_000 * MS, 10 * MS) == 5_009 * MS


@given(now=st.integers(1, 10**12), last=st.one_of(st.none(), st.integers(1, 10**12)), duration=st.integers(0, 10**9))
def test_a_sleep_never_ends_before_now_nor_later_than_one_duration_from_now(now, last, duration):
    end = deadline_ns(now, last, duration)
    assert now <= end <= now + duration


def test_the_clock_env_puts_the_site_folder_first_once_and_names_the_folder(tmp_path):
    env = student_clock_env(tmp_path, os.pathsep.join(["/opt/ros", str(SITE_DIR), ""]))
    assert env["PYTHONPATH"].split(os.pathsep) == [str(SITE_DIR), "/opt/ros"]
    assert env[ROOT_ENV] == str(tmp_path.resolve())


@pytest.fixture
def restore_sleep():
    original = time.sleep
    yield
    time.sleep = original


def test_without_the_folder_named_time_sleep_stays_the_builtin(restore_sleep):
    before = time.sleep
    assert install({}) is False
    assert time.sleep is before


def test_installed_twice_it_wraps_once(restore_sleep, tmp_path):
    assert install({ROOT_ENV: str(tmp_path)})
    wrapped = time.sleep
    assert install({ROOT_ENV: str(tmp_path)})
    assert time.sleep is wrapped


def test_a_call_from_outside_the_students_folder_keeps_the_wall_clock(restore_sleep, tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(clock_sleep.time, "sleep", calls.append)
    install({ROOT_ENV: str(tmp_path)})
    time.sleep(0.25)  # this file is not below tmp_path
    assert calls == [0.25]


def test_a_call_from_the_students_folder_without_rospy_keeps_the_wall_clock(restore_sleep, tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(clock_sleep.time, "sleep", calls.append)
    monkeypatch.delitem(sys.modules, "rospy", raising=False)
    install({ROOT_ENV: str(tmp_path)})
    student = tmp_path / "student.py"
    student.write_text("import time\ndef pause():\n    time.sleep(0.5)\n")
    namespace: dict = {}
    exec(compile(student.read_text(), str(student), "exec"), namespace)
    namespace["pause"]()
    assert calls == [0.5]


def test_the_site_hook_wraps_sleep_and_then_runs_the_next_sitecustomize(tmp_path):
    nxt = tmp_path / "next"
    nxt.mkdir()
    (nxt / "sitecustomize.py").write_text("print('next sitecustomize ran')\n")
    repo = str(SITE_DIR.parents[3])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SITE_DIR), repo, str(nxt)]), **{ROOT_ENV: str(tmp_path)})
    out = subprocess.run([sys.executable, "-c", "import time; print(type(time.sleep.__self__).__name__)"],
                         env=env, capture_output=True, text=True, timeout=60, check=True).stdout.split()
    assert out == ["next", "sitecustomize", "ran", "_Sleeper"]


def test_a_thread_that_published_since_its_last_sleep_waits_for_the_clock():
    assert clock_sleep.follows_clock(published=7, published_at_last_sleep=6)


def test_a_thread_that_published_nothing_since_its_last_sleep_keeps_the_wall_clock():
    """A wait for a subscriber before the loop: the grader steps only once the node published."""
    assert not clock_sleep.follows_clock(published=6, published_at_last_sleep=6)


def test_a_threads_first_sleep_keeps_the_wall_clock():
    assert not clock_sleep.follows_clock(published=6, published_at_last_sleep=None)


def test_without_rospys_count_of_messages_sleep_keeps_the_wall_clock():
    assert not clock_sleep.follows_clock(published=None, published_at_last_sleep=3)
