"""The student box's view, rule by rule, as pure functions of paths: which package folders and search paths are
shown, what the box's arguments are in which order, and how each mount is named. No box is started here
(test_student_view.py starts real ones)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from hri_teleop.grading.run import view as view_module
from hri_teleop.grading.run.view import View, mount_points, python_packages, shown_search_paths, toolkit_view, view_argv


def _checkout(root: Path, gradescope: bool = True) -> Path:
    for folder in ("hri_teleop/core", "hri_lab/scripts", "grading/traces", "tools"):
        (root / folder).mkdir(parents=True)
    if gradescope:
        (root / "hri_teleop/grading/gradescope").mkdir(parents=True)
    return root


def test_each_mount_is_named_by_its_kind():
    view = View(shown=("/usr",), masked_files=("/c/hri_lab/x.py",), masked_folders=("/c/gradescope",),
                links=(("/bin", "usr/bin"),), writable=("/w",))
    assert mount_points(view) == {"/usr": "ro", "/c/hri_lab/x.py": "mask", "/c/gradescope": "mask", "/bin": "link",
                                  "/w": "rw"}


def test_the_box_argv_links_then_dev_proc_and_tmp_then_binds_shallowest_first_then_masks_then_writables():
    view = View(shown=("/usr/lib", "/usr", "/opt/ros"), masked_files=("/usr/lib/f.py",),
                masked_folders=("/opt/ros/g",), links=(("/bin", "usr/bin"),), writable=("/w",))
    assert view_argv(view) == [
        "--symlink", "usr/bin", "/bin", "--dev", "/dev", "--proc", "/proc", "--tmpfs", "/tmp",
        "--ro-bind", "/usr", "/usr", "--ro-bind", "/opt/ros", "/opt/ros", "--ro-bind", "/usr/lib", "/usr/lib",
        "--ro-bind", "/dev/null", "/usr/lib/f.py", "--tmpfs", "/opt/ros/g", "--remount-ro", "/opt/ros/g",
        "--bind", "/w", "/w"]
    sized = view_argv(View(shown=()), proc=("--ro-bind", "/proc", "/proc"), tmp_bytes=4096)
    assert sized == ["--dev", "/dev", "--ro-bind", "/proc", "/proc", "--size", "4096", "--tmpfs", "/tmp"]


@pytest.mark.parametrize("entry, repo, shown", [
    ("/usr/lib/python3/dist-packages", "/opt/course/hri", True),
    ("/usr/lib/python3/dist-packages/ros", "/opt/course/hri", True),         # a folder below a package folder
    ("/opt/py/site-packages", "/opt/py/site-packages", False),               # the checkout itself
    ("/opt/py/site-packages", "/opt/py/site-packages/course", False),        # above the checkout
    ("/", "/opt/course/hri", False),
    ("/usr/lib/python3/dist", "/opt/course/hri", False),
    ("/var/tmp/x/site-packages", "/opt/course/hri", True),                   # below /tmp: wherever they lie
    ("/srv/site-packages-above", "/opt/course/hri", False),
])
def test_a_pythons_package_folder_is_shown_unless_at_or_above_the_checkout(entry, repo, shown):
    assert python_packages(entry, repo) is shown


def test_every_entry_of_a_search_path_is_judged_on_its_own():
    env = {"PATH": "/opt/ros/noetic/bin:/opt/tools/bin:/home/ann/bin", "ROS_PACKAGE_PATH": "/opt/ros/noetic/share"}
    assert shown_search_paths(env, "/srv2/checkout", []) == ["/opt/ros/noetic/bin", "/opt/tools/bin",
                                                              "/opt/ros/noetic/share"]


def test_no_shown_folder_lies_inside_another():
    """/usr/bin on PATH is inside /usr, already shown: one bind each."""
    shown = toolkit_view(dict(os.environ)).shown
    assert [(a, b) for a in shown for b in shown if a != b and view_module.under(a, b)] == []


def test_a_python_whose_prefix_is_the_root_does_not_show_the_whole_machine(monkeypatch, tmp_path):
    monkeypatch.setattr(view_module, "_python_prefixes", lambda: ["/", sys.prefix])
    assert "/" not in toolkit_view({}, repo=str(_checkout(tmp_path)), cwd="/").shown


def test_the_folder_python_runs_in_is_not_shown_for_being_on_its_path(monkeypatch, tmp_path):
    """python -m puts its working folder on sys.path; a grader started in /boot does not show /boot."""
    monkeypatch.setattr(sys, "path", [*sys.path, "/boot"])
    repo = str(_checkout(tmp_path))
    assert "/boot" not in toolkit_view({}, repo=repo, cwd="/boot").shown
    assert "/boot" in toolkit_view({}, repo=repo, cwd="/").shown


@pytest.mark.parametrize("gradescope", [True, False])
def test_the_gradescope_course_is_masked_where_the_checkout_has_it(tmp_path, monkeypatch, gradescope):
    repo = _checkout(tmp_path / "c", gradescope=gradescope)
    monkeypatch.chdir(tmp_path)
    masked = toolkit_view({}, repo=str(repo), cwd="/").masked_folders
    assert masked == ((str(repo / "hri_teleop/grading/gradescope"),) if gradescope else ())


def test_a_search_path_inside_the_checkout_is_shown_only_inside_the_toolkit(tmp_path, monkeypatch):
    """The checkout under tmp_path, with /tmp taken off the never-shown list, so that this rule decides alone."""
    monkeypatch.setattr(view_module, "NEVER_SHOWN", tuple(n for n in view_module.NEVER_SHOWN if n not in ("/tmp", "/var/tmp")))
    repo = _checkout(tmp_path / "c")
    (repo / "solutions").mkdir()
    env = {"PYTHONPATH": f"{repo}/hri_lab/scripts:{repo}/solutions:{repo}:{repo}/tools"}
    assert shown_search_paths(env, str(repo), [str(repo / "hri_lab")]) == [str(repo / "hri_lab/scripts")]
    shown = toolkit_view(env, repo=str(repo), cwd="/").shown
    assert str(repo / "hri_lab") in shown
    assert not [s for s in shown if view_module.under(s, str(repo / "solutions")) or s == str(repo)]


def test_a_kernels_box_shows_nothing_of_the_answer_key_the_course_or_the_checkouts_history():
    """The notebooks' kernels run in a box of the same allowlist: solutions/ is not in what it shows."""
    from hri_teleop.core.paths import REPO
    from hri_teleop.grading.run.kernel_box import KernelPolicy, kernel_view

    view = kernel_view(KernelPolicy(hidden=(str(REPO / "notebooks"),)), dict(os.environ), None)
    for secret in ("solutions", "solutions/hri_lab/scripts/teleoperation.py", ".git", "notebooks/source", "out",
                   "benchmarks"):
        path = str(REPO / secret)
        assert not [s for s in view.shown if view_module.under(path, s)], f"{secret} is readable from a kernel's box"
    assert str(REPO / "hri_teleop") in view.shown or any(view_module.under(str(REPO / "hri_teleop"), s)
                                                         for s in view.shown)
