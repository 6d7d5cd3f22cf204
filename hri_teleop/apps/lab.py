"""``make lab``: JupyterLab on ``notebooks/`` with the "hri-teleop" kernel (:mod:`hri_teleop.ros.kernel`).

The kernelspec goes into ``.venv`` (``sys.prefix``), never the user's home, so removing
``.venv`` removes it. With ``--notebooks`` (the student bundle's ``make lab``) JupyterLab shows
students only nbgrader's student side: the instructors' formgrader, course list, nbgrader menu and
"Create Assignment" panel are off (:func:`student_config`), and nbgrader finds a configuration.

    python -m hri_teleop.apps.lab [--install-only] [--notebooks FOLDER] [jupyter lab options...]
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Dict, List, Mapping, Optional, Sequence

from hri_teleop.core.paths import REPO
from hri_teleop.ros.kernel import KERNEL_NAME, KernelError, install_kernelspec

__all__ = ["lab_command", "student_config", "student_env", "INSTRUCTOR_LABEXTENSIONS", "INSTRUCTOR_SERVER_EXTENSIONS",
           "main"]

#: nbgrader's JupyterLab plugins for instructors (the formgrader, the course list, the nbgrader menu
#: that opens them, the "Create Assignment" panel); students keep the assignment list and Validate.
INSTRUCTOR_LABEXTENSIONS = ("@jupyter/nbgrader:menu", "@jupyter/nbgrader:formgrader",
                            "@jupyter/nbgrader:create-assignment", "@jupyter/nbgrader:course-list")
#: The server extensions behind them.
INSTRUCTOR_SERVER_EXTENSIONS = ("nbgrader.server_extensions.formgrader", "nbgrader.server_extensions.course_list")

#: The students' nbgrader configuration: the course's id and its execution limits (notebooks/nbgrader_config.py).
STUDENT_NBGRADER_CONFIG = """# The student's side of nbgrader for Task 4 (written by `make lab`; the course's own config is the
# instructors'). Validate runs a notebook as the grader does, with the same limits.
c = get_config()
c.CourseDirectory.course_id = "hri-task4-teleoperation"
c.Execute.timeout = 300
c.Execute.startup_timeout = 120
c.Execute.interrupt_on_timeout = True
"""


def student_config(prefix: Path = Path(sys.prefix)) -> Path:
    """A Jupyter configuration folder for the students' JupyterLab (in ``prefix``, the toolkit's .venv).

    On JUPYTER_CONFIG_PATH it comes before the installed packages' own settings (the .venv's etc/jupyter,
    where nbgrader enables everything) and the user's: the instructors' plugins and server
    extensions are off, and nbgrader reads its nbgrader_config.py (else it warns that it found none).
    """
    files = {
        Path("labconfig", "page_config.json"): json.dumps(
            {"disabledExtensions": {name: True for name in INSTRUCTOR_LABEXTENSIONS}}, indent=2) + "\n",
        Path("jupyter_server_config.json"): json.dumps(
            {"ServerApp": {"jpserver_extensions": {name: False for name in INSTRUCTOR_SERVER_EXTENSIONS}}}, indent=2) + "\n",
        Path("nbgrader_config.py"): STUDENT_NBGRADER_CONFIG,
    }
    # The container's toolkit belongs to root (written at its build, by --install-only) and runs as the
    # student: a folder that is as it should be is left alone; one that cannot be written, replaced by /tmp's.
    for folder in (prefix / "etc" / "hri-teleop-student-jupyter",
                   Path(tempfile.gettempdir()) / f"hri-teleop-student-jupyter-{os.getuid()}"):
        try:
            for relative, text in files.items():
                path = folder / relative
                if not path.is_file() or path.read_text(encoding="utf-8") != text:
                    path.parent.mkdir(parents=True, exist_ok=True)
                    path.write_text(text, encoding="utf-8")
            return folder
        except OSError:
            continue
    raise KernelError(f"cannot write the students' Jupyter configuration in {prefix / 'etc'} or {tempfile.gettempdir()}: "
                      "make them writable, or run make setup again")


def student_env(environ: Mapping[str, str], config: Path) -> Dict[str, str]:
    """``environ`` with ``config`` first on JUPYTER_CONFIG_PATH."""
    env = dict(environ)
    rest = [p for p in env.get("JUPYTER_CONFIG_PATH", "").split(os.pathsep) if p and p != str(config)]
    env["JUPYTER_CONFIG_PATH"] = os.pathsep.join([str(config), *rest])
    return env


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
    student = "--notebooks" in args
    if student:  # the student bundle: JupyterLab on the bundle's folder
        at = args.index("--notebooks")
        if at + 1 >= len(args):
            print("lab: --notebooks needs a folder, e.g. --notebooks $(pwd)", file=sys.stderr)
            return 1
        notebooks = Path(args[at + 1])
        del args[at:at + 2]
    try:
        import ipykernel  # noqa: F401, PLC0415 - only to say what is missing
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
    try:
        config = student_config()  # also at --install-only: a container's build writes it as root
    except KernelError as exc:
        print(f"lab: {exc}", file=sys.stderr)
        return 1
    if install_only:
        return 0
    notebooks.mkdir(exist_ok=True)
    command = lab_command(notebooks, args)
    env = student_env(os.environ, config) if student else dict(os.environ)
    os.execve(command[0], command, env)
    return 0  # pragma: no cover - execv does not return


if __name__ == "__main__":
    sys.exit(main())
