"""Student processes under limits (hri_teleop.grading.run.sandbox), without ROS: fork bombs, floods, writes."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from pathlib import Path

import pytest
from grading_helpers import open_folder

from hri_teleop.grading.run.sandbox import (
    DEFAULT_LIMITS,
    Limits,
    StudentProcess,
    bwrap_problem,
    describe_exit,
    student_uid,
)


def wait_until(condition, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)
    return True


@pytest.fixture
def tmp_path():
    """A folder the student's uid can enter (pytest's own is private to root)."""
    yield from open_folder("hri-sandbox-test-")


def _start(tmp_path: Path, code: str, limits: Limits = DEFAULT_LIMITS) -> StudentProcess:
    """``code`` as student/x.py, started as the grader starts a student's node (own uid where root)."""
    folder = tmp_path / "student"
    folder.mkdir(exist_ok=True)
    uid = student_uid()
    if uid is not None:
        os.chown(folder, uid, uid)
    (folder / "x.py").write_text(code)
    return StudentProcess([sys.executable, str(folder / "x.py")], folder, {"PATH": os.environ["PATH"]},
                          tmp_path / "x.log", limits, uid=uid, nested=True, network=False)


def _run(tmp_path: Path, code: str, limits: Limits = DEFAULT_LIMITS, timeout_s: float = 20.0):
    proc = _start(tmp_path, code, limits)
    code = proc.wait(timeout_s)
    proc.stop()
    return code, proc


def test_a_fork_bomb_hits_the_process_limit_and_leaves_nothing_behind(tmp_path):
    code, proc = _run(tmp_path, "import os, time\nn = 0\ntry:\n    while n < 2000:\n        if os.fork() == 0:\n"
                                "            time.sleep(60)\n            os._exit(0)\n        n += 1\n"
                                "except OSError as e:\n    print('stopped after', n, e.errno)\n",
                      Limits(processes=40))
    out = proc.output_tail()
    assert "stopped after" in out, out
    assert int(out.split("stopped after")[1].split()[0]) <= 40
    if proc.uid is not None:
        assert proc.process_count() == 0, "forked children outlived the stop"
    else:
        pytest.skip("not root: no uid of its own to count leftovers by")


def test_output_beyond_the_cap_ends_the_process_with_a_clear_reason(tmp_path):
    from hri_teleop.grading.judge.compare_common import process_hints
    from hri_teleop.grading.run.records import ProcessFacts

    cap = DEFAULT_LIMITS.file_bytes
    code, proc = _run(tmp_path, "import sys\nwhile True:\n    sys.stdout.write('x' * 65536)\n")
    # Python ignores SIGXFSZ: the write fails with EFBIG and the program ends with an error
    assert code not in (None, 0)
    assert cap - 65536 <= proc.output_size() <= cap
    facts = ProcessFacts(exit_code=code, output_bytes=proc.output_size(), output_tail=proc.output_tail())
    assert any("output limit" in hint for hint in process_hints(facts))
    assert "output limit" in describe_exit(-signal.SIGXFSZ)


def test_a_hang_is_stopped_by_the_caller_and_cpu_time_is_capped(tmp_path):
    code, proc = _run(tmp_path, "while True:\n    pass\n", Limits(cpu_s=1), timeout_s=10)
    assert code in (-signal.SIGXCPU, -signal.SIGKILL), code
    assert "CPU" in describe_exit(code) or "killed" in describe_exit(code)


@pytest.mark.skipif(bool(bwrap_problem()), reason="bubblewrap not usable here: the grader runs with limits only")
def test_with_bubblewrap_only_the_own_folder_is_writable_and_there_is_no_network(tmp_path):
    outside = tmp_path / "outside.txt"  # beside the student's folder, in the machine's /tmp
    shown = Path(sys.prefix) / "hri-outside.txt"  # in a folder the box shows (read-only)
    code, proc = _run(tmp_path, f"import socket\nopen('mine.txt', 'w').write('ok')\n"
                                f"open({str(outside)!r}, 'w').write('in the box')\n"
                                f"try:\n    open({str(shown)!r}, 'w')\nexcept OSError as e:\n    print('write', e.errno)\n"
                                "s = socket.socket()\ntry:\n    s.connect(('1.1.1.1', 80))\nexcept OSError as e:\n"
                                "    print('net', e.errno)\n")
    out = proc.output_tail()
    assert code == 0, out
    assert (tmp_path / "student" / "mine.txt").read_text() == "ok"
    assert not outside.exists(), "the box's /tmp is its own: nothing reaches the machine's"
    assert not shown.exists() and "write 30" in out  # EROFS
    assert "net " in out


def test_student_code_sees_only_the_variables_ros_and_python_need():
    from hri_teleop.grading.run.sandbox import student_environment

    env = student_environment({"PATH": "/bin", "ROS_MASTER_URI": "http://127.0.0.1:1/", "LC_ALL": "C",
                               "GITHUB_TOKEN": "secret", "AWS_SECRET_ACCESS_KEY": "x", "HOME": "/root",
                               "ROS_SECRET_TOKEN": "x", "LC_CANVAS_TOKEN": "x", "HRI_CANVAS_TOKEN": "x",
                               "PYTHON_KEYRING_PASSWORD": "x"})
    assert env == {"PATH": "/bin", "ROS_MASTER_URI": "http://127.0.0.1:1/", "LC_ALL": "C", "HOME": "/root"}


def test_bubblewrap_is_used_for_a_checkout_whose_python_lies_under_tmp(tmp_path):
    """The probe once hid /tmp behind a tmpfs, so a checkout under /tmp fell back to no sandbox."""
    import subprocess
    import sys
    import venv

    from hri_teleop.grading.run import sandbox

    if sandbox.bwrap_problem() and "HRI_GRADE_SANDBOX" not in os.environ:
        pytest.skip(f"no bubblewrap here: {sandbox.bwrap_problem()}")
    assert str(tmp_path).startswith("/tmp/"), tmp_path
    venv.EnvBuilder(system_site_packages=True, with_pip=False).create(tmp_path / ".venv")
    code = ("import importlib.util, sys; spec = importlib.util.spec_from_file_location('sb', sys.argv[1]); "
            "m = importlib.util.module_from_spec(spec); sys.modules['sb'] = m; spec.loader.exec_module(m); "
            "print(repr(m.bwrap_problem()))")
    env = {k: v for k, v in os.environ.items() if k != "HRI_GRADE_SANDBOX"}
    out = subprocess.run([str(tmp_path / ".venv" / "bin" / "python"), "-c", code, sandbox.__file__],
                         capture_output=True, text=True, timeout=60, env=env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "''", f"python under /tmp: {out.stdout.strip()}"
    assert sys.executable  # the test's own interpreter is not the one probed


def test_checks_graded_side_by_side_get_uids_of_their_own_and_one_ending_leaves_the_other_running(tmp_path):
    """A check's end kills every process of its uid: two threads of one grader (hri-grade submission's
    checks side by side) shared one uid, so one check's end killed the other's node (I13: the
    answer key's mapping node SIGKILLed before it subscribed)."""
    uids: dict = {}

    def in_thread(name: str, body) -> None:
        thread = threading.Thread(target=lambda: uids.__setitem__(name, body()))
        thread.start()
        thread.join(60)

    in_thread("a", student_uid)
    in_thread("b", student_uid)
    main_uid = student_uid()
    if main_uid is None:
        pytest.skip("not root: student code runs as the grader's own uid")
    assert len({main_uid, uids["a"], uids["b"]}) == 3
    folder = tmp_path / "student"
    folder.mkdir()
    folder.chmod(0o755)
    (folder / "sleep.py").write_text("import time\ntime.sleep(60)\n")
    started, other_ended = threading.Event(), threading.Event()
    seen = {}

    def sleeper_check() -> None:
        # the whole check in its own thread, as grade_submission runs it: a child started by a
        # thread is ended when that thread ends (bubblewrap's --die-with-parent follows the thread)
        proc = StudentProcess([sys.executable, str(folder / "sleep.py")], folder, {"PATH": os.environ["PATH"]},
                              tmp_path / "a.log", DEFAULT_LIMITS, uid=student_uid(), nested=True, network=False)
        try:
            seen["up"] = wait_until(lambda: proc.process_count() > 0, 30)
            started.set()
            other_ended.wait(60)
            seen["running"] = proc.running
        finally:
            proc.stop()

    def other_check() -> None:
        proc = StudentProcess([sys.executable, "-c", "pass"], folder, {"PATH": os.environ["PATH"]},
                              tmp_path / "b.log", DEFAULT_LIMITS, uid=student_uid(), nested=True, network=False)
        proc.wait(20)
        proc.stop()  # kills every process of its uid

    sleeper = threading.Thread(target=sleeper_check)
    sleeper.start()
    try:
        assert started.wait(60) and seen["up"]
        in_thread("other", other_check)
    finally:
        other_ended.set()
        sleeper.join(60)
    assert seen["running"], "the other check's end killed this check's process"


_SLOW_TO_END = """import os, signal, subprocess, sys, time
def asked(sig, frame):
    open(os.path.join(os.path.dirname(__file__), "asked"), "w").write(str(sig))
    time.sleep(30)  # a node whose shutdown takes its time
signal.signal(signal.SIGINT, asked)
signal.signal(signal.SIGTERM, asked)
# a child in a session of its own, as roslaunch starts its nodes
subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"], start_new_session=True)
open(os.path.join(os.path.dirname(__file__), "up"), "w").write("1")
time.sleep(60)
"""


def test_a_run_whose_verdict_is_recorded_is_killed_without_being_asked_and_leaves_nothing(tmp_path):
    """kill() (a clean run of a check, everything judged recorded) sends no SIGINT: a node's shutdown
    (rospy's 0.5 s poll, or one that takes its time) is not waited for; its children go too."""
    proc = _start(tmp_path, _SLOW_TO_END)
    folder = tmp_path / "student"
    assert wait_until(lambda: (folder / "up").exists() or not proc.running, 30) and proc.running, proc.output_tail()
    assert proc.kill() == -signal.SIGKILL
    assert not (folder / "asked").exists(), "kill() asked the node to end first"
    if proc.uid is not None:
        assert proc.process_count() == 0, "its child outlived the kill"


def test_a_process_that_fills_its_folder_with_many_files_is_stopped_with_the_reason(tmp_path):
    """Each file is capped (RLIMIT_FSIZE), not how many: a node once wrote 1.5 GB of 2 MB files in 1.5 s."""
    from hri_teleop.grading.run.sandbox import folder_bytes

    limits = Limits(disk_bytes=8 * 1024 ** 2)
    code, proc = _run(tmp_path, "import os\nfor i in range(300):\n    with open(f'f{i}.bin', 'wb') as fh:\n"
                                "        fh.write(os.urandom(1 << 20))\nprint('done')\n", limits)
    out = proc.output_tail()
    assert proc.disk_exceeded and "done" not in out, out
    assert code is not None and code < 0, code  # killed, not ended by itself
    assert "wrote more than 8 MB into its folder" in out, out
    assert folder_bytes(tmp_path / "student", 1 << 40) < 300 * (1 << 20)


def test_a_process_that_writes_a_little_is_not_stopped(tmp_path):
    code, proc = _run(tmp_path, "open('small.bin', 'wb').write(b'x' * (1 << 20))\nprint('done')\n",
                      Limits(disk_bytes=8 * 1024 ** 2))
    assert code == 0 and not proc.disk_exceeded and "done" in proc.output_tail()


@pytest.mark.parametrize("size,counted", [(1000, 1000), (0, 0)])
def test_folder_bytes_counts_regular_files_and_not_what_links_lead_to(tmp_path, size, counted):
    from hri_teleop.grading.run.sandbox import folder_bytes

    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "f").write_bytes(b"x" * size)
    os.symlink("/usr", tmp_path / "d" / "usr")  # a folder link: not walked
    os.symlink("/usr/bin/python3", tmp_path / "d" / "python3")  # a file link: not counted
    assert folder_bytes(tmp_path / "d", 1 << 40) == counted
