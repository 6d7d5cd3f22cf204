"""The student bundle as a student receives it: unpacked on its own, set up with its Makefile, checked
with `make check`. It holds no answer; the answer key copied into its files gets full marks, untouched zero."""

from __future__ import annotations

import contextlib
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import tarfile
import tempfile
from pathlib import Path
from typing import Dict, List, Optional

import pytest
from bundle_helpers import copy_answer_key, files_points, notebook_points

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.bundle import (
    LAB_DELIVERABLES,
    answer_files,
    assemble_bundle,
    distinctive,
    pack_bundle,
    toolkit_leaks,
)
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.course.release import prepare_course_copy, solution_texts
from hri_teleop.grading.assignments import ASSIGNMENTS
from hri_teleop.grading.cases.templates import make_answer
from hri_teleop.ros.master import ManagedProcess, MasterError, RunningMaster, free_port
from hri_teleop.ros.proc_table import descendants

pytestmark = pytest.mark.ros

#: the notebooks `make check` runs here: a node check, a launch check and the pipeline's graph
CHECKED = "ex05,ex06,ex15"


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    return prepare_course_copy(tmp_path_factory.mktemp("bundle-course"))


@pytest.fixture(scope="module")
def home():
    """A student's home: readable by the unprivileged user the grader runs student code as (when
    the tests run as root), which pytest's own 0700 temporary folders are not."""
    folder = Path(tempfile.mkdtemp(prefix="hri-student-home-"))
    folder.chmod(0o755)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def unpacked(course, home, tmp_path_factory):
    """The bundle packed as `make release` packs it, then unpacked where no checkout is."""
    work = tmp_path_factory.mktemp("bundle")
    archive = pack_bundle(assemble_bundle(course / "release", work / "assembled", ASSIGNMENTS), work / "b.tar.gz")
    with tarfile.open(archive) as tar:
        tar.extractall(home)
    return home / "task4"


def _copy(installed: Path, home: Path, name: str) -> Path:
    """A second student's folder sharing the installed toolkit's .venv (set up once)."""
    bundle = home / name / "task4"
    shutil.copytree(installed, bundle, symlinks=True, ignore=shutil.ignore_patterns(".venv"))
    os.symlink(installed / "toolkit" / ".venv", bundle / "toolkit" / ".venv")
    (home / name).chmod(0o755)
    return bundle


def test_the_bundle_has_its_three_commands_and_the_provided_nodes(unpacked):
    make = (unpacked / "Makefile").read_text()
    for target in ("setup:", "lab:", "check:"):
        assert target in make
    assert "make check" in (unpacked / "README.md").read_text()
    scripts = unpacked / "toolkit" / "hri_lab" / "scripts"
    for provided in ("FSR_sensor.py", "gripper_manager.py", "teleoperation_subscriber_publisher.py", "lab_sim.py"):
        assert (scripts / provided).is_file(), provided
    for assignment in ASSIGNMENTS:
        assert (unpacked / assignment / STUDENT_PACKAGE / "package.xml").is_file()


def test_the_pages_the_provided_nodes_point_to_are_in_the_bundle_and_the_rubric_is_not(unpacked):
    toolkit = unpacked / "toolkit"
    pointed = {m for path in (toolkit / "hri_lab").rglob("*") if path.is_file() and path.suffix in (".py", ".md")
               for m in re.findall(r"docs/[\w-]+\.md", path.read_text(encoding="utf-8"))}
    assert "docs/ros-nodes.md" in pointed
    assert [page for page in sorted(pointed) if not (toolkit / page).is_file()] == []
    assert not (toolkit / "docs" / "instructors.md").exists()


def test_the_bundle_holds_the_browser_pad_for_the_students_own_node_and_no_reference_node(unpacked):
    toolkit = unpacked / "toolkit"
    for needed in ("hri_teleop/course/widgets/browser_pad.py", "hri_teleop/course/widgets/browser_pad.js",
                   "hri_teleop/course/widgets/hold_button.js", "hri_teleop/hardware/joy_pad.py",
                   "hri_teleop/course/pad_route.py", "docs/browser-pad.md"):
        assert (toolkit / needed).is_file(), needed
    for reference in ("hri_lab/scripts/teleoperation.py", "hri_lab/launch/teleoperation.launch"):
        assert not (toolkit / reference).exists(), reference
    # the student's own node takes its pad from ~pad (given code): _pad:=browser reads the page's pad
    template = (unpacked / "lab" / STUDENT_PACKAGE / "scripts" / "teleoperation.py").read_text(encoding="utf-8")
    assert 'node.open_pad(rospy.get_param("~pad", "pygame")' in template
    for notebook in ("ex08_gamepad_commands", "ex09_teleoperation_node", "ex10_teleoperate_robot",
                     "ex14_force_feedback"):
        text = (unpacked / "lab" / f"{notebook}.ipynb").read_text(encoding="utf-8")
        assert 'PAD = \\"browser\\"' in text or "lab.browser_pad(PAD)" in text, notebook


def test_the_bundle_holds_no_solution_line_and_no_completed_deliverable(unpacked, course):
    assert toolkit_leaks(unpacked, solution_texts(SOLUTIONS, course), answer_files()) == []
    assert not (unpacked / "toolkit" / "tests").exists() and not (unpacked / "toolkit" / "solutions").exists()


def test_the_leak_check_finds_a_deliverable_copied_into_the_toolkit(unpacked, course, tmp_path):
    bundle = tmp_path / "task4"
    shutil.copytree(unpacked, bundle, symlinks=True, ignore=shutil.ignore_patterns(".venv"))  # no packages: never scanned
    hidden = bundle / "toolkit" / "hri_teleop" / "hardware" / "sim" / "answer.launch"
    hidden.write_text(make_answer((SOLUTIONS / "launch" / "sensor.launch").read_text()))
    (bundle / "toolkit" / LAB_DELIVERABLES[0]).write_text("#!/usr/bin/env python3\n")
    leaks = toolkit_leaks(bundle, solution_texts(SOLUTIONS, course), answer_files())
    assert any("answer.launch" in leak and "completed" in leak for leak in leaks)
    assert any(LAB_DELIVERABLES[0] in leak for leak in leaks)


def _student_env() -> dict:
    """Only the machine's own PATH: no project .venv, no ROS_PACKAGE_PATH pointing at this checkout."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "VIRTUAL_ENV", "PYTHON", "HRI_"))}
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if ".venv" not in p)
    env["SDL_VIDEODRIVER"] = env["SDL_AUDIODRIVER"] = "dummy"
    return env


def _make(bundle: Path, *args: str, timeout: float, extra_env: Optional[Dict[str, str]] = None
          ) -> subprocess.CompletedProcess:
    env = dict(_student_env(), **(extra_env or {}))
    return subprocess.run(["make", "-C", str(bundle), *args], capture_output=True, text=True, timeout=timeout,
                          env=env, stdin=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def installed(unpacked):
    """`make setup` of the bundle: its own venv with the toolkit, as on a student's machine."""
    done = _make(unpacked, "setup", timeout=1200)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    return unpacked


def test_the_installed_toolkit_holds_no_answer(installed, course):
    site = next((installed / "toolkit" / ".venv" / "lib").glob("python3*/site-packages"))
    probe = subprocess.run([str(installed / "toolkit" / ".venv" / "bin" / "python"), "-c",
                            "import hri_teleop, pathlib; print(pathlib.Path(hri_teleop.__file__).parent)"],
                           capture_output=True, text=True, check=True, cwd=installed, env=_student_env())
    assert Path(probe.stdout.strip()) == installed / "toolkit" / "hri_teleop"  # no checkout is imported
    # the toolkit is installed in place: site-packages holds only its metadata and import hook
    owned = [p.name for p in site.iterdir() if "hri_teleop" in p.name]
    assert owned and all(n.endswith(".dist-info") or n.startswith("__editable__") for n in owned), owned
    assert toolkit_leaks(installed / "toolkit", solution_texts(SOLUTIONS, course), answer_files()) == []


def _checked_points() -> float:
    """The points of the checks the notebooks of CHECKED show (mapping-node, sensor-launch, graph)."""
    from hri_teleop.apps.files_check import checks_for
    from hri_teleop.grading.points import check_points

    return sum(check_points(c) for a in ASSIGNMENTS for c in checks_for(a, CHECKED.split(",")))


def _listing(bundle: Path) -> Dict[str, tuple]:
    """Every entry of the student's side of the bundle (all but the toolkit), folders included, with its
    kind, size and modification time: a file written, changed or removed anywhere changes it."""
    entries = {".": bundle.lstat()}
    for top in bundle.iterdir():
        if top.name != "toolkit":
            entries[top.name] = top.lstat()
            if top.is_dir() and not top.is_symlink():
                entries.update({str(p.relative_to(bundle)): p.lstat() for p in top.rglob("*")})
    return {name: (st.st_mode, st.st_size, st.st_mtime_ns) for name, st in sorted(entries.items())}


@pytest.fixture(scope="module")
def untouched_check(installed, home):
    """`make check ONLY=CHECKED` of an untouched bundle: (bundle, listing before, listing after, the run)."""
    bundle = _copy(installed, home, "untouched")
    before = _listing(bundle)
    done = _make(bundle, "check", f"ONLY={CHECKED}", timeout=1200)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return bundle, before, _listing(bundle), done


def test_untouched_the_bundle_scores_zero(untouched_check):
    _bundle, _before, _after, done = untouched_check
    scores = notebook_points(done.stdout)
    assert len(scores) == 3 and all(got == 0 for got, _most in scores.values()), done.stdout
    assert files_points(done.stdout) == (0, _checked_points()), done.stdout


def _failing_parts(feedback: str) -> List[str]:
    """The lines of each failing part of a check's feedback (its [FAIL] line and its message), without the
    grader's scratch paths (a new folder in every run)."""
    shown, failing = [], False
    for line in feedback.splitlines():
        if line.startswith("  ["):
            failing = line.startswith("  [FAIL]")
        elif not line.startswith("         "):
            failing = False
        if failing and "/tmp/hri-grade-" not in line:
            shown.append(line.strip())
    return shown


@pytest.mark.parametrize("cell, package", [("mapping_node", "preparation"), ("graph", "lab")])
def test_make_check_shows_each_failing_part_with_the_feedback_its_check_cell_shows(installed, untouched_check, cell,
                                                                                  package):
    bundle, _before, _after, done = untouched_check
    # the installed bundle's Python, as the notebooks' kernel runs it (this copy's .venv is a link to it,
    # and a student process started through the link would not find it in its box)
    python = installed / "toolkit" / ".venv" / "bin" / "python"
    in_the_cell = subprocess.run(
        ["bash", "-c", f". toolkit/tools/env.sh && {python} -c "
                       f"'from hri_teleop.course import check; check.{cell}(\"{package}/{STUDENT_PACKAGE}\")'"],
        cwd=bundle, env=_student_env(), capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert in_the_cell.returncode == 0, in_the_cell.stdout[-2000:] + in_the_cell.stderr[-2000:]
    expected = _failing_parts(in_the_cell.stdout)
    assert expected and any(line.startswith("[FAIL]") for line in expected), in_the_cell.stdout
    printed = {line.strip() for line in done.stdout.splitlines()}
    assert [line for line in expected if line not in printed] == [], done.stdout


def test_make_check_leaves_the_students_folders_as_they_were(untouched_check):
    _bundle, before, after, done = untouched_check
    assert "in a copy of its folder" in done.stdout
    assert {k: v for k, v in after.items() if before.get(k) != v} == {}
    assert [k for k in before if k not in after] == []


def _carrying(marker: str) -> Dict[int, str]:
    """pid -> command line of each live process whose environment holds HRI_TEST_MARKER=marker."""
    needle, found = f"HRI_TEST_MARKER={marker}".encode(), {}
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and needle in (entry / "environ").read_bytes().split(b"\0") \
                    and (entry / "stat").read_text().rsplit(")", 1)[-1].split()[0] != "Z":
                found[int(entry.name)] = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, IndexError):  # ended meanwhile, or another user's
            continue
    return found


def test_ctrl_c_stops_make_check_with_every_kernel_node_and_roscore_it_started(installed, home):
    bundle = _copy(installed, home, "ctrl-c")
    marker = f"ctrl-c-{os.getpid()}"
    proc = subprocess.Popen(["make", "-C", str(bundle), "check"], env=dict(_student_env(), HRI_TEST_MARKER=marker),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, stdin=subprocess.DEVNULL,
                            start_new_session=True)
    try:
        seen = []
        for line in proc.stdout:  # the first notebook ended: two more kernels, their masters and nodes run
            seen.append(line)
            if ".ipynb ... " in line:
                break
        assert _carrying(marker), "".join(seen)
        os.killpg(proc.pid, signal.SIGINT)  # what Ctrl-C in the terminal does
        rest, _ = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert "check: stopped (Ctrl-C)" in rest, "".join(seen) + rest
    assert "points for your files" not in rest
    assert _carrying(marker) == {}


def test_the_readme_names_hri_grade_and_its_lines_run_in_the_bundle(installed, home):
    bundle = _copy(installed, home, "hri-grade")
    readme = (bundle / "README.md").read_text(encoding="utf-8")
    block = readme.split("One check on its own", 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    lines = [_command(line) for line in block.splitlines() if line.strip()]
    assert lines[0] == "source toolkit/tools/env.sh" and "toolkit/.venv/bin/hri-grade" in readme
    assert len(lines) > 2 and all(line.startswith("hri-grade ") for line in lines[1:]), lines
    for line in lines[1:]:
        ran = subprocess.run(["bash", "-c", f"{lines[0]} && {line}"], cwd=bundle, env=_student_env(),
                             capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL)
        # exit 1: a check failed (the bundle is untouched); 2 would be the grader unable to run
        assert ran.returncode in (0, 1), f"{line}: exit {ran.returncode}\n{ran.stdout[-2000:]}{ran.stderr[-2000:]}"
        assert "total: 0/" in ran.stdout or line.endswith("-h"), f"{line}:\n{ran.stdout[-2000:]}"


def test_with_the_answer_key_copied_in_the_bundle_gets_full_marks_even_run_on_the_lab_pcs_master(
        installed, course, home, lab_twin):
    """On the lab PC (here its twin: ROS_MASTER_URI points at it, nothing else set) make check still
    grades on private masters: Ex. 10's scripted pad and simulated robot never reach the real ones."""
    bundle = _copy(installed, home, "answers")
    copy_answer_key(bundle, course)
    on_the_lab_pc = {"ROS_MASTER_URI": lab_twin.master_uri, "HRI_OWN_MASTER": ""}
    done = _make(bundle, "check", f"ONLY={CHECKED},ex10", timeout=1200, extra_env=on_the_lab_pc)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert f"check: grading on private masters (ROS_MASTER_URI={lab_twin.master_uri} is not used)" in done.stdout
    scores = notebook_points(done.stdout)  # the check cells' notebooks show 0/0: their points are the files'
    assert len(scores) == 4 and all(got == most for got, most in scores.values()), done.stdout
    assert scores["ex10_teleoperate_robot"][1] > 0, done.stdout
    assert files_points(done.stdout) == (_checked_points(),) * 2 > (0, 0), done.stdout
    report = lab_twin.report()
    assert report.nonzero_twists == 0 and sum(report.gripper_goals.values()) == 0, report.lines()
    assert report.pub_force_publishers == ["/serial_node"], report.lines()
    assert report.replaced == [] and report.stopped == [], report.lines()


def test_make_lab_serves_the_bundle_with_the_toolkits_kernel(installed):
    done = _make(installed, "lab", "LAB_ARGS=--version", timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    kernel = json.loads(next((installed / "toolkit" / ".venv" / "share" / "jupyter" / "kernels").glob(
        "hri-teleop/kernel.json")).read_text())
    assert kernel["argv"][1] == str(installed / "toolkit" / "tools" / "kernel.sh")
    assert done.stderr.strip() == ""


def test_make_doctor_checks_the_simulated_lab_from_the_bundle_alone(installed):
    env = _student_env()
    env.update({"HRI_MODE": "home", "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}/"})  # nobody there
    done = subprocess.run(["make", "-C", str(installed), "doctor"], capture_output=True, text=True, timeout=300,
                          env=env, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert re.search(r"^ok\s+robot\s+the simulation \(lab_sim\)", done.stdout, re.M), done.stdout
    assert re.search(r"^ok\s+board\s+the simulated board", done.stdout, re.M), done.stdout


# -- what the notebooks and the README name ------------------------------------------------------

_BACKTICKED = re.compile(r"`([^`\s]+)`")
_FILE_SUFFIX = re.compile(r"\.(py|launch|yaml|yml|ipynb|md|txt|xml|ino|h|cpp|png|sh|bag|csv|json)$")
#: Named by a notebook but made later, not shipped: by the build cells, or by the student.
MADE_LATER = {
    "catkin_ws/": "the build cells of ex09 and ex12_13 (build_workspace) make it",
    "hri_lab/scripts/teleoperation_remapped.py": "Ex. 10 has the student write this copy",
}


def _markdown(notebook: Path) -> str:
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    return "\n".join("".join(c["source"]) if isinstance(c["source"], list) else c["source"]
                     for c in cells if c["cell_type"] == "markdown")


def _named_paths(text: str) -> list:
    """Files and folders named in backticks: relative, with a file suffix or a trailing slash
    (not topics, message types, commands or URLs)."""
    return [t for t in _BACKTICKED.findall(text) if "/" in t and not t.startswith(("/", "$", "~", "!", "http"))
            and (t.endswith("/") or _FILE_SUFFIX.search(t))]


def test_every_file_or_folder_a_notebook_names_is_in_the_bundle(unpacked):
    checked, missing = [], []
    for notebook in sorted(unpacked.glob("*/*.ipynb")):
        bases = (notebook.parent, notebook.parent / STUDENT_PACKAGE, unpacked, unpacked / "toolkit")
        for named in _named_paths(_markdown(notebook)):
            checked.append(named)
            if named not in MADE_LATER and not any(glob.glob(str(base / named)) for base in bases):
                missing.append(f"{notebook.relative_to(unpacked)}: `{named}`")
    assert "toolkit/firmware/arduino_code_force_node/" in checked and len(checked) >= 10, checked
    assert missing == []


def _make_targets_named(text: str) -> set:
    """`make X` in backticks, and code lines that start with make X."""
    return set(re.findall(r"`make ([\w-]+)", text)) | set(re.findall(r"^\s*make ([\w-]+)", text, re.M))


def test_every_make_target_the_notebooks_and_the_readme_name_is_in_the_bundles_makefile(unpacked):
    targets = set(re.findall(r"^([\w-]+):", (unpacked / "Makefile").read_text(), re.M))
    named = {}
    for source in [unpacked / "README.md", *sorted(unpacked.glob("*/*.ipynb"))]:
        text = _markdown(source) if source.suffix == ".ipynb" else source.read_text(encoding="utf-8")
        for target in _make_targets_named(text):
            named.setdefault(target, source.name)
    assert {"setup", "lab", "check", "doctor"} <= set(named), named
    assert {t: where for t, where in named.items() if t not in targets} == {}


def test_the_leak_check_finds_a_solution_line_inside_a_string_of_the_toolkit(unpacked, course, tmp_path):
    texts = solution_texts(SOLUTIONS, course)
    line = next(line.strip() for where, lines in texts.items() if where.endswith("mapping_node.py")
                for line in lines if distinctive(line))
    bundle = tmp_path / "task4"
    # without the .venv `make setup` may have put in (1.4 GB of packages, never scanned for leaks)
    shutil.copytree(unpacked, bundle, symlinks=True, ignore=shutil.ignore_patterns(".venv"))
    (bundle / "toolkit" / "hri_teleop" / "grading" / "judge" / "hint.py").write_text(f"HINT = 'write {line} here'\n")
    leaks = toolkit_leaks(bundle, texts, answer_files())
    assert [leak for leak in leaks if "hint.py" in leak and "inside a longer line" in leak], leaks


# -- the README's terminal workflow, line by line ------------------------------------------------

#: Lines that keep running: started in the background, then judged by what appears on the master.
_LONG_RUNNING = ("roscore", "rosrun", "roslaunch")
#: The handout's commands the README's section "In a terminal" must give (as a line or its start).
HANDOUT_LINES = ("cd preparation && source ../toolkit/tools/env.sh", "roscore", "rosrun hri_lab FSR_sensor.py",
                 "rosparam set /max_sensor_force 700", "rosrun hri_lab mapping_node.py",
                 "roslaunch hri_lab sensor.launch", "cd lab && source ../toolkit/tools/env.sh",
                 "cd catkin_ws && catkin_make && source devel/setup.bash", "rosrun hri_lab teleoperation.py",
                 "roslaunch hri_lab teleoperation.launch")
_TWIST = "/cartesian_velocity_controller/cmd_vel"


def _terminal_blocks(readme: str) -> list:
    """(subsection, [lines]) of each code block in the README's section "In a terminal", in order."""
    section = readme.split("\n## In a terminal\n", 1)[1].split("\n## ", 1)[0]
    blocks, current, subsection = [], None, ""
    for line in section.splitlines():
        if line.startswith("### "):
            subsection = line[4:].strip()
        elif line.startswith("```"):
            if current is None:
                current = []
            else:
                blocks.append((subsection, [x for x in current if x.strip() and not x.strip().startswith("#")]))
                current = None
        elif current is not None:
            current.append(line)
    return blocks


def _command(line: str) -> str:
    return re.sub(r"\s+#.*$", "", line).strip()


class _Shell:
    """One terminal's state -- its folder and environment -- carried from line to line."""

    MARK = "__hri_terminal_state__"

    def __init__(self, cwd: Path, env: dict) -> None:
        self.cwd, self.env = cwd, dict(env)

    def run(self, line: str, timeout_s: float = 900) -> str:
        script = f'{line}\n__status=$?\nprintf "\\n%s\\n" {self.MARK}; pwd; env -0; exit $__status\n'
        done = subprocess.run(["bash", "-c", script], cwd=self.cwd, env=self.env, capture_output=True,
                              timeout=timeout_s, stdin=subprocess.DEVNULL)
        out = done.stdout.decode(errors="replace")
        assert done.returncode == 0 and self.MARK in out, \
            f"`{line}` in {self.cwd}: exit {done.returncode}\n{out[-3000:]}\n{done.stderr.decode(errors='replace')[-3000:]}"
        printed, state = out.rsplit(f"\n{self.MARK}\n", 1)
        folder, _, variables = state.partition("\n")
        self.cwd = Path(folder)
        self.env = dict(item.split("=", 1) for item in variables.split("\0") if "=" in item)
        return printed


def _expect(command: str, master, started: list):
    """(what, condition) a long-running line of the README must bring about on the master."""
    def publishes(node: str, topic: str, *inputs: str):
        return lambda: node in master.publishers(topic) and all(master.connections(node, t) > 0 for t in inputs)

    if command.startswith("roscore"):
        return "the master to answer", master.is_online
    if command == "rosrun hri_lab FSR_sensor.py":
        return "/FSR_sensor to publish /pub_force", publishes("/FSR_sensor", "/pub_force")
    if command == "rosrun hri_lab mapping_node.py":
        return ("/mapping_node to publish /force_mapped, fed by /pub_force",
                publishes("/mapping_node", "/force_mapped", "/pub_force"))
    if command == "roslaunch hri_lab sensor.launch":
        replaced = [p for c, p in started if c in ("rosrun hri_lab FSR_sensor.py", "rosrun hri_lab mapping_node.py")]
        launched = publishes("/mapping_node", "/force_mapped", "/pub_force")
        return ("the launch's FSR_sensor and mapping_node (the rosrun ones stopped first) to connect",
                lambda: launched() and "/FSR_sensor" in master.publishers("/pub_force")
                and not any(p.running for p in replaced))
    if command.startswith("rosrun hri_lab teleoperation.py"):
        return ("/teleoperation to publish the twist, fed by /force_mapped",
                publishes("/teleoperation", _TWIST, "/force_mapped"))
    pytest.fail(f"the README runs `{command}`, which this test does not know: say here what it must start")


def _lab_only(shell: _Shell, command: str, bundle: Path) -> None:
    """The lab's roslaunch at home: it finds the student's launch file, then stops at the lab's packages."""
    found = shell.run("rospack find hri_lab").strip().splitlines()[-1]
    assert Path(found).resolve() == (bundle / "lab" / STUDENT_PACKAGE).resolve(), found
    assert command == "roslaunch hri_lab teleoperation.launch", command
    if subprocess.run(["bash", "-c", "rospack find franka_control"], env=shell.env, capture_output=True).returncode:
        done = subprocess.run(["bash", "-c", command], cwd=shell.cwd, env=shell.env, capture_output=True, text=True,
                              timeout=120, stdin=subprocess.DEVNULL)
        assert done.returncode != 0 and "franka_control" in done.stdout + done.stderr, done.stdout + done.stderr


def test_the_readmes_terminal_lines_work_as_written(installed, course, home, tmp_path):
    bundle = _copy(installed, home, "terminal")
    copy_answer_key(bundle, course)
    blocks = _terminal_blocks((bundle / "README.md").read_text(encoding="utf-8"))
    commands = [_command(line) for _sub, lines in blocks for line in lines]
    assert [h for h in HANDOUT_LINES if not any(c.startswith(h) for c in commands)] == []
    lab_block = [_command(line) for sub, lines in blocks if sub == "In the lab" for line in lines]
    assert "roscore" not in lab_block and any("ROS_MASTER_URI" in c for c in lab_block), lab_block

    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    env = _student_env()
    env.update({"ROS_MASTER_URI": uri, "ROS_HOME": str(tmp_path / "ros_home"), "ROS_LOG_DIR": str(tmp_path / "log")})
    master = RunningMaster(uri, base_env=env, work_dir=tmp_path / "master")
    started: list = []
    try:
        for subsection, lines in blocks:
            shell = _Shell(bundle, env)
            for line in lines:
                command = _command(line)
                if not command.startswith(_LONG_RUNNING):
                    shell.run(line)
                elif subsection == "In the lab":
                    _lab_only(shell, command, bundle)
                else:
                    # "(Ctrl-C the two above first)": as the README says. Left running, two nodes replaced
                    # by name at once can lose their connection to each other (rospy drops the first
                    # of two subscriptions with one caller id; L26 waited 120 s for /pub_force).
                    asked = re.search(r"Ctrl-C the (one|two|three) above first", line)
                    if asked:
                        for _c, earlier in started[-("one", "two", "three").index(asked.group(1)) - 1:]:
                            earlier.stop()
                    run = re.sub(r"^roscore\b", f"roscore -p {port}", line)  # a private master, never 11311
                    proc = ManagedProcess(["bash", "-c", run], shell.env, tmp_path / f"line{len(started)}.log",
                                          cwd=shell.cwd)
                    started.append((command, proc))
                    what, condition = _expect(command, master, started)
                    try:
                        master.wait_for(lambda c=condition, p=proc: c() or not p.running, 120, what)
                    except MasterError:
                        pytest.fail(f"`{line}`: timed out waiting for {what}\n{proc.output()[-3000:]}")
                    assert proc.running, f"`{line}` ended:\n{proc.output()[-3000:]}"
            if subsection == "" and lines:  # the first block: the shell of an assignment folder
                found = shell.run("rospack find hri_lab").strip().splitlines()[-1]
                assert Path(found) == (bundle / "preparation" / STUDENT_PACKAGE).resolve(), found
    finally:
        family = [pid for _c, p in started for pid in descendants(p.popen.pid)]
        for _c, proc in reversed(started):
            proc.stop()
        for pid in family:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
    assert [c for c, p in started if p.anything_left] == []


def test_make_doctor_from_a_shell_sourced_in_an_assignment_still_finds_the_toolkits_simulation(installed):
    env = _student_env()
    env.update({"HRI_MODE": "home", "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}/"})  # nobody there
    script = ("cd preparation && source ../toolkit/tools/env.sh && rospack find hri_lab && "
              "cd .. && make --no-print-directory doctor")
    done = subprocess.run(["bash", "-c", script], cwd=installed, capture_output=True, text=True, timeout=300, env=env,
                          stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert done.stdout.splitlines()[0] == str((installed / "preparation" / STUDENT_PACKAGE).resolve()), done.stdout
    assert re.search(r"^ok\s+robot\s+the simulation \(lab_sim\)", done.stdout, re.M), done.stdout
