"""The "hri-teleop" Jupyter kernel: ``.venv``'s Python in the lab's ROS shell.

Jupyter's default kernel runs in whatever environment the server was started in; the
notebooks need ROS on the path and ``hri_lab`` on ``ROS_PACKAGE_PATH``, so the kernelspec
starts ``tools/kernel.sh``. ``make lab``, the release tools and the grader all use it.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional

from traitlets.config import Config

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import REPO

__all__ = ["KERNEL_NAME", "KernelError", "kernelspec", "install_kernelspec", "ipc_kernel_config", "ipc_kernel_argv"]

KERNEL_NAME = "hri-teleop"


class KernelError(HriTeleopError, RuntimeError):
    """The kernelspec cannot be installed (one line with the fix)."""


def kernelspec(repo: Path = REPO) -> Dict[str, object]:
    """The kernel.json content: tools/kernel.sh of ``repo`` runs ipykernel in the lab's shell."""
    return {
        "argv": ["bash", str(repo / "tools" / "kernel.sh"), "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "Python 3 (hri-teleop, ROS)",
        "language": "python",
        "interrupt_mode": "signal",
        "metadata": {"debugger": True},
    }


def install_kernelspec(repo: Path = REPO, prefix: Optional[Path] = None) -> Path:
    """Write ``<prefix>/share/jupyter/kernels/hri-teleop/kernel.json`` if it differs; returns its folder."""
    folder = Path(prefix if prefix is not None else sys.prefix) / "share" / "jupyter" / "kernels" / KERNEL_NAME
    text = json.dumps(kernelspec(repo), indent=1) + "\n"
    target = folder / "kernel.json"
    try:
        if not target.is_file() or target.read_text(encoding="utf-8") != text:
            folder.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise KernelError(f"cannot write the kernelspec {target} ({exc.strerror}): check that {folder.parent} "
                       "is writable, or run `make clean setup`") from None
    return folder


@contextmanager
def ipc_kernel_config() -> Iterator[Any]:
    """A traitlets Config whose kernels talk over Unix sockets in a private folder (removed after).

    Jupyter's default TCP transport picks five free ports and closes them before the kernel
    binds them: with kernels, roscores and nodes starting side by side another process can
    take one first and the kernel dies ("Kernel died before replying to kernel_info").
    Socket files in a folder of our own have no such race.
    """
    folder = tempfile.mkdtemp(prefix="hri-kernel-")
    config = Config()
    config.KernelManager.transport = "ipc"
    config.KernelManager.ip = os.path.join(folder, "k")
    try:
        yield config
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def ipc_kernel_argv(folder: Path) -> List[str]:
    """The same as command-line options for a Jupyter app (nbgrader) run as a subprocess, sockets in ``folder``."""
    return ["--KernelManager.transport=ipc", f"--KernelManager.ip={folder / 'k'}"]
