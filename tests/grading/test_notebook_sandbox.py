"""make grade runs the students' notebooks in the kernel sandbox: what a hostile notebook tries is refused.

A minimal course (the preparation with Ex. 1 only, which runs no ROS) graded by the real make grade
path. Mallory hands in the answer key plus cells that write into the grader's home (the test's fake
HOME) and the machine's /tmp, read another student's folder and the gradebook, list the autograded
folder, connect to a TCP service this test listens with on 127.0.0.1, fork until the process limit,
fill the scratch folder, and sleep forever; Alice hands in the answer key. Then the same without
bubblewrap: make grade refuses, and grades with UNSANDBOXED=1, saying so first.
"""

from __future__ import annotations

import csv
import html
import json
import os
import shutil
import signal
import socket
import subprocess
import threading
import uuid
from pathlib import Path
from typing import Dict, List

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course

pytestmark = pytest.mark.ros

ASSIGNMENT = "preparation"
NOTEBOOK = "ex01_fsr_and_arduino"
#: The course's per-cell limit, short here: the cell that sleeps forever is cut off after it.
CELL_TIMEOUT_S = 30
FORKS = 4096  # the fork loop's own bound: far above the kernel's process limit


@pytest.fixture(scope="module")
def course(tmp_path_factory) -> Path:
    """The preparation with Ex. 1 only, generated; the per-cell limit CELL_TIMEOUT_S."""
    return nbgrader_course(tmp_path_factory.mktemp("sandboxcourse") / "course", ASSIGNMENT, [NOTEBOOK],
                           f"\nc.Execute.timeout = {CELL_TIMEOUT_S}\n")


def _answer_key(folder: Path) -> Path:
    from hri_teleop.grading.cases.templates import generate_answers

    folder.mkdir(parents=True)
    generate_answers(SOLUTIONS, folder / "hri_lab")
    return folder


def _hand_in(course: Path, student: str, extra: Dict[str, str], last: str = "") -> Path:
    """The answer key's notebook with the ``extra`` cells (name -> code) after its first answer, ``last`` at its end."""
    import nbformat

    folder = _answer_key(course / "submitted" / student / ASSIGNMENT)
    nb = nbformat.read(str(course / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"), as_version=4)
    first = next(i for i, c in enumerate(nb.cells) if c.metadata.get("nbgrader", {}).get("solution"))
    cells = [nbformat.v4.new_code_cell(f"# attack: {name}\n{code}") for name, code in extra.items()]
    if last:
        cells.append(nbformat.v4.new_code_cell(f"# attack: last\n{last}"))
    for cell in cells:
        cell.pop("id", None)  # the course's notebooks are nbformat 4.4, without cell ids
    nb.cells[first + 1:first + 1] = cells[:len(extra)]
    nb.cells.extend(cells[len(extra):])
    nbformat.write(nb, str(folder / f"{NOTEBOOK}.ipynb"))
    return folder


def _fresh_submissions(course: Path) -> None:
    for kind in ("submitted", "autograded", "feedback"):
        shutil.rmtree(course / kind, ignore_errors=True)


def _fake_home(tmp_path: Path) -> Path:
    """The grader's HOME for make grade; matplotlib's font list copied in (the kernel's box copies it in turn)."""
    home = tmp_path / "home"
    fonts = Path.home() / ".cache" / "matplotlib"
    if fonts.is_dir():
        shutil.copytree(fonts, home / ".cache" / "matplotlib")
    home.mkdir(exist_ok=True)
    return home


def _make_grade(submitted: Path, out: Path, env: Dict[str, str], timeout_s: float = 600, **variables: str):
    """`make -s -o setup grade DIR=... OUT=...`: (returncode, stdout lines, stderr)."""
    argv = ["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}", "CHECKS=robot-params",
            *[f"{k}={v}" for k, v in variables.items()]]
    proc = subprocess.Popen(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:  # a hang guard only: make and all it started
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
    return proc.returncode, stdout.splitlines(), stderr


def _autograded_points(course: Path) -> float:
    cells = json.loads((course / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb").read_text())["cells"]
    return sum(c["metadata"]["nbgrader"]["points"] for c in cells if c.get("metadata", {}).get("nbgrader", {})
               .get("grade") and not c["metadata"]["nbgrader"].get("solution"))


def _attack_outputs(course: Path, student: str) -> Dict[str, str]:
    """attack name -> what its cell printed and the error it ended with, from the autograded notebook."""
    nb = json.loads((course / "autograded" / student / ASSIGNMENT / f"{NOTEBOOK}.ipynb").read_text())
    found = {}
    for cell in nb["cells"]:
        source = "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
        if cell["cell_type"] == "code" and source.startswith("# attack: "):
            parts = []
            for out in cell.get("outputs", []):
                if out["output_type"] == "stream":
                    parts.append("".join(out["text"]) if isinstance(out["text"], list) else out["text"])
                elif out["output_type"] == "error":
                    parts.append(f"{out['ename']}: {out['evalue']}")
            found[source.split("\n", 1)[0][len("# attack: "):]] = "\n".join(parts)
    return found


def _scores(out: Path) -> Dict[str, Dict[str, str]]:
    with open(out / "grades.csv") as fh:
        return {row["student"]: row for row in csv.DictReader(fh)}


def _left_in(folder: Path) -> List[str]:
    """Live processes whose working folder is under ``folder`` (a kernel's is its notebook's)."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                cwd = os.readlink(f"/proc/{entry}/cwd")
                with open(f"/proc/{entry}/stat", "rb") as fh:
                    state = fh.read().rsplit(b")", 1)[1].split()[0]
            except OSError:
                continue
            if cwd.startswith(str(folder)) and state not in (b"Z", b"X"):
                found.append(f"{entry} in {cwd}")
    return found


class _Listener:
    """A TCP service on 127.0.0.1 (outside any sandbox) that records who connected."""

    def __init__(self) -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(8)
        self.port = self.sock.getsockname()[1]
        self.accepted: List[str] = []
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while True:
            try:
                conn, peer = self.sock.accept()
            except OSError:
                return
            self.accepted.append(f"{peer}")
            conn.close()

    def close(self) -> None:
        self.sock.close()
        self.thread.join(timeout=5)


def _attacks(course: Path, home: Path, machine_tmp: Path, port: int) -> Dict[str, str]:
    return {
        "home": f"open({str(home / 'owned')!r}, 'w').write('owned')",
        "machine-tmp": f"open({str(machine_tmp)!r}, 'w').write('owned')",
        "other-student": f"import os\nprint(sorted(os.listdir({str(course / 'submitted' / 'alice')!r})))",
        "autograded": f"import os\nprint('autograded:', sorted(os.listdir({str(course / 'autograded')!r})))",
        "gradebook": f"print(open({str(course / 'gradebook.db')!r}, 'rb').read(16))",
        "network": f"import socket\nsocket.create_connection(('127.0.0.1', {port}), timeout=10).close()\nprint('connected')",
        "fork-bomb": (
            "import os, signal, time\nchildren = []\ntry:\n"
            f"    for _ in range({FORKS}):\n"
            "        pid = os.fork()\n        if pid == 0:\n            time.sleep(120)\n            os._exit(0)\n"
            "        children.append(pid)\nfinally:\n    print(f'forked {len(children)}')\n"
            "    for pid in children:\n        os.kill(pid, signal.SIGKILL)\n"
            "    for pid in children:\n        os.waitpid(pid, 0)"),
        "memory": "held = bytearray(12 << 30)\nprint('held', len(held) >> 30, 'GB')",
        "cpu-bound": "import resource\nprint('cpu limit', resource.getrlimit(resource.RLIMIT_CPU))",
        "disk": ("import os\ntry:\n    with open('fill.bin', 'wb') as fh:\n        while True:\n"
                 "            fh.write(b'x' * (1 << 20))\nfinally:\n"
                 "    print('wrote', os.path.getsize('fill.bin') >> 20, 'MB')\n    os.remove('fill.bin')"),
    }


def test_a_hostile_notebook_is_refused_each_thing_and_honest_ones_keep_their_points(course, tmp_path):
    from hri_teleop.grading.run.kernel_sandbox import kernel_sandbox_problem

    if kernel_sandbox_problem():
        pytest.skip(f"the kernel sandbox cannot run here: {kernel_sandbox_problem()}")
    _fresh_submissions(course)
    home = _fake_home(tmp_path)
    machine_tmp = Path("/tmp") / f"hri-owned-{uuid.uuid4().hex}"
    listener = _Listener()
    try:
        _hand_in(course, "alice", {})
        _hand_in(course, "mallory", _attacks(course, home, machine_tmp, listener.port), "import time\nwhile True:\n"
                 "    time.sleep(1)")
        out = tmp_path / "grades"
        code, lines, stderr = _make_grade(course / "submitted", out, grader_env(HOME=str(home)), JOBS="2")
    finally:
        listener.close()
        leaked = machine_tmp.exists()
        if leaked:
            machine_tmp.unlink()
    text = "\n".join(lines) + "\n" + stderr
    print(text)
    assert code == 0, text
    assert not lines[0].startswith("UNSANDBOXED"), text

    # every attempt refused, or cut off, with the reason in the cell's output
    seen = _attack_outputs(course, "mallory")
    hidden = ("No such file or directory", "Read-only file system")  # not there, or there and read-only
    assert any(w in seen["home"] for w in hidden) and not (home / "owned").exists(), seen["home"]
    assert not leaked, seen["machine-tmp"]  # the kernel's /tmp is its own: the write stays in the box
    assert "FileNotFoundError" in seen["other-student"], seen["other-student"]
    assert "autograded: ['mallory']" in seen["autograded"], seen["autograded"]  # her own folder, nobody else's
    assert "FileNotFoundError" in seen["gradebook"], seen["gradebook"]
    assert "ConnectionRefusedError" in seen["network"] and listener.accepted == [], (seen["network"], listener.accepted)
    forked = int(seen["fork-bomb"].split("forked ", 1)[1].split()[0])
    assert "BlockingIOError" in seen["fork-bomb"] and 0 < forked < FORKS, seen["fork-bomb"]
    assert "No space left on device" in seen["disk"], seen["disk"]
    assert "MemoryError" in seen["memory"] and "held" not in seen["memory"], seen["memory"]
    from hri_teleop.grading.run.kernel_box import CPU_S
    assert f"cpu limit ({CPU_S}, {CPU_S + 5})" in seen["cpu-bound"], seen["cpu-bound"]  # a busy loop ends
    assert "CellTimeoutError" in seen["last"], seen["last"]
    feedback = (course / "feedback" / "mallory" / ASSIGNMENT / f"{NOTEBOOK}.html").read_text()
    for reason in ("No such file or directory", "ConnectionRefusedError", "BlockingIOError",
                   "No space left on device", "CellTimeoutError"):
        assert reason in feedback, reason  # what the student reads

    # graded as usual: the honest answers keep their points, in her notebook and in Alice's
    auto = _autograded_points(course)
    rows = _scores(out)
    assert rows["alice"]["status"] == rows["mallory"]["status"] == "graded", rows
    assert float(rows["alice"]["notebooks_score"]) == float(rows["mallory"]["notebooks_score"]) == auto, rows
    assert "UNSANDBOXED" not in (out / "report.html").read_text()
    assert _left_in(course) == []  # the kernels, their forks and their sleep are gone


def _no_bwrap(tmp_path: Path) -> Path:
    """A folder holding a `bwrap` that fails as it does where user namespaces are off."""
    bin_dir = tmp_path / "no-bwrap"
    bin_dir.mkdir()
    fake = bin_dir / "bwrap"
    fake.write_text("#!/bin/sh\necho 'bwrap: No permissions to create a new namespace' >&2\nexit 1\n")
    fake.chmod(0o755)
    return bin_dir


def test_without_bubblewrap_make_grade_refuses_unless_unsandboxed_and_then_says_so_first(course, tmp_path):
    _fresh_submissions(course)
    home = _fake_home(tmp_path)
    _hand_in(course, "carol", {"home": f"open({str(home / 'owned')!r}, 'w').write('owned')"})
    base = grader_env(HOME=str(home))
    env = dict(base, PATH=f"{_no_bwrap(tmp_path)}:{base['PATH']}")
    out = tmp_path / "grades"

    code, lines, stderr = _make_grade(course / "submitted", out, env, timeout_s=120)
    ours = [line for line in stderr.splitlines() if not line.startswith("make")]
    assert code != 0 and len(ours) == 1 and ours[0].startswith("hri-grade: bubblewrap cannot sandbox"), stderr
    assert "No permissions to create a new namespace" in ours[0] and "UNSANDBOXED=1" in ours[0], stderr
    assert not (out / "grades.csv").exists() and not (course / "autograded").exists()

    code, lines, stderr = _make_grade(course / "submitted", out, env, UNSANDBOXED="1")
    text = "\n".join(lines) + "\n" + stderr
    assert code == 0, text
    assert lines[0].startswith("UNSANDBOXED (make grade UNSANDBOXED=1): the students' notebooks and files run with "
                               "the grader's rights"), text
    report = (out / "report.html").read_text()
    body = html.unescape(report.split("<body>", 1)[1])
    assert body.startswith('<p style="border:2px solid #c00;padding:.5em"><strong>UNSANDBOXED: the code of 1 '
                           "student(s) ran with the grader's rights"), body[:300]
    assert float(_scores(out)["carol"]["notebooks_score"]) == _autograded_points(course)
    assert (home / "owned").read_text() == "owned"  # what the flag means: the notebook had the grader's rights


def test_a_folder_of_packages_is_refused_too_without_bubblewrap(tmp_path):
    """make grade on plain student folders (no notebooks) refuses the same way, before grading anything."""
    _answer_key(tmp_path / "submissions" / "dan")
    base = grader_env()
    env = dict(base, PATH=f"{_no_bwrap(tmp_path)}:{base['PATH']}")
    code, lines, stderr = _make_grade(tmp_path / "submissions", tmp_path / "grades", env, timeout_s=120)
    ours = [line for line in stderr.splitlines() if not line.startswith("make")]
    assert code != 0 and len(ours) == 1, stderr
    assert ours[0].startswith("hri-grade: bubblewrap cannot sandbox the students' files here"), stderr
    assert "UNSANDBOXED=1" in ours[0] and not (tmp_path / "grades" / "grades.csv").exists(), stderr
