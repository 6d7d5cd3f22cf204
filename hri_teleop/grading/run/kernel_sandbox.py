"""Student notebooks' Jupyter kernels in bubblewrap: how make grade and the Gradescope autograder start them.

A kernel runs the student's code, so it gets what a student process gets (grading/README.md,
"Notebooks' kernels"): a scratch folder of its own (a tmpfs of a fixed size holding a copy of the
submission), no view of the instructor's files, a network namespace with loopback only (its roscore
lives there) and a process limit. The launcher itself is :mod:`.kernel_box`; this is what the grader calls.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from dataclasses import replace
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.run import kernel_box
from hri_teleop.grading.run.kernel_box import (
    CHANNEL,
    CHECK_RESULTS,
    ERROR_MARK,
    POLICY_ENV,
    Box,
    KernelBoxError,
    KernelPolicy,
)
from hri_teleop.grading.run.sandbox import bwrap_problem

__all__ = ["POLICY_ENV", "CHECK_RESULTS", "ERROR_MARK", "KernelPolicy", "boxed_command", "kernel_sandbox",
           "kernel_sandbox_problem"]

#: Loads the launcher from its file (no import of the grader's package) and runs it on the arguments after it.
_BOOT = ("import importlib.util, sys; spec = importlib.util.spec_from_file_location('hri_kernel_box', sys.argv[1]); "
         "box = importlib.util.module_from_spec(spec); sys.modules['hri_kernel_box'] = box; "
         "spec.loader.exec_module(box); sys.exit(box.main(sys.argv[2:]))")


def boxed_command(cmd: Sequence[str], connection_file: str, policy: str) -> List[str]:
    """``cmd`` (a kernelspec's argv, its connection file filled in) started in a box by the launcher."""
    return [sys.executable, "-c", _BOOT, kernel_box.__file__, "--connection-file", connection_file, "--policy", policy,
            "--", *cmd]


_tried: Dict[bool, str] = {}


def _try(policy: KernelPolicy) -> str:
    """'' when a box with ``policy``'s mounts is filled and runs ``true`` here, else why not."""
    folder = tempfile.mkdtemp(prefix="hri-kernel-probe-")
    with tempfile.TemporaryFile() as said:  # bwrap's own words, for the reason
        try:
            os.chmod(folder, 0o755)
            box = Box(["true"], folder, policy, os.environ, stderr=said.fileno())
            try:
                box.wait_ready()
                box.fill([([("probe", "f", 0o644, b"probe")], folder)], [(f"{CHANNEL}/probe", b"probe")])
                box.release()
            except KernelBoxError as exc:
                box.kill()
                raise exc
            code = box.process.wait()
            if code == 0:
                return ""
            problem = f"a kernel's box exits with status {code}"
        except (KernelBoxError, OSError) as exc:
            problem = str(exc).replace(ERROR_MARK, "").replace("; its message is above", "")
        finally:
            shutil.rmtree(folder, ignore_errors=True)
        said.seek(0)
        lines = said.read().decode(errors="replace").strip().splitlines()
    return f"{problem}: {lines[-1]}" if lines else problem


def kernel_sandbox(policy: KernelPolicy) -> Tuple[Optional[KernelPolicy], str]:
    """(``policy`` as kernels can run with it here, '') or (None, why they cannot: one line).

    Tried for real, once per process: a box with ``policy``'s mounts is filled and runs ``true``.
    Where the box may not mount a /proc of its own (a container: bwrap says "Can't mount proc"),
    it shows the machine's instead.
    """
    problem = bwrap_problem()
    if problem:
        return None, problem
    for own_proc in (True, False):
        if own_proc not in _tried:
            _tried[own_proc] = _try(replace(policy, own_proc=own_proc))
        if not _tried[own_proc]:
            return replace(policy, own_proc=own_proc), ""
    return None, _tried[True]


def kernel_sandbox_problem(policy: Optional[KernelPolicy] = None) -> str:
    """'' when notebooks' kernels can be boxed here, else why not (:func:`kernel_sandbox`)."""
    return kernel_sandbox(policy or KernelPolicy())[1]
