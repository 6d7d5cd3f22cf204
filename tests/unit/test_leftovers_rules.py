"""What the run's end counts as its leftovers, on a process table the test writes: an orphan of this checkout
(its parent pid 1 or a subreaper), started at or after the run began; those that end within the grace are let
go, the others killed and named. No process is started or killed; the grace runs on a clock the test steps.
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import SimpleNamespace
from typing import Dict, List, Tuple

import leftovers as module
import pytest
from leftovers import leftovers, reap

REPO = "/work/checkout"
SINCE = 5_000       # the run's start, in clock ticks since boot
ME = 4242           # the test run's own pid


@pytest.fixture
def table(monkeypatch):
    """``procs``: pid -> (ppid, state, start ticks, command line); ``comm``: pid -> its name; ``killed``: the
    SIGKILLs sent; ``ends``: pid -> the wait (0, 1, ...) after which it is gone; ``clock``: the grace's clock."""
    procs: Dict[int, Tuple[int, bytes, object, str]] = {}
    comm: Dict[int, str] = {1: "systemd"}
    killed: List[int] = []
    ends: Dict[int, int] = {}
    clock = SimpleNamespace(now=100.0, waits=0)

    def proc_table() -> Dict[int, Tuple[int, bytes]]:
        gone = {pid for pid, after in ends.items() if clock.waits > after}
        return {pid: (ppid, state) for pid, (ppid, state, _t, _c) in procs.items() if pid not in gone}

    def sleep(seconds: float) -> None:
        clock.now += seconds
        clock.waits += 1

    def kill(pid: int, sig: int) -> None:
        killed.append(pid)

    monkeypatch.setattr(module, "proc_table", proc_table)
    monkeypatch.setattr(module, "start_ticks", lambda pid: procs[pid][2] if pid in procs else None)
    monkeypatch.setattr(module, "_comm", lambda pid: comm.get(pid, ""))
    monkeypatch.setattr(module, "_cmdline", lambda pid: procs[pid][3] if pid in procs else "")
    monkeypatch.setattr(module, "time", SimpleNamespace(monotonic=lambda: clock.now, sleep=sleep))
    monkeypatch.setattr(module, "os", SimpleNamespace(getpid=lambda: ME, kill=kill))
    return SimpleNamespace(procs=procs, comm=comm, killed=killed, ends=ends, clock=clock)


def _orphan(table, pid: int, ticks: object = SINCE + 10, parent: int = 1, state: bytes = b"S",
            command: str = f"python3 {REPO}/hri_lab/scripts/lab_sim.py") -> None:
    table.procs[pid] = (parent, state, ticks, command)


# --- which processes are the run's leftovers -------------------------------------------------------------------

@pytest.mark.parametrize("ticks, found", [(SINCE - 1, False), (SINCE, True), (SINCE + 1, True), (None, False)])
def test_an_orphan_counts_only_if_it_started_at_or_after_the_run_began(table, ticks, found):
    """One left by an earlier run (or before this one) is not this run's to kill, nor its failure."""
    _orphan(table, 700, ticks=ticks)
    assert (leftovers(REPO, SINCE) == [(700, f"python3 {REPO}/hri_lab/scripts/lab_sim.py")]) is found


@pytest.mark.parametrize("reaper", ["init", "systemd", "tini", "docker-init", "dumb-init"])
def test_an_orphan_handed_to_a_subreaper_counts_like_one_handed_to_pid_1(table, reaper):
    """In a container (tini, docker-init, dumb-init) or under a user's systemd, orphans go to a subreaper."""
    table.comm[30] = reaper
    _orphan(table, 701, parent=30)
    assert [pid for pid, _c in leftovers(REPO, SINCE)] == [701]


@pytest.mark.parametrize("parent_name", ["bash", "python3", "roslaunch", ""])
def test_a_process_whose_parent_still_runs_is_not_a_leftover(table, parent_name):
    table.comm[31] = parent_name
    _orphan(table, 702, parent=31)
    assert leftovers(REPO, SINCE) == []


@pytest.mark.parametrize("state, found", [(b"Z", False), (b"X", False), (b"S", True), (b"R", True), (b"D", True)])
def test_a_zombie_or_dead_orphan_is_not_counted(table, state, found):
    _orphan(table, 703, state=state)
    assert bool(leftovers(REPO, SINCE)) is found


def test_an_orphan_of_another_folder_and_the_run_itself_are_not_counted(table):
    _orphan(table, 704, command="python3 /home/someone/other/lab_sim.py")
    _orphan(table, ME)
    _orphan(table, 705)
    assert [pid for pid, _c in leftovers(REPO, SINCE)] == [705]


# --- the grace, then SIGKILL -------------------------------------------------------------------------------------

def test_an_orphan_that_ends_within_the_grace_is_neither_killed_nor_named(table):
    """A node ending its shutdown as the run ends: gone after the first wait."""
    _orphan(table, 800)
    table.ends[800] = 0
    assert reap(Path(REPO), SINCE, grace_s=10.0) == []
    assert table.killed == [] and table.clock.waits == 1


def test_an_orphan_that_outlives_the_grace_is_killed_and_named(table):
    _orphan(table, 801)
    _orphan(table, 802)
    table.ends[802] = 3  # gone after the fourth wait
    left = reap(Path(REPO), SINCE, grace_s=10.0)
    assert [pid for pid, _c in left] == [801] and table.killed == [801]
    assert table.clock.now >= 110.0  # it waited the whole grace before killing


def test_without_a_grace_the_orphans_are_killed_at_once(table):
    _orphan(table, 803)
    table.ends[803] = 0
    assert [pid for pid, _c in reap(Path(REPO), SINCE, grace_s=0.0)] == [803]
    assert table.killed == [803] and table.clock.waits == 0


def test_an_orphan_gone_before_its_kill_is_named_and_the_rest_are_still_killed(table, monkeypatch):
    _orphan(table, 804)
    _orphan(table, 805)

    def kill(pid: int, sig: int) -> None:
        if pid == 804:
            raise ProcessLookupError(pid)
        table.killed.append(pid)

    monkeypatch.setattr(module, "os", SimpleNamespace(getpid=lambda: ME, kill=kill))
    assert [pid for pid, _c in reap(Path(REPO), SINCE, grace_s=0.0)] == [804, 805]
    assert table.killed == [805]



# --- how a leftover is named -------------------------------------------------------------------------------------

def test_a_leftover_is_named_by_its_command_line_with_spaces_even_with_bytes_that_are_not_utf_8():
    """Read from /proc for real: a child started here (not an orphan), read once it says it runs, then ended."""
    import subprocess

    python, code = sys.executable, "import sys; print(flush=True); sys.stdin.read()"
    child = subprocess.Popen([python, "-c", code, b"marker-\xff", "last"], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE)
    try:
        assert child.stdout is not None and child.stdout.readline() == b"\n"
        assert module._cmdline(child.pid) == f"{python} -c {code} marker-\ufffd last"
    finally:
        child.communicate(b"")
