"""started_here: a master counts as this kernel's only when the master itself answers with the pid recorded
at its start. A stale or copied HRI_OWN_MASTER, or a port another master took over, is the lab's.

The master is described as it answers getPid; the process table as /proc would list it. No master runs.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Dict, List, Optional

import pytest

from hri_teleop.ros import master as master_module
from hri_teleop.ros.master import OWN_MASTER_ENV, started_here
from hri_teleop.ros.master_api import MasterApiError

PORT = 11523
ROSCORE_PID = 4100     # the roscore this process started
ROSMASTER_PID = 4107   # the rosmaster it spawned: the pid getPid answers


@pytest.fixture
def world(monkeypatch):
    """``answers``: URI (as the caller wrote it) -> the pid its master answers (absent: none answers);
    ``children``: pid -> its descendants; ``own``: URI -> a roscore this process started."""
    state: Dict[str, object] = {"answers": {}, "children": {}}
    own: Dict[str, object] = {}

    def master_call(method: str, *args: object, uri: Optional[str] = None, timeout_s: float = 5.0) -> int:
        assert method == "getPid"
        state.setdefault("timeouts", []).append(timeout_s)  # type: ignore[union-attr]
        answers = state["answers"]
        assert isinstance(answers, dict)
        if uri not in answers:
            raise MasterApiError(f"no master at {uri}")
        return int(answers[uri])

    def descendants(root: int) -> List[int]:
        children = state["children"]
        assert isinstance(children, dict)
        return list(children.get(root, []))

    monkeypatch.setattr(master_module, "master_call", master_call)
    monkeypatch.setattr(master_module, "descendants", descendants)
    monkeypatch.setattr(master_module, "_OWN_MASTERS", own)
    monkeypatch.delenv(OWN_MASTER_ENV, raising=False)
    state["own"] = own
    return state


def _started(world, uri: str, running: bool = True) -> None:
    """This process started a roscore (pid ROSCORE_PID) whose rosmaster is ROSMASTER_PID, registered as ``uri``."""
    world["own"][master_module.uri_key(uri)] = SimpleNamespace(running=running, popen=SimpleNamespace(pid=ROSCORE_PID))
    world["children"][ROSCORE_PID] = [ROSMASTER_PID, ROSMASTER_PID + 1]


# --- a master this process started ---------------------------------------------------------------------------------

def test_a_master_started_here_through_roscore_is_ours_by_its_rosmasters_pid(world):
    """roscore spawns rosmaster: the pid the master answers is a descendant of the process we started."""
    uri = f"http://127.0.0.1:{PORT}"
    _started(world, uri)
    world["answers"][uri] = ROSMASTER_PID
    assert started_here(uri)


def test_a_master_started_here_answering_with_the_started_pid_itself_is_ours(world):
    uri = f"http://127.0.0.1:{PORT}"
    _started(world, uri)
    world["answers"][uri] = ROSCORE_PID
    assert started_here(uri)


def test_a_port_ours_once_but_now_answered_by_another_master_is_not_ours(world):
    """Our roscore still runs (or its record does), but the master on the port is a stranger's."""
    uri = f"http://127.0.0.1:{PORT}"
    _started(world, uri)
    world["answers"][uri] = 9999
    assert not started_here(uri)


@pytest.mark.parametrize("registered, asked", [
    (f"http://127.0.0.1:{PORT}", f"http://localhost:{PORT}/"),
    (f"http://localhost:{PORT}/", f"http://127.0.0.1:{PORT}"),
    (f"http://localhost:{PORT}", f"http://localhost:{PORT}/"),
    (f"http://127.0.0.1:{PORT}", f"127.0.0.1:{PORT}"),          # without the scheme
    (f"localhost:{PORT}", f"http://127.0.0.1:{PORT}/"),
    (f"http://:{PORT}", f"http://localhost:{PORT}"),            # no host: this machine's
])
def test_localhost_and_127_0_0_1_name_the_same_master(world, registered, asked):
    _started(world, registered)
    world["answers"][asked] = ROSMASTER_PID
    assert started_here(asked)


def test_a_master_on_another_host_is_not_the_local_one_of_the_same_port(world):
    _started(world, f"http://127.0.0.1:{PORT}")
    world["answers"][f"http://labpc:{PORT}"] = ROSMASTER_PID
    assert not started_here(f"http://labpc:{PORT}")


def test_a_master_that_does_not_answer_is_not_ours(world):
    _started(world, f"http://127.0.0.1:{PORT}")
    assert not started_here(f"http://127.0.0.1:{PORT}")


# --- a master the parent process started (HRI_OWN_MASTER) ----------------------------------------------------------

def test_the_parents_master_named_in_hri_own_master_with_the_pid_it_answers_is_ours(world):
    uri = f"http://localhost:{PORT}"
    world["answers"][uri] = ROSMASTER_PID
    assert started_here(uri, env={OWN_MASTER_ENV: f"http://127.0.0.1:{PORT} {ROSMASTER_PID}"})


def test_the_mark_is_read_from_the_environment_by_default(world, monkeypatch):
    uri = f"http://127.0.0.1:{PORT}"
    world["answers"][uri] = ROSMASTER_PID
    monkeypatch.setenv(OWN_MASTER_ENV, f"{uri} {ROSMASTER_PID}")
    assert started_here(uri)


@pytest.mark.parametrize("answered", [ROSMASTER_PID + 1, ROSMASTER_PID - 1, 1])
def test_a_stale_or_copied_hri_own_master_whose_pid_the_master_does_not_answer_is_not_ours(world, answered):
    """A notebook copied from a kernel whose master ended, the port now the lab's master: not ours."""
    uri = f"http://127.0.0.1:{PORT}"
    world["answers"][uri] = answered
    world["children"][ROSMASTER_PID] = [answered]  # only a master we started counts its descendants
    assert not started_here(uri, env={OWN_MASTER_ENV: f"{uri} {ROSMASTER_PID}"})


@pytest.mark.parametrize("mark", [
    "",
    f"http://127.0.0.1:{PORT}",                              # no pid
    f"http://127.0.0.1:{PORT} {ROSMASTER_PID} extra",
    f"http://127.0.0.1:{PORT + 1} {ROSMASTER_PID}",          # another port
    f"http://127.0.0.1:{PORT} pid{ROSMASTER_PID}",
    f"http://127.0.0.1:{PORT} -{ROSMASTER_PID}",
])
def test_a_mark_that_does_not_name_this_master_and_a_pid_is_not_ours(world, mark):
    uri = f"http://127.0.0.1:{PORT}"
    world["answers"][uri] = ROSMASTER_PID
    assert not started_here(uri, env={OWN_MASTER_ENV: mark})


def test_a_master_started_here_that_ended_falls_back_to_the_mark(world):
    """Our roscore stopped and somebody's master took the port: only a mark naming its pid makes it ours."""
    uri = f"http://127.0.0.1:{PORT}"
    _started(world, uri, running=False)
    world["answers"][uri] = ROSMASTER_PID  # a descendant of the roscore we started, but that one ended
    assert not started_here(uri, env={})
    assert started_here(uri, env={OWN_MASTER_ENV: f"{uri} {ROSMASTER_PID}"})


@pytest.mark.parametrize("bound_s", [0.3, 2.5])
def test_the_master_is_asked_within_the_callers_bound_so_a_hung_master_cannot_hang_the_kernel(world, bound_s):
    uri = f"http://127.0.0.1:{PORT}"
    _started(world, uri)
    world["answers"][uri] = ROSMASTER_PID
    assert started_here(uri, timeout_s=bound_s)
    assert world["timeouts"] == [bound_s]
