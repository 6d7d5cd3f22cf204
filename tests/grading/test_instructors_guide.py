"""docs/instructors.md's grading cycle, run as written from a fresh shell, on a scratch course (issue 43, item 8).

The commands are read from the guide's own ``bash`` block of "The cycle" (and the exchange commands its
comments give), so a change of the guide that breaks one fails here. Each runs in a shell without the
project's environment (no .venv on PATH, no ROS variables: nbgrader is not reachable but through what the
guide says); DIR, OUT and the like point ``make`` at a scratch course with two notebooks of the
preparation (Ex. 4: autograded cells, a written answer and the robot-params check; Ex. 6-7: only the
sensor-launch check, which nbgrader scores 0.0 / 0.0). Three students: alice (the answer key) and bob (the
untouched release) hand in through nbgrader's exchange, carl's folder is unpacked into submitted/. The
written answer is graded by hand through the running formgrader's own API. What the students then fetch
with ``nbgrader fetch_feedback`` (what ``release_feedback`` shipped) must carry their files' points and
feedback, with each page's score counting the parts it shows, and no path of the grading machine.
``make release`` runs dry (``make -n``): it builds the bundle of the checkout's own course.
"""

from __future__ import annotations

import csv
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from typing import Dict, List, Optional

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course, run_session

pytestmark = pytest.mark.ros

GUIDE = REPO / "docs" / "instructors.md"
ASSIGNMENT = "preparation"
NOTEBOOKS = ("ex04_robot_params", "ex06_07_sensor_launch")
CHECKS = "robot-params,sensor-launch"
COURSE_ID = "hri-task4-teleoperation"
TOKEN = "guide-test-token"
#: A make command in a comment line of the block (the exchange's release and collect).
_MAKE_IN_TEXT = re.compile(r"\bmake [a-z][\w-]*(?: [A-Z_]+=(?:\"[^\"]*\"|\S+))*")


def guide_commands(text: str) -> List[str]:
    """The commands of the guide's block under "## The cycle", in order: its lines (without their comments),
    and the make commands its comment lines give."""
    section = text[text.index("## The cycle"):]
    block = section[section.index("```bash\n") + len("```bash\n"):]
    block = block[:block.index("```")]
    commands = []
    for line in block.splitlines():
        if line.lstrip().startswith("#"):
            commands += [m.group(0).rstrip(",.;:)") for m in _MAKE_IN_TEXT.finditer(line)]
        elif line.strip():
            commands.append(shlex.join(shlex.split(line, comments=True)))
    return commands


def fresh_env(**extra: str) -> Dict[str, str]:
    """A new terminal's environment: this one without what tools/env.sh and the venv add."""
    drop = ("ROS", "HRI_", "PYTHON", "VIRTUAL_ENV", "CMAKE_PREFIX_PATH", "PKG_CONFIG_PATH", "LD_LIBRARY_PATH",
            "CATKIN", "JUPYTER", "NBGRADER", "MAKE", "MFLAGS")
    env = {k: v for k, v in os.environ.items() if not k.startswith(drop)}
    env["PATH"] = ":".join(p for p in os.environ.get("PATH", "/usr/bin:/bin").split(":")
                           if p and not p.startswith(str(REPO)) and "/opt/ros" not in p and "/.venv" not in p)
    env.update(extra)
    return env


def _shell(command: str, env: Dict[str, str], timeout: float = 600) -> subprocess.CompletedProcess:
    done = run_session(["bash", "--noprofile", "--norc", "-c", command], REPO, env, timeout)
    return subprocess.CompletedProcess(command, done.returncode, done.stdout, "")


def _student_nbgrader(args: List[str], cwd: Path, exchange: Path) -> str:
    """A student's own nbgrader (fetch, submit, fetch_feedback) against the course's exchange, with a cache of
    their own (the student's home has it: fetch_feedback fetches for every submission in the cache)."""
    proc = subprocess.run([sys.executable, "-m", "nbgrader", *args, f"--course={COURSE_ID}",
                           f"--Exchange.root={exchange}", f"--Exchange.cache={cwd / '.nbgrader_cache'}"],
                          cwd=cwd, capture_output=True, text=True, env=grader_env(PYTHONWARNINGS="ignore"), timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    return proc.stdout + proc.stderr


def _hand_in(course: Path, exchange: Path, students: Path) -> None:
    """alice (the answer key) and bob (the release as fetched) submit through the exchange."""
    from hri_teleop.grading.cases.templates import generate_answers

    for student in ("alice", "bob"):
        home = students / student
        home.mkdir(parents=True)
        _student_nbgrader(["fetch_assignment", ASSIGNMENT], home, exchange)
        if student == "alice":
            for name in NOTEBOOKS:
                shutil.copy(course / "source" / ASSIGNMENT / f"{name}.ipynb", home / ASSIGNMENT)
            shutil.rmtree(home / ASSIGNMENT / "hri_lab")
            generate_answers(SOLUTIONS, home / ASSIGNMENT / "hri_lab")
        _student_nbgrader(["submit", ASSIGNMENT, f"--student={student}"], home, exchange)


def _api(port: int, path: str, body: Optional[dict] = None):
    request = urllib.request.Request(f"http://127.0.0.1:{port}/formgrader/api/{path}",
                                     data=json.dumps(body).encode() if body is not None else None,
                                     method="PUT" if body is not None else "GET",
                                     headers={"Authorization": f"token {TOKEN}", "Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=30) as response:
        return json.loads(response.read().decode())


def _grade_by_hand_in_the_formgrader(command: str, env: Dict[str, str]) -> float:
    """Start the guide's formgrader command, give alice's written answer of Ex. 4 its point through the
    formgrader's API, stop it; the points given."""
    from hri_teleop.ros.master import free_port

    port = free_port()
    env = dict(env, FORMGRADER_ARGS=f"--no-browser --port={port} --IdentityProvider.token={TOKEN}")
    proc = subprocess.Popen(["bash", "--noprofile", "--norc", "-c", command], cwd=REPO, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        deadline = time.monotonic() + 300
        while True:
            try:
                _api(port, "status")
                break
            except OSError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    pytest.fail(f"{command}: the formgrader never answered\n{proc.stdout.read()[-3000:]}")
                time.sleep(0.5)
        assert [a["name"] for a in _api(port, "assignments")] == [ASSIGNMENT]
        submission = next(s for s in _api(port, f"submitted_notebooks/{ASSIGNMENT}/{NOTEBOOKS[0]}")
                          if s["student"] == "alice")
        written = [g for g in _api(port, f"grades?submission_id={submission['id']}") if g["auto_score"] is None]
        assert [g["name"] for g in written] == ["ex4_structure"], written
        graded = _api(port, f"grade/{written[0]['id']}", {"manual_score": written[0]["max_score"]})
        assert graded["manual_score"] == written[0]["max_score"] and not graded["needs_manual_grade"]
        return float(graded["manual_score"])
    finally:
        os.killpg(proc.pid, signal.SIGTERM)  # make, and the JupyterLab it started
        try:
            proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        print(f"$ {command}\n{proc.stdout.read()[-3000:]}")


def _heading_score(page: str) -> float:
    found = re.search(r"<h4>[^<(]* \(Score: (-?[\d.]+) / (-?[\d.]+)[^<]*</h4>", page)
    assert found, page[:2000]
    print(found.group(0))
    return float(found.group(1))


def test_the_guides_grading_cycle_runs_as_written_from_a_fresh_shell(tmp_path):
    from hri_teleop.course.nodes import STUDENT_PACKAGE
    from hri_teleop.grading.cases.templates import generate_templates

    commands = guide_commands(GUIDE.read_text())
    targets = [shlex.split(c)[1] if c.startswith("make ") else c for c in commands]
    assert targets == ["release", "nbgrader", "nbgrader", "grade", "formgrader", "feedback", "release-feedback"], \
        commands
    exchange = tmp_path / "exchange"
    exchange.mkdir()
    course = nbgrader_course(tmp_path / "course", ASSIGNMENT, list(NOTEBOOKS), f"\nc.Exchange.root = {str(exchange)!r}\n")
    generate_templates(SOLUTIONS, course / "release" / ASSIGNMENT / STUDENT_PACKAGE)
    out = tmp_path / "grades"
    env = fresh_env(DIR=str(course), OUT=str(out), CHECKS=CHECKS, JOBS="2")
    assert shutil.which("nbgrader", path=env["PATH"]) is None, "the fresh shell reaches nbgrader without the guide"

    by_hand = 0.0
    for command in commands:
        if command == "make release":  # the checkout's own bundle: what it would run, not run
            dry = _shell("make -n release", env)
            assert dry.returncode == 0 and "hri_teleop.apps.course release" in dry.stdout, dry.stdout
            continue
        if command.startswith("make formgrader"):
            by_hand = _grade_by_hand_in_the_formgrader(command, env)
            continue
        run = _shell(command, env)
        assert run.returncode == 0, run.stdout[-3000:]
        if "release_assignment" in command:
            _hand_in(course, exchange, tmp_path / "students")
        elif "collect" in command:
            assert sorted(p.name for p in (course / "submitted").iterdir()) == ["alice", "bob"]
            assert (course / "submitted" / "alice" / ASSIGNMENT / "submission_secret.txt").is_file()
            shutil.copytree(course / "release" / ASSIGNMENT, course / "submitted" / "carl" / ASSIGNMENT)  # unpacked
        elif command.startswith("make release-feedback"):
            assert re.search(r"carl handed in without nbgrader submit .* hand out", run.stdout), run.stdout
    assert by_hand == 1.0

    with open(out / "grades.csv") as fh:
        rows = {row["student"]: row for row in csv.DictReader(fh)}
    assert sorted(rows) == ["alice", "bob", "carl"] and {r["status"] for r in rows.values()} == {"graded"}
    assert rows["alice"]["needs_manual_grade"] == "" and float(rows["alice"]["files_score"]) == 20

    # what the students receive: nbgrader fetch_feedback of what release_feedback shipped
    received: Dict[str, Dict[str, str]] = {}
    for student in ("alice", "bob"):
        home = tmp_path / "students" / student
        _student_nbgrader(["fetch_feedback", ASSIGNMENT, f"--student={student}"], home, exchange)
        pages = sorted((home / ASSIGNMENT / "feedback").glob("*/*.html"))
        assert [p.stem for p in pages] == list(NOTEBOOKS), pages
        received[student] = {p.stem: p.read_text() for p in pages}
    alice, bob = received["alice"], received["bob"]
    # the score of each page counts the files' parts its check cell shows; together the assignment's points
    assert "Score: 0.0 / 0.0" not in alice["ex06_07_sensor_launch"]
    assert _heading_score(alice["ex06_07_sensor_launch"]) == 10.0 and _heading_score(bob["ex06_07_sensor_launch"]) == 0
    assert _heading_score(alice["ex04_robot_params"]) == 13.0  # 2 autograded + 1 by hand + robot-params 10
    assert sum(_heading_score(p) for p in alice.values()) == float(rows["alice"][f"{ASSIGNMENT}_score"]) == 23
    assert sum(_heading_score(p) for p in bob.values()) == float(rows["bob"][f"{ASSIGNMENT}_score"])
    # the files' points and feedback, in the grader's words (not the kernel's print of the check cell)
    for page in bob.values():
        assert "Your hri_lab files (preparation): 0 / 20 points" in page
    assert "This notebook's check cells show sensor-launch 0 / 10" in bob["ex06_07_sensor_launch"]
    assert "[FAIL] parses with roslaunch (0/1)" in bob["ex06_07_sensor_launch"].split('id="hri-files-feedback"')[1]
    assert "robot-params (hri_lab/config/robot_params.yaml): 0/10" in bob["ex04_robot_params"]
    # no path of the grading machine: the course, OUT, the checkout, /tmp boxes
    for student, pages in received.items():
        for name, page in pages.items():
            for path in (str(tmp_path), str(REPO), str(course), str(out), "/tmp/", str(Path.home()) + "/"):
                assert path not in page, (student, name, path, page[max(0, page.find(path) - 300):page.find(path) + 300])


def test_every_make_command_the_guide_names_is_a_target_of_the_makefile_it_means():
    """The guide's inline `make X ...` are this checkout's targets; `make check` is the student bundle's."""
    def targets(makefile: Path) -> set:
        return set(re.findall(r"^([a-z][\w-]*):", makefile.read_text(), re.M))

    ours, bundle = targets(REPO / "Makefile"), targets(REPO / "notebooks" / "bundle" / "Makefile")
    named = set(re.findall(r"`make ([a-z][\w-]*)", GUIDE.read_text()))
    named |= {shlex.split(c)[1] for c in guide_commands(GUIDE.read_text()) if c.startswith("make ")}
    assert named - ours == {"check"} and "check" in bundle, named - ours


def test_release_feedback_names_what_is_missing_in_one_line(tmp_path):
    course = tmp_path / "course"
    (course / "feedback").mkdir(parents=True)
    (course / "nbgrader_config.py").write_text(f"c = get_config()\nc.Exchange.root = {str(tmp_path / 'exchange')!r}\n")

    def release() -> str:
        proc = subprocess.run([sys.executable, "-m", "hri_teleop.apps.instructor", "release-feedback", str(course)],
                              capture_output=True, text=True, env=grader_env(), timeout=120)
        assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1, proc.stderr
        return proc.stderr

    assert "no feedback to release; run make grade" in release()
    (course / "feedback" / "ann" / ASSIGNMENT).mkdir(parents=True)
    assert f"exchange {tmp_path / 'exchange'} does not exist: create it" in release()
