"""What the student-bundle tests share (tests/integration/test_student_bundle.py, tests/bench/test_bench_selfcheck.py,
tests/container/): one bundle unpacked and set up per test run, copies of it, the answer key copied into a bundle,
and the points `make check` prints."""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Dict, Iterator, Optional, Tuple

import pytest

#: What the run's one bundle is (its course, its folder, set up or why not, who is done with it), beside the
#: lock that guards it.
_STATE = "student-bundle.json"
#: The test files that use it: the last of them to be done removes it (1.4 GB; else the run's end does).
USERS = ("integration/test_student_bundle.py", "bench/test_bench_selfcheck.py")


def __getattr__(name: str) -> object:
    """copy_answer_key (hri_teleop.course.release's, which loads nbgrader: 1.3 s), imported when a test asks."""
    if name == "copy_answer_key":
        from hri_teleop.course.release import copy_answer_key

        return copy_answer_key
    raise AttributeError(name)


def student_env() -> dict:
    """Only the machine's own PATH: no project .venv, no ROS_PACKAGE_PATH pointing at this checkout."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "VIRTUAL_ENV", "PYTHON", "HRI_"))}
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if ".venv" not in p)
    env["SDL_VIDEODRIVER"] = env["SDL_AUDIODRIVER"] = "dummy"
    return env


def make(bundle: Path, *args: str, timeout: float, extra_env: Optional[Dict[str, str]] = None
         ) -> subprocess.CompletedProcess:
    """``make -C bundle ARGS`` in a student's shell."""
    env = dict(student_env(), **(extra_env or {}))
    return subprocess.run(["make", "-C", str(bundle), *args], capture_output=True, text=True, timeout=timeout,
                          env=env, stdin=subprocess.DEVNULL)


def _run_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The test run's temporary folder: every xdist worker's is a folder of it."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@contextlib.contextmanager
def _shared_state(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict]:
    """The run's bundle state, read and written under an exclusive lock (one worker at a time)."""
    folder = _run_folder(tmp_path_factory)
    with open(folder / "student-bundle.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        state_file = folder / _STATE
        state = json.loads(state_file.read_text()) if state_file.is_file() else {}
        before = dict(state)
        try:
            yield state
        finally:
            if state != before:
                state_file.write_text(json.dumps(state))


def shared_bundle(tmp_path_factory: pytest.TempPathFactory) -> Tuple[Path, Path]:
    """(course, bundle): the course copied with its student versions generated, and its bundle packed as
    `make release` packs it, unpacked where no checkout is (benchmarks.selfcheck.unpack_bundle), in a home the
    grader's student uid may read. Made once per test run, by whichever test asks first; not to be changed
    (work in a :func:`bundle_copy`)."""
    from benchmarks.selfcheck import unpack_bundle

    with _shared_state(tmp_path_factory) as state:
        if state.get("removed"):
            pytest.fail("the run's shared bundle was removed when its users were done: add this test file to "
                        "tests/bundle_helpers.USERS")
        if "bundle" not in state:
            work = Path(tempfile.mkdtemp(prefix="hri-student-home-"))
            work.chmod(0o755)
            state["work"] = str(work)  # removed at the run's end (remove_shared_bundle)
            course, bundle = unpack_bundle(work)
            state.update(course=str(course), bundle=str(bundle))
        return Path(state["course"]), Path(state["bundle"])


def shared_installed_bundle(tmp_path_factory: pytest.TempPathFactory) -> Tuple[Path, Path]:
    """(course, bundle): :func:`shared_bundle` after the bundle's `make setup` (its own venv with the toolkit, as
    on a student's machine), run once per test run; a failed setup fails every test that needs it, with its output."""
    course, bundle = shared_bundle(tmp_path_factory)
    with _shared_state(tmp_path_factory) as state:
        if "setup" not in state:
            done = make(bundle, "setup", timeout=1200)
            state["setup"] = "" if done.returncode == 0 else f"exit {done.returncode}\n" + done.stdout[-2000:] + \
                done.stderr[-2000:]
        if state["setup"]:
            pytest.fail(f"the bundle's make setup failed: {state['setup']}")
    return course, bundle


def done_with_shared_bundle(tmp_path_factory: pytest.TempPathFactory, user: str) -> None:
    """``user`` (one of :data:`USERS`) needs the shared bundle no more; the last of them removes it."""
    with _shared_state(tmp_path_factory) as state:
        state["done"] = sorted(set(state.get("done", [])) | {user})
        if "work" in state and set(USERS) <= set(state["done"]) and not state.get("removed"):
            shutil.rmtree(state["work"], ignore_errors=True)
            state["removed"] = True


def remove_shared_bundle(run_folder: Path) -> None:
    """At the run's end (the controller's session finish): the shared bundle's folder, if a test made one and
    not all of its users ran."""
    state_file = run_folder / _STATE
    if state_file.is_file():
        state = json.loads(state_file.read_text())
        if "work" in state and not state.get("removed"):
            shutil.rmtree(state["work"], ignore_errors=True)


def bundle_copy(installed: Path, home: Path, name: str) -> Path:
    """A student's folder ``home/name/task4`` copied from a set-up bundle, sharing its .venv (set up once)."""
    bundle = home / name / "task4"
    shutil.copytree(installed, bundle, symlinks=True, ignore=shutil.ignore_patterns(".venv"))
    os.symlink(installed / "toolkit" / ".venv", bundle / "toolkit" / ".venv")
    (home / name).chmod(0o755)
    return bundle


def notebook_points(output: str) -> dict:
    """notebook -> (points, possible) of make check's notebook lines."""
    scores = {}
    for line in output.splitlines():
        if line.strip().endswith(")") and "points (" in line and ".ipynb ... " in line:
            name = line.split("/")[1].split(".ipynb")[0]
            got, most = line.split(" ... ")[1].split(" points")[0].split("/")
            scores[name.strip()] = (float(got), float(most))
    return scores


def files_points(output: str) -> tuple:
    """(points, possible) of make check's line for the files (the checks' points are the files')."""
    line = next(line for line in output.splitlines() if line.endswith("points for your files, beside the "
                                                                        "notebooks' autograded points above"))
    got, most = line.split("check: ")[1].split(" points")[0].split("/")
    return float(got), float(most)
