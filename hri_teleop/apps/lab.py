"""``make lab``: JupyterLab on ``notebooks/`` with the "hri-teleop" kernel (:mod:`hri_teleop.ros.kernel`).

The kernelspec goes into ``.venv`` (``sys.prefix``), never the user's home, so removing
``.venv`` removes it.

    python -m hri_teleop.apps.lab [--install-only] [--notebooks FOLDER] [jupyter lab options...]
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import List, Optional, Sequence

from hri_teleop.core.paths import REPO
from hri_teleop.ros.kernel import KERNEL_NAME, KernelError, install_kernelspec

__all__ = ["lab_command", "main"]


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
    except KernelError as exc:
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
