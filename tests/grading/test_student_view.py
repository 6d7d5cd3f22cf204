"""Student code sees only what it runs on: the view of a box is a list of what is shown (hri_teleop.grading.run.view).

Unit cases on a made-up checkout (which folder is shown, which file masked, which search path refused),
then a real boxed student process that tries to read the answer key through the checkout's .git, the
lab's completed nodes, the course, /tmp and the grader's home, as root and as an unprivileged grader.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from grading_helpers import open_folder

from hri_teleop.core.paths import REPO
from hri_teleop.grading.run.view import (
    FOLDERS_MASKED,
    TOOLKIT_MASKED,
    mount_points,
    shown_search_paths,
    toolkit_view,
    under,
    view_argv,
)


@pytest.fixture
def checkout(tmp_path):
    """A made-up checkout with everything a real one holds that students must not see."""
    for folder in (".git", "solutions/hri_lab/scripts", "notebooks/source/lab", "notebooks/submitted/ann", "out/grades",
                   "hri_teleop/core", "hri_teleop/grading/gradescope", "hri_lab/scripts", "hri_lab/launch",
                   "hri_lab/config", "grading/traces", "benchmarks", "tools", ".venv/lib"):
        (tmp_path / folder).mkdir(parents=True)
    for relative in TOOLKIT_MASKED + ("hri_lab/scripts/FSR_sensor.py", ".git/HEAD"):
        (tmp_path / relative).write_text("x")
    return tmp_path


def test_the_toolkit_view_shows_the_toolkit_and_masks_what_students_write(checkout):
    view = toolkit_view({}, repo=str(checkout), cwd="/")
    shown = set(view.shown)
    for part in ("hri_teleop", "hri_lab", "grading/traces"):
        assert str(checkout / part) in shown, part
    for secret in ("", ".git", "solutions", "notebooks", "out", "benchmarks", "tools", "grading"):
        path = str(checkout / secret) if secret else str(checkout)
        assert path not in shown and not any(under(path, s) for s in shown), f"{secret or 'the checkout'} is shown"
    assert set(view.masked_files) == {str(checkout / p) for p in TOOLKIT_MASKED}
    assert set(view.masked_folders) == {str(checkout / p) for p in FOLDERS_MASKED}
    assert "/usr" in shown and "/etc" in shown
    prefixes = (sys.prefix, sys.base_prefix, os.path.realpath(sys.prefix))  # a clone's .venv may lie under /tmp
    outside = [s for s in shown if not under(s, str(checkout)) and not any(under(s, p) for p in prefixes)]
    assert not any(under(s, h) for s in outside for h in ("/home", "/root", "/tmp", "/srv", "/mnt")), outside


def test_the_lab_package_is_masked_file_by_file_and_the_provided_nodes_stay():
    assert "hri_lab/scripts/FSR_sensor.py" not in TOOLKIT_MASKED
    assert "hri_lab/scripts/gripper_manager.py" not in TOOLKIT_MASKED
    for deliverable in ("scripts/mapping_node.py", "scripts/teleoperation.py", "launch/sensor.launch",
                        "launch/teleoperation.launch", "config/robot_params.yaml", "graph.yaml"):
        assert f"hri_lab/{deliverable}" in TOOLKIT_MASKED, deliverable


@pytest.mark.parametrize("entry", ["/home/prof", "/home", "/root/.local/bin", "/tmp/course", "/tmp", "/", "/srv/x",
                                   "/run/user/0", "/mnt/share", "/media/usb", "/var/tmp/x", "/var"])
def test_a_search_path_in_a_home_or_tmp_or_above_them_is_not_shown(entry):
    assert shown_search_paths({"PYTHONPATH": entry, "PATH": entry}, "/opt/course/hri", []) == []


@pytest.mark.parametrize("entry,shown", [
    ("/opt/course/hri", False),               # the checkout's root
    ("/opt/course", False),                   # above the checkout
    ("/opt/course/hri/solutions", False),     # inside, not the toolkit
    ("/opt/course/hri/hri_teleop", True),     # the toolkit
    ("/opt/course/hri/hri_teleop/core", True),
    ("/opt/ros/noetic/lib", True),            # a ROS install
    ("/srvdata/ros", True),                   # not under /srv: whole components only
    ("relative/dir", False),
])
def test_search_paths_show_the_toolkit_and_other_installs_but_not_the_checkout(entry, shown):
    found = shown_search_paths({"ROS_PACKAGE_PATH": entry}, "/opt/course/hri", ["/opt/course/hri/hri_teleop"])
    assert (found == [entry]) is shown, found


@pytest.mark.parametrize("entry,shown", [
    ("/tmp/clone/.venv/lib/python3.11/site-packages", True),   # a venv reused from a clone under /tmp
    ("/home/prof/.local/lib/python3.11/site-packages", True),  # the user's packages, not their home
    ("/usr/lib/python3/dist-packages", True),
    ("/tmp", False), ("/home/prof", False), ("/home", False), ("/", False),
    ("/tmp/clone/lib", False),                                 # not a package folder
    ("/opt/course/hri/.venv/lib/python3.11/site-packages", True),
    ("/opt/course", False),                                    # above the checkout
])
def test_the_python_s_own_package_folders_are_shown_wherever_they_lie(entry, shown):
    from hri_teleop.grading.run.view import python_packages

    assert python_packages(entry, "/opt/course/hri") is shown


def test_under_compares_whole_components():
    assert under("/srv/x", "/srv") and under("/srv", "/srv") and not under("/srvdata", "/srv")
    assert under("/anything", "/") and not under("/srv", "/srv/x")


def test_the_box_argv_builds_on_an_empty_root_with_masks_after_the_binds(checkout):
    view = toolkit_view({}, writable=[str(checkout / "out")], repo=str(checkout), cwd="/")
    argv = view_argv(view, tmp_bytes=1024)
    assert ["--ro-bind", "/", "/"] not in [argv[i:i + 3] for i in range(len(argv) - 2)]
    first_mask = argv.index(str(checkout / "hri_lab" / "scripts" / "mapping_node.py"))
    assert argv.index(str(checkout / "hri_lab")) < first_mask
    assert argv[argv.index("/tmp") - 3:argv.index("/tmp")] == ["--size", "1024", "--tmpfs"]
    assert argv.index("/tmp") < argv.index(str(checkout / "hri_lab")), "a folder shown under /tmp goes on top of it"
    assert argv[-3:] == ["--bind", str(checkout / "out"), str(checkout / "out")]
    assert mount_points(view)[str(checkout / "out")] == "rw"


# -- a real box -------------------------------------------------------------------------------------------------

_PROBE = """
import os, sys
for path in sys.argv[1:]:
    try:
        with open(path, 'rb') as fh:
            print('READ', path, fh.read(64))
    except OSError as exc:
        print('refused', path, type(exc).__name__)
import hri_teleop.core.fsr, rospy, yaml
print('imports ok')
"""


def _secrets(folder: Path) -> list:
    secret = folder / "grader-secret.txt"
    secret.write_text("SECRET-OF-THE-GRADER")
    secret.chmod(0o644)
    return [str(REPO / ".git" / "HEAD"), str(REPO / "solutions" / "README.md"),
            str(REPO / "hri_lab" / "scripts" / "mapping_node.py"), str(REPO / "notebooks" / "README.md"),
            str(REPO / "hri_teleop" / "grading" / "gradescope" / "build.py"), str(secret)]


def _boxed(folder: Path, paths: list, env_extra: dict) -> str:
    from hri_teleop.grading.run.sandbox import StudentProcess, student_uid

    student = folder / "student"
    student.mkdir()
    uid = student_uid()
    if uid is not None:
        os.chown(student, uid, uid)
    (student / "x.py").write_text(_PROBE)
    env = dict(os.environ, **env_extra)
    proc = StudentProcess([sys.executable, str(student / "x.py"), *paths], student, env, folder / "x.log", uid=uid,
                          nested=False, network=False)
    code = proc.wait(60)
    proc.stop()
    out = proc.output_tail(20000)
    assert code == 0, out
    return out


@pytest.fixture
def box_folder():
    from hri_teleop.grading.run.sandbox import bwrap_problem

    if bwrap_problem():
        pytest.skip(f"no bubblewrap here: {bwrap_problem()}")
    yield from open_folder("hri-view-test-")


def test_a_student_process_reads_none_of_the_answer_key_course_or_grader_files_but_runs(box_folder):
    paths = _secrets(box_folder) + [str(REPO / "hri_lab" / "scripts" / "FSR_sensor.py")]
    out = _boxed(box_folder, paths, {})
    assert "imports ok" in out, out
    for path in paths[:-1]:
        assert f"refused {path}" in out, out
    assert f"READ {paths[-1]}" in out, out  # a node the lab provides to everyone
    assert "SECRET-OF-THE-GRADER" not in out


def test_graded_by_an_unprivileged_instructor_the_box_keeps_their_home_and_ssh_key_out_of_sight(box_folder):
    """The grader as a normal user: student code runs as that user, and only the box keeps their home away."""
    if os.geteuid() != 0:
        pytest.skip("needs root to become a normal user for the test")
    home = box_folder / "home"
    (home / ".ssh").mkdir(parents=True)
    key = home / ".ssh" / "id_ed25519"
    key.write_text("PRIVATE-KEY-OF-THE-INSTRUCTOR")
    key.chmod(0o600)
    work = box_folder / "work"
    work.mkdir()
    for path in (home, home / ".ssh", key, work):
        os.chown(path, 65534, 65534)
    home.chmod(0o700)
    script = ("import sys; sys.path.insert(0, sys.argv[1]); import test_student_view as t; "
              "from pathlib import Path; print(t._boxed(Path(sys.argv[2]), [sys.argv[3]], {'HOME': sys.argv[4]}))")

    def become_nobody() -> None:
        os.setgroups([])
        os.setgid(65534)
        os.setuid(65534)

    proc = subprocess.run([sys.executable, "-c", script, str(Path(__file__).parent), str(work), str(key), str(home)],
                          capture_output=True, text=True, timeout=120, preexec_fn=become_nobody,
                          env=dict(os.environ, HOME=str(home), PYTHONPATH=os.pathsep.join(
                              [str(Path(__file__).parent), str(Path(__file__).parents[1])])),
                          cwd=str(work), stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "imports ok" in proc.stdout, proc.stdout
    assert f"refused {key}" in proc.stdout, proc.stdout
    assert "PRIVATE-KEY" not in proc.stdout


# -- before grading anyone: student code must reach the toolkit ----------------------------------------------------

@pytest.mark.parametrize("mode,reachable", [(0o700, False), (0o750, False), (0o704, False), (0o701, True),
                                            (0o755, True), (0o711, True)])
def test_a_folder_other_users_cannot_enter_above_the_toolkit_is_named_with_the_fix(box_folder, mode, reachable):
    from hri_teleop.grading.run.sandbox import unreachable

    root = box_folder / "private"
    (root / "hri" / ".venv" / "bin").mkdir(parents=True)
    python = root / "hri" / ".venv" / "bin" / "python"
    python.write_text("")
    root.chmod(mode)
    try:
        problem = unreachable([str(python)], uid=123456)
    finally:
        root.chmod(0o755)
    if reachable:
        assert problem == ""
    else:
        assert problem.startswith(f"student code cannot reach {python}: {root} (mode {mode:04o})"), problem
        assert f"chmod o+x {root}" in problem and "\n" not in problem


def test_the_grader_s_own_user_needs_no_check():
    from hri_teleop.grading.run.sandbox import unreachable

    assert unreachable(["/root/anything/python"], uid=None) == ""


def test_grading_refuses_in_one_line_before_anyone_when_the_toolkit_is_out_of_reach(box_folder, monkeypatch):
    """Graded as root from a checkout in a 0700 folder, every student got 0 ("could not be imported")."""
    from hri_teleop.grading.run import sandbox

    if os.geteuid() != 0:
        pytest.skip("only root grades under a uid of its own")
    hidden = box_folder / "locked" / "hri_teleop"
    hidden.mkdir(parents=True)
    (box_folder / "locked").chmod(0o700)
    monkeypatch.setattr(sandbox, "toolkit_paths", lambda: [str(hidden)])
    monkeypatch.setattr(sandbox, "_bwrap_state", {})
    with pytest.raises(sandbox.SandboxError, match=r"^student code cannot reach .*locked \(mode 0700\)"):
        sandbox.bwrap_problem()
    with pytest.raises(sandbox.SandboxError):
        sandbox.sandbox_mode()


def test_a_mount_that_appears_after_the_box_started_does_not_show_inside_it(box_folder):
    """bubblewrap alone makes a box a slave of the machine's mounts: a USB stick or a share mounted later
    under a shown folder appeared inside, writable. As root the box's mounts propagate nothing in."""
    from hri_teleop.grading.run.sandbox import StudentProcess, student_uid

    if os.geteuid() != 0:
        pytest.skip("mounting needs root")
    ws = box_folder / "ws"
    student = ws / "hri_lab"
    (ws / "later").mkdir(parents=True)
    student.mkdir()
    uid = student_uid()
    os.chown(student, uid, uid)
    (student / "x.py").write_text(
        "import os, time\nopen('started', 'w').close()\n"
        "while not os.path.exists('go'):\n    time.sleep(0.01)\n"
        f"print('seen' if os.path.exists({str(ws / 'later' / 'marker')!r}) else 'not seen')\n")
    env = dict(os.environ, ROS_PACKAGE_PATH=f"{ws}:/usr/share")
    # the machine's mounts shared, as systemd makes them (this container's are private)
    shared = subprocess.run(["sh", "-c", f"mount --bind {ws} {ws} && mount --make-shared {ws}"], capture_output=True,
                            text=True)
    if shared.returncode != 0:
        pytest.skip(f"cannot mount here: {shared.stderr.strip()}")
    proc = StudentProcess([sys.executable, str(student / "x.py")], student, env, box_folder / "x.log", uid=uid,
                          nested=False, network=False)
    mounted = False
    try:
        deadline = 600
        while not (student / "started").exists() and proc.running and deadline:
            deadline -= 1
            proc.wait(0.1)
        assert (student / "started").exists(), proc.output_tail()
        mount = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(ws / "later")],
                               capture_output=True, text=True)
        if mount.returncode != 0:
            pytest.skip(f"cannot mount here: {mount.stderr.strip()}")
        mounted = True
        (ws / "later" / "marker").write_text("a share mounted later")
        (student / "go").write_text("")
        assert proc.wait(60) == 0, proc.output_tail()
        assert "not seen" in proc.output_tail(), proc.output_tail()
    finally:
        proc.stop()
        if mounted:
            subprocess.run(["umount", str(ws / "later")], check=False)
        subprocess.run(["umount", str(ws)], check=False)


def test_a_kernel_gets_the_variables_it_reads_by_exact_name_and_no_token_of_the_grader():
    """Variables once passed by prefix (HRI_*, PYTHON*, ROS*, NBGRADER_*): the instructor's tokens with them."""
    from hri_teleop.grading.run.kernel_box import POLICY_ENV, kernel_environment

    grader = {"PATH": "/usr/bin", "ROS_MASTER_URI": "http://127.0.0.1:1/", "HRI_GRADE_SEED": "7",
              "NBGRADER_EXECUTION": "autograde", "PYTHONPATH": "/opt/ros/noetic/lib/python3/dist-packages",
              "HRI_CANVAS_TOKEN": "secret", "PYTHON_KEYRING_PASSWORD": "secret", "ROS_SECRET_TOKEN": "secret",
              "NBGRADER_API_TOKEN": "secret", "CATKIN_TOKEN": "secret", "LC_TOKEN": "secret", POLICY_ENV: "{}"}
    env = kernel_environment(grader, "/box/.home", "/box/.tmp")
    assert not [k for k, v in env.items() if v == "secret"] and POLICY_ENV not in env
    for kept in ("PATH", "ROS_MASTER_URI", "HRI_GRADE_SEED", "NBGRADER_EXECUTION", "PYTHONPATH"):
        assert env[kept] == grader[kept], kept
    assert env["HOME"] == "/box/.home" and env["TMPDIR"] == "/box/.tmp" and env["JPY_PARENT_PID"] == "1"
