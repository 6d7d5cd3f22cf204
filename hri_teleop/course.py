"""The nbgrader course of Task 4 (``notebooks/``): what its notebooks call, and what the instructor runs.

Why a module: the notebooks carry no logic of their own, and the release has rules that
must hold every time (templates generated from ``solutions/``, no solution text in the
student bundle, no outputs in committed notebooks). Both halves live here:

* **In a notebook**: :func:`score` (the last line of an autograded cell: prints the
  grader's feedback, returns the points for nbgrader's partial credit), the two halves of
  the teleoperation check (:func:`grade_teleoperation_parts` for Ex. 8,
  :func:`grade_teleoperation_node` for Ex. 9), :func:`show_file` (where a student file is,
  a link that opens it in JupyterLab's editor, its text) and :func:`fast` / :func:`seconds`
  (the MIT course's flag: under ``make test``, ``nbgrader validate`` and ``autograde``
  long real-time cells run short, with the same functions).
* **For the instructor**: :func:`build_release` (``make release``: nbgrader's
  ``generate_assignment``, then the templates of the student files, then
  :func:`bundle_leaks` must find nothing), :func:`notebook_output_problems` and
  :func:`strip_outputs` (notebooks are committed without outputs), :func:`check_course`
  (every source notebook runs and gets full marks, nbgrader's ``validate --invert`` finds
  no autograded cell passing in any student version).
* **Between the two**: running nodes from a cell (:func:`run_provided_node`,
  :func:`run_student_node`, :func:`launch_student`, :func:`launch`, :func:`stop_nodes`) on
  the kernel's master from :func:`hri_teleop.notebook_ros.ensure_ros`.

Course layout (``notebooks/README.md``): ``source/<assignment>/<notebook>.ipynb`` and, beside
the notebooks, ``hri_lab``: in ``source/`` a link to the answer key ``solutions/hri_lab``
(so the instructor's notebooks check the answer key), in ``release/`` the generated templates.
nbgrader does not follow the link (``os.walk``), so it never copies the answer key anywhere.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

from hri_teleop.bundle import (
    answer_files,
    assemble_bundle,
    bundle_leaks,
    pack_bundle,
    read_notebook,
    solution_texts,
    toolkit_leaks,
)
from hri_teleop.errors import HriTeleopError
from hri_teleop.paths import NOTEBOOKS, REPO, SOLUTIONS

__all__ = [
    "CourseError", "REPO", "COURSE_DIR", "SOLUTIONS", "ASSIGNMENTS", "ASSIGNMENT_CHECKS", "STUDENT_PACKAGE", "nbgrader_env",
    "fast", "seconds", "score", "show_file", "stop_nodes", "run_provided_node", "run_student_node", "rosrun_student", "launch",
    "wait_for_publisher",
    "student_workspace", "launch_student", "import_student_file", "grade_teleoperation_parts", "grade_teleoperation_node",
    "student_files", "exclude_overwriting", "link_answer_key", "source_notebooks", "solution_texts",
    "bundle_leaks", "generate_assignments", "build_release", "notebook_output_problems", "strip_outputs",
    "validate_release", "run_source", "prepare_course_copy", "run_course", "check_course", "main",
]

PathLike = Union[str, Path]
COURSE_DIR = NOTEBOOKS
#: The student's package folder beside the notebooks of every assignment.
STUDENT_PACKAGE = "hri_lab"
#: Scripts the handout has students make executable (Ex. 9, Ex. 12 c): released without the bit.
STUDENT_MAKES_EXECUTABLE = ("scripts/teleoperation.py", "scripts/gripper_manager.py")
#: nbgrader assignments: the preparation at home (Ex. 1-7), the lab session (Ex. 8-15).
ASSIGNMENTS = ("preparation", "lab")
#: The grader's checks of the student files each assignment's notebooks grade (``make grade`` runs
#: them on ``submitted/<student>/<assignment>/hri_lab`` beside nbgrader's autograde).
ASSIGNMENT_CHECKS: Dict[str, Tuple[str, ...]] = {
    "preparation": ("robot-params", "mapping-node", "sensor-launch"),
    "lab": ("teleoperation", "teleoperation-launch", "graph", "catkin-package"),
}
#: Environment variables that make :func:`fast` true (nbgrader sets NBGRADER_EXECUTION).
FAST_ENV = ("HRI_NOTEBOOK_FAST", "NBGRADER_EXECUTION")


class CourseError(HriTeleopError, RuntimeError):
    """A release or validation step failed (one line: what and the fix)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


# -- in a notebook ------------------------------------------------------------------------------

def fast() -> bool:
    """True under ``make test``, ``nbgrader validate`` and ``nbgrader autograde``: run real-time cells short."""
    return any(os.environ.get(name, "").strip().lower() not in ("", "0", "false", "no") for name in FAST_ENV)


def seconds(interactive_s: float, fast_s: float = 1.0) -> float:
    """How long a real-time cell runs: ``interactive_s`` for a student, ``fast_s`` under tests and grading."""
    return float(fast_s if fast() else interactive_s)


def score(result: Any) -> float:
    """Print a check's feedback and return its points: the last line of an autograded cell.

    nbgrader gives a test cell whose last value is a number that many points (partial
    credit), so a student loses the points of the parts that fail and keeps the rest,
    exactly as ``hri-grade`` and ``make grade`` score them.
    """
    from hri_teleop.grading.results import feedback_text

    print(feedback_text([result]))
    return float(result.score)


def _sandbox_note_on_stdout() -> None:
    """Say once, on stdout, when student code will run without bubblewrap.

    Said when a notebook imports this module (its setup cell), so that the check cells stay
    quiet (the checks' feedback repeats it as a note).
    """
    from hri_teleop.grading.sandbox import SandboxError, sandbox_mode

    try:
        sandbox_mode()
    except SandboxError as exc:  # HRI_GRADE_SANDBOX set wrongly: the check cells will say so
        print(f"hri-grade: {exc}")


def _node_part_names() -> set:
    from hri_teleop.grading.compare import TELEOP

    return {name for key, (name, _points) in TELEOP.items() if key.startswith("node_")}


def grade_teleoperation_parts(path: PathLike, **kwargs: Any) -> Any:
    """Ex. 8: the teleoperation check's parts of the class (gripper, sticks, toggle, rumble), no ROS node."""
    from hri_teleop.grading.checks import grade_teleoperation

    result = grade_teleoperation(path, node=False, **kwargs)
    node = _node_part_names()
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name not in node])


def grade_teleoperation_node(path: PathLike, **kwargs: Any) -> Any:
    """Ex. 9: the teleoperation check's parts of the ROS node (topics, types, values with the virtual pad)."""
    from hri_teleop.grading.checks import grade_teleoperation

    result = grade_teleoperation(path, **kwargs)
    node = _node_part_names()
    failed_ex8 = [p.name for p in result.parts if p.name not in node and not p.passed]
    notes = tuple(result.notes) + ((f"Ex. 8 parts still failing (see notebook 08): {'; '.join(failed_ex8)}",)
                                   if failed_ex8 else ())
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name in node], notes=notes)


def show_file(path: PathLike) -> Path:
    """Show where a student file is: a link that opens it in JupyterLab's editor, and its text."""
    target = Path(path)
    if not target.is_file():
        raise FileNotFoundError(f"{target}: not found next to this notebook; it comes with the assignment "
                                f"(restore it from the released version if you deleted it)")
    try:
        from IPython.display import Code, Markdown, display
    except ImportError:  # plain Python: print it
        print(f"{target.resolve()}\n{target.read_text(encoding='utf-8')}")
        return target
    language = {".py": "python", ".yaml": "yaml", ".launch": "xml"}.get(target.suffix, "text")
    display(Markdown(f"**[{target.as_posix()}]({target.as_posix()})** (click to edit; save with Ctrl+S) "
                     f"-- on disk: `{target.resolve()}`"))
    display(Code(target.read_text(encoding="utf-8"), language=language))
    return target


if "ipykernel" in sys.modules:  # imported by a notebook: see _sandbox_note_on_stdout
    _sandbox_note_on_stdout()


# -- running nodes from a notebook ----------------------------------------------------------------
#
# Nodes run on the kernel's master (hri_teleop.notebook_ros.ensure_ros() points
# ROS_MASTER_URI at it), each in its own process group with its output in a log file
# (``proc.output()``), so a cell never blocks on a node. They stop with stop_nodes(), at the
# latest when the kernel stops.

_STARTED: List[Any] = []
_SCRATCH: List[Path] = []


def _scratch(prefix: str) -> Path:
    """A temporary folder of this kernel (node logs, workspaces), removed when the kernel stops."""
    import atexit
    import tempfile

    if not _SCRATCH:
        atexit.register(lambda: [shutil.rmtree(p, ignore_errors=True) for p in _SCRATCH])
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    _SCRATCH.append(folder)
    return folder


def _ros_args(params: Dict[str, Any]) -> List[str]:
    return [f"_{name}:={value}" for name, value in params.items()]


def _start(argv: Sequence[str], name: str, extra_env: Optional[Dict[str, str]] = None,
           cwd: Optional[Path] = None, nodes: Optional[Sequence[str]] = None) -> Any:
    """Start ``argv`` (its ROS node names ``nodes``, default ``[name]``), unless one of them runs already."""
    from hri_teleop.modes import duplicate_refusal
    from hri_teleop.notebook_ros import running_nodes
    from hri_teleop.ros.master import ManagedProcess

    if not os.environ.get("ROS_MASTER_URI"):
        raise CourseError("no ROS master for this kernel: run ensure_ros() (hri_teleop.notebook_ros) first; "
                          "it says in one line what is missing")
    wanted = list(nodes) if nodes is not None else [name]
    refusal = duplicate_refusal(wanted, running_nodes(among=wanted))
    if refusal:
        raise CourseError(refusal)
    env = dict(os.environ)
    env.update({"PYTHONUNBUFFERED": "1", **(extra_env or {})})
    log = _scratch("hri-notebook-node-") / f"{name}.log"
    proc = ManagedProcess(list(argv), env, log, cwd=cwd)
    _STARTED.append(proc)
    return proc


def stop_nodes() -> None:
    """Stop every node and launch this notebook started, side by side (the master keeps running)."""
    from hri_teleop.ros.master import stop_side_by_side

    procs = list(_STARTED)
    _STARTED.clear()
    stop_side_by_side(procs)


def run_provided_node(script: str, **params: Any) -> Any:
    """Start one of the lab's own nodes (``FSR_sensor.py``, ``lab_sim.py``, ...) with private parameters."""
    from hri_teleop.grading.workspace import REFERENCE_PACKAGE

    path = REFERENCE_PACKAGE / "scripts" / script
    if not path.is_file():
        raise CourseError(f"{script}: not one of the lab's nodes in {path.parent}")
    return _start([sys.executable, str(path), *_ros_args(params)], Path(script).stem)


def run_student_node(path: PathLike, name: str = "", **params: Any) -> Any:
    """Start the student's node file (``hri_lab/scripts/...py``) as ``rosrun`` would; ``name`` renames the node."""
    script = Path(path)
    if not script.is_file():
        raise CourseError(f"{script}: no such file next to this notebook")
    node = name or script.stem
    return _start([sys.executable, str(script.resolve()), f"__name:={node}", *_ros_args(params)], node,
                  cwd=script.resolve().parent)


def rosrun_student(workspace: Any, script: str, name: str = "", **params: Any) -> Any:
    """``rosrun hri_lab SCRIPT`` in the student's built workspace (:func:`hri_teleop.catkin_ws.build_workspace`)."""
    node = name or Path(script).stem
    return _start(["rosrun", "hri_lab", script, f"__name:={node}", *_ros_args(params)], node, extra_env=workspace.env())


def _launch_nodes(where: Sequence[str], extra_env: Optional[Dict[str, str]] = None) -> List[str]:
    """The node names ``roslaunch`` would start (``roslaunch --nodes``); [] when it cannot tell."""
    env = dict(os.environ, **(extra_env or {}))
    try:
        proc = subprocess.run(["roslaunch", "--nodes", *where], env=env, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return []
    if proc.returncode != 0:
        return []  # the launch itself will say what is wrong with the file
    return [line.strip() for line in proc.stdout.splitlines() if line.strip().startswith("/")]


def launch(package: str, launch_file: str, **args: Any) -> Any:
    """``roslaunch PACKAGE FILE name:=value ...`` of an installed package (the lab's ``hri_lab``)."""
    where = [package, launch_file, *[f"{k}:={v}" for k, v in args.items()]]
    return _start(["roslaunch", "--wait", *where], Path(launch_file).stem, nodes=_launch_nodes(where))


def wait_for_publisher(topic: str, process: Any = None, timeout_s: float = 20.0) -> bool:
    """Wait until somebody publishes ``topic`` (False after ``timeout_s`` or when ``process`` ended)."""
    import time

    from hri_teleop.notebook_ros import master_call

    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if any(name == topic and nodes for name, nodes in master_call("getSystemState")[0]):
            return True
        if process is not None and not process.running:
            return False
        time.sleep(0.1)
    return False


def import_student_file(path: PathLike) -> Any:
    """The student's Python file as a fresh module (re-read on every call, so edits take effect)."""
    import importlib.util

    script = Path(path)
    if not script.is_file():
        raise CourseError(f"{script}: no such file next to this notebook")
    name = f"student_{script.stem}"
    spec = importlib.util.spec_from_file_location(name, str(script.resolve()))
    module = importlib.util.module_from_spec(spec)
    sys.modules.pop(name, None)
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    return module


def student_workspace(package: PathLike = STUDENT_PACKAGE) -> Path:
    """A ROS workspace with the student's package as ``hri_lab`` plus the lab's provided nodes.

    The grader's own workspace (the student's files never change; a fresh copy each call),
    so ``roslaunch`` of the student's launch file finds *their* nodes, and FSR_sensor.py,
    gripper_manager.py and a stand-in franka_control from the lab.
    """
    from hri_teleop.grading.workspace import prepare_workspace

    return prepare_workspace(package, _scratch("hri-notebook-ws-")).ws


def launch_student(launch_file: str, package: PathLike = STUDENT_PACKAGE, **args: Any) -> Any:
    """``roslaunch hri_lab FILE`` with the student's package (their nodes, the lab's provided ones)."""
    from hri_teleop.grading.workspace import ros_package_path

    ws = student_workspace(package)
    path = ws / "hri_lab" / "launch" / launch_file
    if not path.is_file():
        raise CourseError(f"{Path(package) / 'launch' / launch_file}: no such file; write it first")
    where = [str(path), *[f"{k}:={v}" for k, v in args.items()]]
    extra_env = {"ROS_PACKAGE_PATH": ros_package_path(ws)}
    return _start(["roslaunch", "--wait", *where], Path(launch_file).stem, extra_env=extra_env,
                  nodes=_launch_nodes(where, extra_env))


# -- the course's files -------------------------------------------------------------------------

def student_files() -> List[str]:
    """The files a student writes, relative to the assignment folder (``hri_lab/...``)."""
    from hri_teleop.grading.workspace import DELIVERABLES

    return [f"{STUDENT_PACKAGE}/{sub}" for sub in DELIVERABLES.values()]


def exclude_overwriting() -> Dict[str, List[str]]:
    """nbgrader's ``Autograde.exclude_overwriting``: autograde never puts the instructor's file over the student's."""
    return {assignment: student_files() + [f"{STUDENT_PACKAGE}/CMakeLists.txt"] for assignment in ASSIGNMENTS}


def link_answer_key(course_dir: PathLike = COURSE_DIR, solutions: PathLike = SOLUTIONS) -> List[Path]:
    """Make ``source/<assignment>/hri_lab`` a link to the answer key (relative inside the repo)."""
    links = []
    for assignment in ASSIGNMENTS:
        folder = Path(course_dir) / "source" / assignment
        if not folder.is_dir():
            raise CourseError(f"{folder}: no such assignment folder; the course needs source/{assignment}/")
        link = folder / STUDENT_PACKAGE
        target = Path(os.path.relpath(Path(solutions).resolve(), folder.resolve()))
        if link.is_symlink() and Path(os.readlink(link)) == target:
            links.append(link)
            continue
        if link.exists() and not link.is_symlink():
            raise CourseError(f"{link}: a real folder; source/ must link to the answer key (solutions/hri_lab), "
                              "never hold a copy: move your changes into solutions/ and remove it")
        if link.is_symlink():
            link.unlink()
        link.symlink_to(target, target_is_directory=True)
        links.append(link)
    return links


def source_notebooks(course_dir: PathLike = COURSE_DIR) -> List[Path]:
    """Every source notebook, assignment by assignment, in name order."""
    found: List[Path] = []
    for assignment in ASSIGNMENTS:
        found += sorted((Path(course_dir) / "source" / assignment).glob("*.ipynb"))
    return found


# -- release -----------------------------------------------------------------------------------

def nbgrader_env(base: Optional[Mapping[str, str]] = None) -> Dict[str, str]:
    """The environment nbgrader runs in (``base``: default this process's): no Python warnings, since
    nbgrader scores a cell that wrote to stderr with 0 points (a DeprecationWarning must not cost a
    student a grade)."""
    return dict(os.environ if base is None else base, PYTHONWARNINGS="ignore")


def _nbgrader(args: Sequence[str], course_dir: Path) -> str:
    argv = [sys.executable, "-m", "nbgrader", *args, f"--CourseDirectory.root={course_dir}"]
    proc = subprocess.run(argv, cwd=str(course_dir), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, env=nbgrader_env())
    if proc.returncode != 0:
        tail = "\n".join(proc.stdout.strip().splitlines()[-15:])
        raise CourseError(f"nbgrader {' '.join(args)} failed (exit {proc.returncode}):\n{tail}")
    return proc.stdout


def generate_assignments(course_dir: PathLike = COURSE_DIR) -> List[Path]:
    """``nbgrader generate_assignment`` for every assignment, then its hri_lab templates; release folders."""
    from hri_teleop.grading.templates import generate_templates

    course = Path(course_dir).resolve()
    link_answer_key(course)
    released = []
    for assignment in ASSIGNMENTS:
        _nbgrader(["generate_assignment", assignment, "--force", "--create"], course)
        folder = course / "release" / assignment
        generate_templates(SOLUTIONS, folder / STUDENT_PACKAGE, not_executable=STUDENT_MAKES_EXECUTABLE)
        released.append(folder)
    return released


def build_release(course_dir: PathLike = COURSE_DIR, archive: Optional[PathLike] = None) -> Tuple[Path, Path]:
    """``make release``: the student versions and templates, proven free of solution text, packed.

    Returns (the release folder, the .tar.gz of it). CourseError when anything leaks.
    """
    course = Path(course_dir).resolve()
    problems = notebook_output_problems(source_notebooks(course))
    if problems:
        raise CourseError("source notebooks have outputs (run `python -m hri_teleop.course strip`): "
                          + "; ".join(problems[:5]))
    generate_assignments(course)
    release = course / "release"
    leaks = bundle_leaks(release, solution_texts(SOLUTIONS, course))
    if leaks:
        raise CourseError("the student bundle holds solution text; nothing was packed:\n" + "\n".join(leaks[:20]))
    target = Path(archive) if archive else REPO / "out" / "task4-student-bundle.tar.gz"
    folder = assemble_bundle(release, target.parent / "task4-student-bundle", ASSIGNMENTS)
    leaks = toolkit_leaks(folder, solution_texts(SOLUTIONS, course), answer_files())
    if leaks:
        raise CourseError("the student bundle's toolkit holds answers; nothing was packed:\n" + "\n".join(leaks[:20]))
    pack_bundle(folder, target)
    shutil.rmtree(folder)
    return release, target


# -- notebooks without outputs -------------------------------------------------------------------

def notebook_output_problems(paths: Iterable[PathLike]) -> List[str]:
    """One line per code cell that has outputs or an execution count (committed notebooks must have none)."""
    problems = []
    for path in paths:
        for number, cell in enumerate(read_notebook(Path(path))["cells"]):
            if cell.get("cell_type") != "code":
                continue
            if cell.get("outputs"):
                problems.append(f"{path}: cell {number} has {len(cell['outputs'])} output(s)")
            if cell.get("execution_count") is not None:
                problems.append(f"{path}: cell {number} has execution_count {cell['execution_count']}")
    return problems


def strip_outputs(paths: Iterable[PathLike]) -> List[Path]:
    """Remove outputs and execution counts (and nbgrader checksums of source cells); the files changed."""
    import nbformat

    changed = []
    for path in map(Path, paths):
        nb = nbformat.read(str(path), as_version=4)
        before = nbformat.writes(nb)
        for cell in nb.cells:
            if cell.cell_type == "code":
                cell.outputs = []
                cell.execution_count = None
            cell.metadata.get("nbgrader", {}).pop("checksum", None)
            cell.metadata.pop("execution", None)
        after = nbformat.writes(nb)
        if after != before:
            path.write_text(after, encoding="utf-8")
            changed.append(path)
    return changed


# -- validate: the answer key passes, the student version fails ------------------------------------

def validate_release(notebook: PathLike, timeout_s: int = 300) -> Dict[str, Any]:
    """nbgrader's ``validate --invert`` on one student version: the autograded cells that PASS (should be none)."""
    from nbgrader.validator import Validator

    from hri_teleop.labkernel import ipc_kernel_config

    with ipc_kernel_config() as config:
        config.Validator.invert = True
        config.Execute.timeout = timeout_s
        config.Execute.startup_timeout = 120
        return Validator(config=config).validate(str(notebook))


def run_source(notebook: PathLike, timeout_s: int = 300) -> Dict[str, Any]:
    """Execute a source notebook top to bottom (nbclient, its own kernel: ``hri-teleop``) and grade it as nbgrader would.

    Returns ``errors`` (every code cell that raised or wrote to stderr), ``grades``
    ({grade_id: [score, max]} of the autograded cells) and ``seconds``.
    """
    import time

    import nbformat
    from nbclient import NotebookClient
    from nbgrader.utils import determine_grade, is_grade, is_solution

    from hri_teleop.labkernel import ipc_kernel_config

    path = Path(notebook)
    nb = nbformat.read(str(path), as_version=4)
    started = time.monotonic()
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=timeout_s, startup_timeout=120, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()
    errors, grades = [], {}
    for number, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        for out in cell.outputs:
            if out.output_type == "error":
                errors.append(f"cell {number}: {out.ename}: {out.evalue.strip()[:800]}")
            elif out.output_type == "stream" and out.name == "stderr":
                errors.append(f"cell {number} wrote to stderr: {out.text.strip()[:800]}")
        if is_grade(cell) and not is_solution(cell):
            got, most = determine_grade(cell)
            grades[cell.metadata.nbgrader["grade_id"]] = [got, most]
    return {"errors": errors, "grades": grades, "seconds": time.monotonic() - started}


def _validate_job(job: Tuple[str, str]) -> Tuple[str, str, Dict[str, Any]]:
    kind, path = job
    import time

    started = time.monotonic()
    if kind == "source":
        result = run_source(path)
    else:
        result = validate_release(path)
        result["seconds"] = time.monotonic() - started
    return kind, path, result


def prepare_course_copy(work_dir: PathLike, course_dir: PathLike = COURSE_DIR, release: bool = True) -> Path:
    """A copy of the course under ``work_dir/course`` with the student versions generated (and the kernel installed).

    ``release=False``: only the source half, each assignment linked to the answer key, for
    running the source notebooks (nbgrader's generate_assignment takes ~10 s).
    """
    from hri_teleop.labkernel import install_kernelspec

    course = Path(work_dir) / "course"
    if course.exists():
        shutil.rmtree(course)
    (course / "source").mkdir(parents=True)
    shutil.copy(Path(course_dir) / "nbgrader_config.py", course / "nbgrader_config.py")
    for assignment in ASSIGNMENTS:
        shutil.copytree(Path(course_dir) / "source" / assignment, course / "source" / assignment,
                        ignore=shutil.ignore_patterns(STUDENT_PACKAGE, ".ipynb_checkpoints"))
    if release:
        generate_assignments(course)
    else:
        link_answer_key(course)
    install_kernelspec()  # the notebooks' kernel: .venv's Python in the lab's shell (tools/kernel.sh)
    return course


def run_course(course: PathLike, jobs: int = 2) -> Dict[str, Dict[str, Any]]:
    """Run every source notebook of a prepared course (must pass every autograded cell) and
    ``validate --invert`` every student version (no autograded cell may pass), ``jobs`` at a time.

    Returns {notebook name: {"source": run_source(...), "release": validate_release(...)}}.
    Real-time cells run short (:func:`fast`). The student versions run in place.
    """
    from concurrent.futures import ProcessPoolExecutor

    course = Path(course)
    os.environ["HRI_NOTEBOOK_FAST"] = "1"
    jobs_list = []
    for notebook in source_notebooks(course):
        jobs_list.append(("source", str(notebook)))
        jobs_list.append(("release", str(course / "release" / notebook.parent.name / notebook.name)))
    results: Dict[str, Dict[str, Any]] = {}
    with ProcessPoolExecutor(max_workers=max(1, jobs)) as pool:
        for kind, path, result in pool.map(_validate_job, jobs_list):
            results.setdefault(Path(path).stem, {})[kind] = result
    return results


def check_course(work_dir: PathLike, course_dir: PathLike = COURSE_DIR, jobs: int = 2) -> Dict[str, Dict[str, Any]]:
    """The whole course checked in a copy under ``work_dir``: :func:`prepare_course_copy`, then :func:`run_course`."""
    return run_course(prepare_course_copy(work_dir, course_dir), jobs)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hri_teleop.course", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    r = sub.add_parser("release", help="student versions + templates into notebooks/release/, checked, packed")
    r.add_argument("--archive", default=None, help="the .tar.gz (default: out/task4-student-bundle.tar.gz)")
    sub.add_parser("link", help="link source/<assignment>/hri_lab to solutions/hri_lab")
    s = sub.add_parser("strip", help="remove outputs and execution counts from the source notebooks")
    s.add_argument("paths", nargs="*", help="notebooks (default: every source notebook)")
    k = sub.add_parser("check", help="run every notebook: the answer key must pass, the student version fail")
    k.add_argument("--jobs", type=int, default=2, help="notebooks at a time (default 2)")
    c = sub.add_parser("check-bundle", help="find solution text in a student bundle folder")
    c.add_argument("path", nargs="?", default=str(COURSE_DIR / "release"))
    args = parser.parse_args(argv)
    try:
        if args.command == "release":
            release, archive = build_release(archive=args.archive)
            for assignment in ASSIGNMENTS:
                files = sorted(p.relative_to(release) for p in (release / assignment).rglob("*") if p.is_file())
                print(f"{release / assignment}: {len(files)} files")
                for f in files:
                    print(f"  {f}")
            print(f"no solution text in the bundle; packed into {archive}")
            return 0
        if args.command == "link":
            for link in link_answer_key():
                print(f"{link} -> {os.readlink(link)}")
            return 0
        if args.command == "strip":
            for path in strip_outputs(args.paths or source_notebooks()):
                print(f"stripped {path}")
            return 0
        if args.command == "check":
            import tempfile

            failed = 0
            with tempfile.TemporaryDirectory(prefix="hri-course-check-") as work:
                for name, result in check_course(work, jobs=args.jobs).items():
                    source, release = result["source"], result["release"]
                    short = {g: v for g, v in source["grades"].items() if v[0] != v[1]}
                    bad = bool(source["errors"] or short or release.get("passed") or release.get("changed"))
                    failed += bad
                    print(f"{'FAIL' if bad else 'ok  '} {name}: answer key {sum(v[0] for v in source['grades'].values()):g}/"
                          f"{sum(v[1] for v in source['grades'].values()):g} in {source['seconds']:.0f} s, "
                          f"student version passes {len(release.get('passed', []))} autograded cell(s) "
                          f"in {release['seconds']:.0f} s")
                    for line in source["errors"] + [f"passes: {c['source']}" for c in release.get("passed", [])]:
                        print(f"       {line}")
            return 1 if failed else 0
        if args.command == "check-bundle":
            leaks = bundle_leaks(args.path)
            print("\n".join(leaks) if leaks else f"{args.path}: no solution text")
            return 1 if leaks else 0
        parser.print_help()
        return 2
    except CourseError as exc:
        print(f"course: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
