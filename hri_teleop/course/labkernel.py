"""``make lab``: JupyterLab on ``notebooks/`` with the "hri-teleop" kernel.

Why a kernel of our own: Jupyter's default ``python3`` kernel runs with whatever
environment the server was started in. The notebooks need the lab's shell -- ROS on the
path, ``hri_lab`` on ``ROS_PACKAGE_PATH``, ``.venv``'s Python with rospy -- also when
JupyterLab was started from a desktop icon or another terminal. The kernelspec therefore
starts ``tools/kernel.sh``, which sources ``tools/env.sh`` and then runs ``.venv``'s
Python. It is installed into ``.venv`` (``sys.prefix``), never into the user's home, so
removing ``.venv`` removes it, and it is rewritten only when it changed.

    python -m hri_teleop.course.labkernel [--install-only] [--notebooks FOLDER] [jupyter lab options...]
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Sequence

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import REPO

__all__ = ["KERNEL_NAME", "LabError", "kernelspec", "install_kernelspec", "lab_command", "ipc_kernel_config",
           "ipc_kernel_argv", "main"]

KERNEL_NAME = "hri-teleop"


class LabError(HriTeleopError, RuntimeError):
    """JupyterLab cannot be started as asked (one line with the fix)."""


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
        raise LabError(f"cannot write the kernelspec {target} ({exc.strerror}): check that {folder.parent} "
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
    from traitlets.config import Config

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


def lab_command(notebook_dir: Path, extra: Sequence[str] = ()) -> List[str]:
    """The ``jupyter lab`` command line: ``notebook_dir`` as the root, the hri-teleop kernel by default."""
    command = [sys.executable, "-m", "jupyterlab", f"--ServerApp.root_dir={notebook_dir}",
               f"--MultiKernelManager.default_kernel_name={KERNEL_NAME}"]
    if os.geteuid() == 0:
        command.append("--allow-root")  # containers and CI run as root; jupyter refuses without it
    return command + list(extra)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    install_only = "--install-only" in args
    args = [a for a in args if a != "--install-only"]
    notebooks = REPO / "notebooks"
    if "--notebooks" in args:  # the student bundle: JupyterLab on the bundle's folder
        at = args.index("--notebooks")
        if at + 1 >= len(args):
            print("lab: --notebooks needs a folder, e.g. --notebooks $(pwd)", file=sys.stderr)
            return 1
        notebooks = Path(args[at + 1])
        del args[at:at + 2]
    try:
        import ipykernel  # noqa: F401, PLC0415
        import jupyterlab  # noqa: F401, PLC0415 - only to say what is missing
    except ImportError as exc:
        print(f"lab: {exc.name} is not installed: run `make setup` (it installs the project's [lab] extra)",
              file=sys.stderr)
        return 1
    try:
        folder = install_kernelspec()
    except LabError as exc:
        print(f"lab: {exc}", file=sys.stderr)
        return 1
    print(f"lab: kernel {KERNEL_NAME!r} ({folder})", flush=True)
    if install_only:
        return 0
    notebooks.mkdir(exist_ok=True)
    command = lab_command(notebooks, args)
    os.execv(command[0], command)
    return 0  # pragma: no cover - execv does not return


if __name__ == "__main__":
    sys.exit(main())
