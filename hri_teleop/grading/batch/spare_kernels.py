"""Kernels for ``make grade``, each started while the notebook before it still runs.

nbgrader runs a submission's notebooks one after another and waits for each new kernel to start
(0.7 s here). With this provisioner, starting a kernel also starts a spare with the same command,
folder and environment for the next notebook (grading/README.md). Only over Unix sockets: a spare's
socket files have a path of their own, so it never takes sockets another kernel was given;
``SPARES_ENV`` says how many spares this process may start. With ``POLICY_ENV`` set, every kernel
starts in the kernel sandbox (:mod:`hri_teleop.grading.run.kernel_sandbox`).
"""

from __future__ import annotations

import atexit
import os
import signal
import subprocess
import threading
import uuid
from dataclasses import dataclass
from typing import Any, Dict, List, Optional

from jupyter_client.connect import KernelConnectionInfo, write_connection_file
from jupyter_client.launcher import launch_kernel
from jupyter_client.provisioning.local_provisioner import LocalProvisioner

from hri_teleop.grading.run.kernel_sandbox import POLICY_ENV, boxed_command
from hri_teleop.grading.run.sandbox import SandboxError

__all__ = ["PROVISIONER", "PROVISIONER_ENV", "SPARES_ENV", "Spare", "SpareProvisioner", "spares_left", "stop_spare",
           "waiting_spare", "ending_kernels", "see_out", "wait_for_ending_kernels", "start_budget"]

#: The provisioner's entry-point name (pyproject.toml) and Jupyter's variable that picks it for
#: kernelspecs that name none, as the hri-teleop kernel.
PROVISIONER = "hri-spare-kernels"
PROVISIONER_ENV = "JUPYTER_DEFAULT_PROVISIONER_NAME"
#: How many spare kernels this process may start (unset or 0: none; the manager then works as Jupyter's).
SPARES_ENV = "HRI_SPARE_KERNELS"


def _boxed(cmd: List[str], connection_file: str, transport: str) -> List[str]:
    """``cmd`` in the kernel sandbox when make grade asks for it (:data:`POLICY_ENV` set), else as it is."""
    policy = os.environ.get(POLICY_ENV, "")
    if not policy:
        return cmd
    if transport != "ipc":
        raise SandboxError(f"{POLICY_ENV} is set but the kernel's transport is {transport!r}: the sandboxed kernel "
                           "is reached over Unix sockets; pass --KernelManager.transport=ipc (make grade does)")
    return boxed_command(cmd, connection_file, policy)


@dataclass
class Spare:
    process: "subprocess.Popen[bytes]"
    connection_file: str
    info: KernelConnectionInfo
    template: List[Optional[str]]  # the command, its connection file left out
    popen_kwargs: Dict[str, Any]


_lock = threading.Lock()
_spare: Optional[Spare] = None
_started = 0


def _budget() -> int:
    value = os.environ.get(SPARES_ENV, "0")
    return int(value) if value.isdigit() else 0


def spares_left() -> int:
    return max(0, _budget() - _started)


def waiting_spare() -> Optional[Spare]:
    """The kernel started ahead that no notebook has taken yet (None: none waits)."""
    with _lock:
        return _spare


def start_budget() -> None:
    """Count spares from zero again, as a new grading process would (the spare left, if any, is stopped)."""
    global _started
    stop_spare()
    with _lock:
        _started = 0


def _copy(popen_kwargs: Dict[str, Any]) -> Dict[str, Any]:
    return {key: dict(value) if isinstance(value, dict) else value for key, value in popen_kwargs.items()}


def _template(cmd: List[str], connection_file: str) -> List[Optional[str]]:
    return [None if arg == connection_file else arg for arg in cmd]


def _remove_files(spare: Spare) -> None:
    paths = [spare.connection_file] + [f"{spare.info['ip']}-{spare.info[name]}" for name in
                                       ("shell_port", "iopub_port", "stdin_port", "control_port", "hb_port")]
    for path in paths:
        try:
            os.remove(path)
        except OSError:
            pass


def _pop_spare() -> Optional[Spare]:
    global _spare
    with _lock:
        spare, _spare = _spare, None
    return spare


def stop_spare() -> None:
    """Stop the spare nobody took (at exit), its process group and its files."""
    spare = _pop_spare()
    if spare is not None:
        _stop(spare)


def _stop(spare: Spare) -> None:
    """Kill a spare (it has run no code: nothing to shut down cleanly) and remove its files."""
    try:
        os.killpg(spare.process.pid, signal.SIGKILL)  # Jupyter starts kernels in a session of their own
    except OSError:
        pass
    try:
        spare.process.wait(5.0)
    except subprocess.TimeoutExpired:
        pass
    _remove_files(spare)


_ending: List[threading.Thread] = []


def see_out(process: "subprocess.Popen[bytes]", pgid: Optional[int], wait_s: float) -> None:
    """What Jupyter does after a shutdown request, off its path: wait, then SIGTERM, then SIGKILL."""
    for signum in (None, signal.SIGTERM, signal.SIGKILL):
        if signum is not None:
            try:
                if pgid:
                    os.killpg(pgid, signum)
                else:
                    process.send_signal(signum)
            except OSError:
                pass
        try:
            process.wait(wait_s / 2)
            return
        except subprocess.TimeoutExpired:
            continue


def ending_kernels() -> List[threading.Thread]:
    """The threads still seeing a kernel out after its shutdown request."""
    return [thread for thread in list(_ending) if thread.is_alive()]


def wait_for_ending_kernels() -> None:
    """At exit: every kernel that was told to shut down has ended (each within its own bound)."""
    for thread in list(_ending):
        thread.join()


atexit.register(wait_for_ending_kernels)
atexit.register(stop_spare)  # atexit runs last-registered first: the spare goes, then the endings are awaited


def _take(template: List[Optional[str]], popen_kwargs: Dict[str, Any]) -> Optional[Spare]:
    """The spare if it is what this launch asks for; one that is not (or died) is stopped."""
    spare = _pop_spare()
    if spare is None:
        return None
    if spare.template == template and spare.popen_kwargs == popen_kwargs and spare.process.poll() is None:
        return spare
    _stop(spare)
    return None


def _start(km: Any, template: List[Optional[str]], popen_kwargs: Dict[str, Any]) -> None:
    global _spare, _started
    if km.transport != "ipc" or not spares_left() or getattr(km, "curve_publickey", None):
        return
    with _lock:
        _started += 1
        number = _started
    ip = f"{km.ip}-spare{os.getpid()}-{number}"
    folder = os.path.dirname(km.connection_file) or "."
    key = str(uuid.uuid4()).encode()
    fname, info = write_connection_file(
        fname=os.path.join(folder, f"kernel-spare-{uuid.uuid4()}.json"), ip=ip, transport="ipc",
        key=key, signature_scheme=km.session.signature_scheme, kernel_name=km.kernel_name)
    # bytes, as the kernel manager keeps it (its session.key); jupyter_client's TypedDict says str
    info["key"] = key  # type: ignore[typeddict-item]
    cmd = _boxed([fname if arg is None else arg for arg in template], fname, "ipc")
    process = launch_kernel(cmd, **_copy(popen_kwargs))  # it adds to the environment it is given
    with _lock:
        _spare = Spare(process, fname, info, template, popen_kwargs)


class SpareProvisioner(LocalProvisioner):
    """Jupyter's local provisioner, which takes a spare kernel when one fits and then starts the next."""

    _spare_file: Optional[str] = None

    async def launch_kernel(self, cmd: List[str], **kwargs: Any) -> KernelConnectionInfo:
        km = self.parent
        if km is None:  # no kernel manager to start a spare for (nor a connection file to box)
            if os.environ.get(POLICY_ENV):
                raise SandboxError(f"{POLICY_ENV} is set but the kernel has no manager: it cannot be sandboxed")
            return await super().launch_kernel(cmd, **kwargs)
        template = _template(cmd, km.connection_file)
        popen_kwargs = _copy(self._scrub_kwargs(kwargs))
        spare = _take(template, popen_kwargs)
        if spare is None:
            info = await super().launch_kernel(_boxed(cmd, km.connection_file, km.transport), **kwargs)
        else:
            self.process = spare.process
            self.pid = spare.process.pid
            try:
                self.pgid = os.getpgid(spare.process.pid)
            except OSError:
                self.pgid = None
            self.cwd = kwargs.get("cwd")
            self.connection_info = info = spare.info
            self._spare_file = spare.connection_file
            self.log.info("hri-teleop: took the spare kernel started ahead (pid %s)", spare.process.pid)
        _start(km, template, popen_kwargs)
        return info

    async def shutdown_requested(self, restart: bool = False) -> None:
        """The kernel was asked to shut down: let it end (stop its nodes, its roscore) while the next
        notebook starts; a thread waits for it and escalates as Jupyter would."""
        await super().shutdown_requested(restart)
        if restart or self.process is None or self.parent is None or not _budget():
            return  # Jupyter's own way outside make grade
        thread = threading.Thread(target=see_out, name=f"kernel-{self.pid}-ending", daemon=True,
                                  args=(self.process, self.pgid, float(self.parent.shutdown_wait_time)))
        thread.start()
        _ending[:] = [*ending_kernels(), thread]  # the ones seen out are dropped: a batch of 300 keeps a few
        self.process = None  # ended for Jupyter: the shutdown goes on at once

    async def cleanup(self, restart: bool = False) -> None:
        await super().cleanup(restart)
        if self._spare_file and not restart:
            try:
                os.remove(self._spare_file)
            except OSError:
                pass
