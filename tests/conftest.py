"""Shared fixtures: a private roscore per test that needs one, headless pygame."""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from typing import TYPE_CHECKING, Iterator

import pytest
from hypothesis import settings

if TYPE_CHECKING:
    from hri_teleop.ros.lab_twin import LabTwin

# Hypothesis judges each example's duration by default (200 ms): on a busy machine that is a
# speed assertion. No test judges time; a hung example is caught by pytest's own guards.
settings.register_profile("hri-teleop", deadline=None)
# The Python 3.8 run (unit/test_python38_compatible.py) asks whether the code runs there at all: each
# property's code paths, not another 100 random examples the 3.11 run already tried.
COMPAT_EXAMPLES = 10
COMPAT = os.environ.get("HRI_TEST_COMPAT") == "1"
settings.register_profile("compat", deadline=None, max_examples=COMPAT_EXAMPLES)
settings.load_profile("compat" if COMPAT else "hri-teleop")

REPO = Path(__file__).resolve().parents[1]

# The suite pins the Panda's numbers: a lab shell's HRI_ROBOT=fr3 (tools/env.sh keeps it) must not change them
# (tests/unit/test_robot_fr3.py runs the FR3 in processes of its own).
os.environ.pop("HRI_ROBOT", None)
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
# The simulated arm solves a 7 x 7 system every millisecond; older OpenBLAS builds (numpy 1.24,
# Python 3.8) run it on a second thread that spins, burning a core the other nodes need.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


# The modules that keep a worker busy longest, longest first (worker-seconds of `make test` on the 2-core
# machine beside other jobs, 2026-11-29: about 2.4 times an idle run's). `make test` hands each file to one
# worker (--dist loadfile) in collection order; a long file that starts last leaves the other workers idle
# while it finishes. This is the schedule only: no test depends on it, and a module missing here just runs
# after these.
LONGEST_FIRST = [
    "integration/test_student_bundle.py",         # 1260 s (its make setup: 650)
    "unit/test_python38_compatible.py",           # 531 s (one test: the core's unit tests on Python 3.8)
    "integration/test_lab_twin_notebooks.py",     # 377 s
    "notebooks/test_notebooks_run.py",            # 320 s
    "grading/test_gradescope.py",                 # 354 s
    "grading/test_instructors_guide.py",          # 354 s
    "grading/test_adding_an_exercise.py",         # ~350 s (130-160 s alone: a copy released, graded, checked)
    "grading/test_corpus.py",                     # 305 s
    "grading/test_kernel_reports.py",             # 235 s
    "grading/test_notebook_sandbox.py",           # 214 s
    "bench/test_bench_grading.py",                # 210 s
    "grading/test_make_grade_nbgrader.py",        # 199 s
    "integration/test_lab_twin.py",               # 197 s
    "integration/test_study_end_to_end.py",       # 193 s
    "bench/test_bench_selfcheck.py",              # 417 s (its bundle's make setup, and 85 s removing it)
    "grading/test_node_feedback_runs.py",         # 164 s
    "integration/test_lab_simulation.py",         # 154 s
    "grading/test_ex10_drive.py",                 # 154 s
    "unit/test_arm_kernel.py",                    # 152 s
    "integration/test_teleoperation_node.py",     # 133 s
    "integration/test_doctor.py",                 # 129 s
    "integration/test_browser_pad.py",            # 120 s
    "integration/test_catkin_workspace.py",       # 103 s
    "grading/test_hostile_output.py",             # 99 s
    "integration/test_lab_twin_launch.py",        # 97 s
    "integration/test_lab_modes.py",              # 97 s
    "integration/test_arm_view_browser.py",       # 95 s
    "unit/test_experiment.py",                    # 91 s
    "grading/test_late_hostile.py",               # 89 s
    "grading/test_command_cells.py",              # 85 s
    "grading/test_make_grade.py",                 # 84 s
    "grading/test_hostile_inputs.py",             # 82 s
    "integration/test_lab_sim_node.py",           # 78 s
]


def pytest_configure(config: pytest.Config) -> None:
    from hri_teleop.ros.proc_table import start_ticks

    config._hri_started_ticks = start_ticks(os.getpid()) or 0  # type: ignore[attr-defined]


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """The run's controller (not an xdist worker): fail the run when it left a process behind."""
    if hasattr(session.config, "workerinput"):
        return
    from leftovers import reap

    left = reap(REPO, getattr(session.config, "_hri_started_ticks", 0))
    if left:
        session.config._hri_leftovers = left  # type: ignore[attr-defined]
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, exitstatus: int, config: pytest.Config) -> None:
    left = getattr(config, "_hri_leftovers", [])
    if left:
        terminalreporter.section("processes the run left behind (killed now)", red=True)
        for pid, command in left:
            terminalreporter.write_line(f"{pid}: {command[:300]}")


def pytest_collection_modifyitems(config: pytest.Config, items: list) -> None:
    """Put the longest modules first (see LONGEST_FIRST); the rest keep their order after them."""
    rank = {name: index for index, name in enumerate(LONGEST_FIRST)}
    tests_dir = Path(__file__).resolve().parent
    gone = [name for name in LONGEST_FIRST if not (tests_dir / name).is_file()]
    if gone:
        raise pytest.UsageError(f"tests/conftest.py LONGEST_FIRST names files that are gone: {', '.join(gone)}; "
                                "rename or drop them there")

    def key(item: pytest.Item) -> int:
        try:
            name = Path(str(item.fspath)).resolve().relative_to(tests_dir).as_posix()
        except ValueError:
            return len(rank)
        return rank.get(name, len(rank))

    items.sort(key=key)  # stable: within a module, and among the rest, the order stays
    if os.environ.get("HRI_TEST_CONTAINER") != "1":
        later = pytest.mark.skip(reason="the container's test takes minutes and downloads a Debian base: "
                                        "`make test-container` runs it")
        for item in items:
            if item.get_closest_marker("container"):
                item.add_marker(later)
    if COMPAT:
        for item in items:  # a test's own @settings(max_examples=...) too
            _cap_examples(getattr(item, "obj", None))


def _cap_examples(test: object) -> None:
    """At most COMPAT_EXAMPLES examples for a property test (hypothesis keeps its settings on the test)."""
    own = getattr(test, "_hypothesis_internal_use_settings", None)
    if own is not None and own.max_examples > COMPAT_EXAMPLES:
        test._hypothesis_internal_use_settings = settings(own, max_examples=COMPAT_EXAMPLES)  # type: ignore[attr-defined]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: object) -> Iterator[None]:
    """With HRI_TEST_CPU_LOG=path: one JSON line per test of the CPU seconds it cost (this process and
    the children it waited for: roscore, nodes, kernels), when it ran and on which worker, to see
    where a 2-core machine's time goes. The Python 3.8 run's tests (test_python38_compatible.py's pytest
    inherits the variable and the worker's name) are marked "compat": true."""
    path = os.environ.get("HRI_TEST_CPU_LOG")
    if not path:
        yield
        return
    import json
    import resource

    def cpu_s() -> float:
        own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime

    import time

    before, start = cpu_s(), time.time()
    yield
    with open(path, "a") as fh:
        fh.write(json.dumps({"test": item.nodeid, "cpu_s": round(cpu_s() - before, 3), "start": round(start, 3),
                             "end": round(time.time(), 3), "worker": os.environ.get("PYTEST_XDIST_WORKER", ""), "compat": COMPAT})
                 + "\n")


def _ros_env() -> dict:
    """The environment tools/env.sh gives: venv first on PATH, hri_lab on ROS_PACKAGE_PATH."""
    from hri_teleop.ros.master import lab_shell_env

    return lab_shell_env(venv_bin=REPO / ".venv" / "bin", package_root=REPO)


@pytest.fixture
def ros_env() -> dict:
    """Environment for ROS command-line tools that need no master (roslaunch --files)."""
    return _ros_env()


@pytest.fixture
def ros_master(tmp_path):
    """A real roscore on a free port, private to this test, stopped afterwards."""
    if shutil.which("roscore") is None:
        pytest.fail("roscore not found: run 'make setup' (installs ROS 1) or source tools/env.sh")
    from hri_teleop.ros.master import PrivateMaster

    master = PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros")
    master.start()
    try:
        yield master
    finally:
        master.stop()
        left = [" ".join(p.argv) for p in master.started if p.anything_left]
        assert not left, f"still running after the test: {left}"


def _running_twin(folder: Path) -> Iterator["LabTwin"]:
    """A started lab twin in ``folder``; stopped afterwards, asserting nothing it started is left running."""
    if shutil.which("roscore") is None:
        pytest.fail("roscore not found: run 'make setup' (installs ROS 1) or source tools/env.sh")
    from hri_teleop.ros.lab_twin import LabTwin

    twin = LabTwin(folder, base_env=_ros_env())
    twin.start()
    try:
        yield twin
    finally:
        twin.stop()
        left = [" ".join(p.argv) for p in twin.started() if p.anything_left]
        assert not left, f"still running after the test: {left}"


@pytest.fixture
def lab_twin(tmp_path):
    """A lab twin (hri_teleop.ros.lab_twin) on its own master, private to this test, stopped afterwards.

    The twin is started with the robot activated and serial_node's ~publish_period_ms 10; a test that
    needs another start builds its own ``LabTwin``. Asserts that nothing the twin started is left running.
    """
    yield from _running_twin(tmp_path / "twin")


@pytest.fixture(scope="module")
def module_lab_twin(tmp_path_factory):
    """The same twin, shared by the tests of one module (an expensive fixture of theirs runs on it)."""
    yield from _running_twin(tmp_path_factory.mktemp("lab-twin"))


@pytest.fixture
def foreign_roscore(tmp_path):
    """A real roscore on a free port that no PrivateMaster of this process started: to the toolkit's
    rules a master somebody else started, as the lab PC's is. ``.uri``, ``.env`` (no HRI_OWN_MASTER)."""
    from types import SimpleNamespace

    from hri_teleop.ros.master import OWN_MASTER_ENV, ManagedProcess, free_port
    from hri_teleop.ros.master_api import master_reachable, running_nodes

    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    env = dict(_ros_env(), ROS_MASTER_URI=uri, ROS_HOSTNAME="127.0.0.1", ROS_LOG_DIR=str(tmp_path / "log"),
               ROS_HOME=str(tmp_path / "home"))
    env.pop(OWN_MASTER_ENV, None)
    core = ManagedProcess(["roscore", "-p", str(port)], env, tmp_path / "roscore.log", is_master=True)
    try:
        while not (master_reachable(uri) and running_nodes(among=["/rosout"], uri=uri)):
            assert core.running, core.output()
            assert core.wait(0.05) is None, core.output()
        yield SimpleNamespace(uri=uri, env=env, core=core)
    finally:
        core.stop()
        assert not core.anything_left, "the foreign roscore was left running"

