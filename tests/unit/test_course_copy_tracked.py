"""The course is checked in a copy of what git tracks: a notebook run in place (an instructor's normal authoring
step) leaves a catkin_ws/build, plots and checkpoints in notebooks/source/, which the copy leaves out, as the
release does. Otherwise catkin_make in the copy refuses the other folder's CMakeCache and Ex. 9 fails."""

from __future__ import annotations

import subprocess
from pathlib import Path

from hri_teleop.course.release import copy_course_sources, tracked_below


def _course(root: Path) -> Path:
    """A course folder as the checkout has it: the config, one notebook per assignment, the answer key's link."""
    course = root / "notebooks"
    for name in ("source/preparation/ex05_mapping_node.ipynb", "source/lab/ex09_teleoperation_node.ipynb",
                 "source/lab/data/trace.csv"):
        (course / name).parent.mkdir(parents=True, exist_ok=True)
        (course / name).write_text(f"{name}\n")
    (course / "nbgrader_config.py").write_text("c = get_config()\n")
    (root / "solutions" / "hri_lab").mkdir(parents=True)
    (root / "solutions" / "hri_lab" / "package.xml").write_text("<package/>\n")
    for assignment in ("preparation", "lab"):
        (course / "source" / assignment / "hri_lab").symlink_to("../../../solutions/hri_lab")
    return course


def _run_in_place(course: Path) -> None:
    """What running the lab's notebooks in place leaves behind."""
    build = course / "source" / "lab" / "catkin_ws" / "build"
    build.mkdir(parents=True)
    (build / "CMakeCache.txt").write_text("CMAKE_CACHEFILE_DIR:INTERNAL=/somewhere/else/catkin_ws/build\n")
    (course / "source" / "lab" / "catkin_ws" / "src").mkdir()
    (course / "source" / "lab" / "timeline.png").write_text("png\n")
    (course / "source" / "lab" / ".ipynb_checkpoints").mkdir()
    (course / "source" / "lab" / ".ipynb_checkpoints" / "ex09-checkpoint.ipynb").write_text("{}\n")
    (course / "source" / "preparation" / "__pycache__").mkdir()


def _files(folder: Path) -> list:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() or p.is_symlink())


def _git(root: Path, *args: str) -> None:
    subprocess.run(["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=root, check=True,
                   capture_output=True)


def test_a_course_run_in_place_is_copied_without_the_workspace_and_plots_the_run_left(tmp_path):
    root = tmp_path / "checkout"
    course = _course(root)
    _git(root, "init", "-q")
    _git(root, "add", ".")
    _git(root, "commit", "-q", "-m", "course")
    _run_in_place(course)
    copy = tmp_path / "copy"
    copy_course_sources(course, copy)
    assert _files(copy) == ["nbgrader_config.py", "source/lab/data/trace.csv", "source/lab/ex09_teleoperation_node.ipynb",
                            "source/preparation/ex05_mapping_node.ipynb"]


def test_a_notebook_added_but_not_yet_committed_is_copied_with_its_edits(tmp_path):
    root = tmp_path / "checkout"
    course = _course(root)
    _git(root, "init", "-q")
    _git(root, "add", ".")
    _git(root, "commit", "-q", "-m", "course")
    (course / "source" / "lab" / "ex16_new.ipynb").write_text("new\n")
    _git(root, "add", "notebooks/source/lab/ex16_new.ipynb")
    (course / "source" / "lab" / "ex09_teleoperation_node.ipynb").write_text("edited\n")
    copy = tmp_path / "copy"
    copy_course_sources(course, copy)
    assert (copy / "source" / "lab" / "ex16_new.ipynb").read_text() == "new\n"
    assert (copy / "source" / "lab" / "ex09_teleoperation_node.ipynb").read_text() == "edited\n"


def test_a_course_outside_git_is_copied_without_workspaces_checkpoints_and_the_student_package(tmp_path):
    course = _course(tmp_path / "unpacked")
    _run_in_place(course)
    assert tracked_below(course / "source" / "lab") is None
    copy = tmp_path / "copy"
    copy_course_sources(course, copy)
    assert _files(copy) == ["nbgrader_config.py", "source/lab/data/trace.csv", "source/lab/ex09_teleoperation_node.ipynb",
                            "source/lab/timeline.png", "source/preparation/ex05_mapping_node.ipynb"]


def test_the_checkouts_course_copies_its_notebooks_and_no_student_package():
    from hri_teleop.course.release import COURSE_DIR

    tracked = tracked_below(COURSE_DIR / "source" / "lab")
    assert tracked is not None and "ex09_teleoperation_node.ipynb" in tracked
    assert not any(name.startswith("catkin_ws/") for name in tracked)
