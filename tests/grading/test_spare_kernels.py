"""make grade's kernels (hri_teleop.grading.batch.spare_kernels): the next notebook's kernel is started
while the one before runs, a kernel that does not fit is stopped, and a kernel told to shut down
ends off nbgrader's path but always ends."""

from __future__ import annotations

import os
import signal
import time

import nbformat
import pytest
from jupyter_client.manager import AsyncKernelManager
from jupyter_client.provisioning.factory import KernelProvisionerFactory
from nbclient import NotebookClient
from traitlets.config import Config

from hri_teleop.grading.batch import spare_kernels as spare


@pytest.fixture
def kernels(tmp_path, monkeypatch):
    """Run small notebooks as nbgrader does (Unix sockets, a new kernel each) with ``spares`` allowed."""
    monkeypatch.setattr(KernelProvisionerFactory.instance(), "default_provisioner_name", spare.PROVISIONER)
    spare.wait_for_ending_kernels()
    spare.start_budget()
    sockets = tmp_path / "sockets"
    sockets.mkdir()
    config = Config()
    config.KernelManager.transport = "ipc"
    config.KernelManager.ip = str(sockets / "k")
    config.KernelManager.shutdown_wait_time = 2.0

    def run(source: str, spares: int, cwd=tmp_path) -> str:
        monkeypatch.setenv(spare.SPARES_ENV, str(spares))
        nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(source)])
        NotebookClient(nb, kernel_name="python3", config=config, kernel_manager_class=AsyncKernelManager,
                       resources={"metadata": {"path": str(cwd)}}).execute()
        return "".join(o.get("text", "") for o in nb.cells[0].outputs).strip()

    yield run, sockets
    spare.stop_spare()
    spare.wait_for_ending_kernels()


PID = "import os; print(os.getpid())"


def test_each_notebook_runs_in_the_kernel_started_while_the_one_before_ran(kernels):
    run, sockets = kernels
    first = run(PID, spares=2)
    ahead = spare.waiting_spare().process.pid
    assert run(PID, spares=2) == str(ahead)
    ahead = spare.waiting_spare().process.pid
    assert run(PID, spares=2) == str(ahead)
    assert spare.waiting_spare() is None and spare.spares_left() == 0  # the budget is spent: nothing idles
    assert int(first) != ahead


def test_without_a_budget_no_kernel_is_started_ahead(kernels):
    run, _ = kernels
    run(PID, spares=0)
    assert spare.waiting_spare() is None
    assert run(PID, spares=0) != run(PID, spares=0)


def test_a_spare_that_does_not_fit_is_stopped_and_a_kernel_started_as_usual(kernels, tmp_path):
    run, _ = kernels
    run(PID, spares=3)
    unfit = spare.waiting_spare().process
    other = tmp_path / "elsewhere"
    other.mkdir()
    assert run("import os; print(os.getpid(), os.getcwd())", spares=3, cwd=other).split() != [str(unfit.pid)]
    assert unfit.poll() is not None
    assert run("import os; print(os.getcwd())", spares=3, cwd=other) == str(other)


def test_a_spare_nobody_took_is_stopped_with_its_files(kernels):
    run, sockets = kernels
    run(PID, spares=1)
    left = spare.waiting_spare()
    deadline = time.monotonic() + 20
    while len(list(sockets.iterdir())) < 5 and time.monotonic() < deadline:  # it bound its sockets
        time.sleep(0.05)
    spare.stop_spare()
    assert left.process.poll() is not None
    assert not os.path.exists(left.connection_file)
    assert list(sockets.iterdir()) == []


@pytest.fixture
def endings(monkeypatch):
    """Every kernel seen out after its shutdown request: (its process, the wait it was given); the
    escalation's waits stretched by ``stretch`` (a test that needs the kernel alive for a while)."""
    seen = []
    real = spare.see_out
    stretch = [1.0]

    def recorded(process, pgid, wait_s):
        seen.append((process, wait_s))
        real(process, pgid, wait_s * stretch[0])

    monkeypatch.setattr(spare, "see_out", recorded)
    return seen, stretch


HOLD = """import atexit, os, time
def _hold(path={release!r}):
    while not os.path.exists(path):
        time.sleep(0.01)
atexit.register(_hold)
print(os.getpid())"""


def test_a_kernel_told_to_shut_down_ends_while_the_next_notebook_starts(kernels, endings, tmp_path):
    run, _ = kernels
    seen, stretch = endings
    stretch[0] = 30.0  # SIGTERM only after 30 s (a hang guard): here it ends when its exit hook returns
    release = tmp_path / "release"
    pid = int(run(HOLD.format(release=str(release)), spares=1))
    # nbclient returned while the kernel's exit hook still holds it (it waits for a file not yet written):
    # had nbclient waited for the kernel to end, it would have killed it after shutdown_wait_time
    assert os.path.exists(f"/proc/{pid}") and open(f"/proc/{pid}/stat").read().split()[2] != "Z"
    assert [p.pid for p, _ in seen] == [pid] and len(spare.ending_kernels()) == 1
    release.touch()
    spare.wait_for_ending_kernels()
    assert seen[0][0].returncode == 0  # it ended by itself, not by a signal
    assert not os.path.exists(f"/proc/{pid}") or open(f"/proc/{pid}/stat").read().split()[2] == "Z"


def test_a_kernel_that_will_not_end_is_killed_as_jupyter_would(kernels, endings):
    run, _ = kernels
    seen, _ = endings
    pid = int(run("import atexit, os, time; atexit.register(time.sleep, 600); print(os.getpid())", spares=1))
    spare.wait_for_ending_kernels()
    # Jupyter's escalation with the kernel manager's shutdown_wait_time (2 s): SIGTERM, then SIGKILL
    [(process, wait_s)] = seen
    assert process.pid == pid and wait_s == 2.0
    assert process.returncode in (-signal.SIGTERM, -signal.SIGKILL)
    assert not os.path.exists(f"/proc/{pid}") or open(f"/proc/{pid}/stat").read().split()[2] == "Z"
