"""Helpers shared by the grader's tests: the answer key, the corpus, and running hri-grade as a program."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path
from typing import Dict, List, Optional

import pytest
import yaml
from conftest import _ros_env  # tests/conftest.py, on sys.path under pytest

REPO = Path(__file__).resolve().parents[2]
SOLUTIONS = REPO / "solutions" / "hri_lab"
CORPUS = Path(__file__).resolve().parent / "corpus"


def grader_env(**extra: str) -> Dict[str, str]:
    """tools/env.sh's environment (tests/conftest.py's formula) plus ``extra``, for hri-grade subprocesses."""
    env = _ros_env()
    env.update(extra)
    return env


def hri_grade(*args: str, timeout: float = 300, env: Optional[Dict[str, str]] = None) -> subprocess.CompletedProcess:
    """Run ``hri-grade ARGS`` (the installed console script) and capture its output."""
    exe = Path(sys.executable).with_name("hri-grade")
    if not exe.exists():
        pytest.fail("hri-grade is not installed: run 'make setup' (pyproject.toml [project.scripts])")
    return subprocess.run([str(exe), *args], capture_output=True, text=True, timeout=timeout,
                          env=env or grader_env(), stdin=subprocess.DEVNULL)


def run_session(argv: List[str], cwd: Path, env: Dict[str, str], timeout: float = 600) -> subprocess.CompletedProcess:
    """``argv`` in a session of its own (everything it starts is killed if it hangs), its output printed and
    returned as stdout (stderr merged)."""
    proc = subprocess.Popen(argv, cwd=cwd, env=env, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
        pytest.fail(f"{' '.join(argv)}: still running after {timeout:.0f} s\n{out[-3000:]}")
    print(f"$ {' '.join(argv)}\n{out}")
    return subprocess.CompletedProcess(argv, proc.returncode, out, "")


def nbgrader(args: List[str], cwd: Path) -> None:
    """``nbgrader ARGS`` in the course folder ``cwd``; fails the test with its output when it fails."""
    proc = subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=str(cwd), capture_output=True, text=True,
                          env=grader_env(PYTHONWARNINGS="ignore"), timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]


def nbgrader_course(root: Path, assignment: str, notebooks: List[str], config_extra: str = "") -> Path:
    """A course like notebooks/ under ``root`` with ``notebooks`` of ``assignment`` (the answer key linked as in
    notebooks/source/) and ``config_extra`` after its nbgrader_config.py; the student version generated."""
    from hri_teleop.course.nodes import STUDENT_PACKAGE
    from hri_teleop.course.release import COURSE_DIR

    source = root / "source" / assignment
    source.mkdir(parents=True)
    (root / "nbgrader_config.py").write_text((COURSE_DIR / "nbgrader_config.py").read_text() + config_extra)
    for name in notebooks:
        shutil.copy(COURSE_DIR / "source" / assignment / f"{name}.ipynb", source)
    (source / STUDENT_PACKAGE).symlink_to(SOLUTIONS, target_is_directory=True)
    nbgrader(["generate_assignment", assignment, "--create", "--force"], root)
    return root


def answer_text(relative: str) -> str:
    """A file of the answer key with the solution markers dropped (what a good student hands in)."""
    from hri_teleop.grading.cases.templates import make_answer

    return make_answer((SOLUTIONS / relative).read_text())


def write_package(root: Path, files: Dict[str, str]) -> Path:
    for relative, text in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        if relative.endswith(".py"):
            path.chmod(0o755)
    return root


def corpus_entries() -> List[str]:
    return sorted(p.name for p in CORPUS.iterdir() if (p / "expect.yaml").is_file())


def expectation(name: str) -> dict:
    return yaml.safe_load((CORPUS / name / "expect.yaml").read_text())


class CorpusError(AssertionError):
    """An entry's expect.yaml no longer fits the answer key (one line: the entry, the op, what is missing)."""


def _mutate(entry: str, text: str, ops: List[dict]) -> str:
    """``text`` with expect.yaml's ``mutate`` ops applied in order; each must match exactly ``count`` times."""
    for index, op in enumerate(ops, 1):
        where = f"corpus entry {entry}, mutate op {index}"
        count = op.get("count", 1)
        if "replace" in op:
            old = op["replace"]
            found = text.count(old)
            if found != count:
                raise CorpusError(f"{where}: {old!r} occurs {found} times in the answer key, not {count}: "
                                  "update the op to the current solutions/hri_lab/ file")
            text = text.replace(old, op.get("with", ""))
        elif "delete_line" in op:
            lines = text.splitlines(keepends=True)
            keep = [line for line in lines if op["delete_line"] not in line]
            if len(lines) - len(keep) != count:
                raise CorpusError(f"{where}: {len(lines) - len(keep)} lines of the answer key contain "
                                  f"{op['delete_line']!r}, not {count}: "
                                  "update the op to the current solutions/hri_lab/ file")
            text = "".join(keep)
        else:
            raise CorpusError(f"{where}: unknown op {sorted(op)}: use replace/with/count or delete_line/count")
    return text


def corpus_files(name: str) -> Dict[str, str]:
    """The files of corpus entry ``name``: expect.yaml's ``file`` from the answer key with its ``mutate`` ops
    applied (or its whole ``text``), and its ``unchanged`` answer-key files as they are."""
    exp = expectation(name)
    relative = exp["file"]
    missing = [f for f in [relative, *exp.get("unchanged", [])] if not (SOLUTIONS / f).is_file()]
    if missing:
        raise CorpusError(f"corpus entry {name}: no {', '.join(missing)} in solutions/hri_lab/: update its expect.yaml")
    files = {other: answer_text(other) for other in exp.get("unchanged", [])}
    if "text" in exp:
        files[relative] = exp["text"]
    else:
        files[relative] = _mutate(f"{name} ({relative})", answer_text(relative), exp["mutate"])
    return files


def write_corpus_entry(name: str, root: Path) -> Path:
    """Corpus entry ``name`` written as a student's package at ``root / name``."""
    return write_package(root / name, corpus_files(name))


def part_keys(check: str) -> Dict[str, str]:
    """part name -> key of the check's table (robot-params: Table 1 keys and 'load')."""
    from hri_teleop.grading.exercises.registry import exercise

    return {name: key for key, (name, _) in exercise(check).parts.items()}


def load_checks(out_dir: Path):
    from hri_teleop.grading.results import CheckResult

    return [CheckResult.from_dict(d) for d in json.loads((out_dir / "checks.json").read_text())]


def open_folder(prefix: str):
    """A fresh folder every uid can enter (pytest's own tmp_path is private to root), removed afterwards.

    A generator for a fixture: ``yield from open_folder("hri-...")``. The sandboxed student
    uid must reach its folder and read world-readable files, like the instructor's.
    """
    import shutil
    import tempfile

    path = Path(tempfile.mkdtemp(prefix=prefix))
    path.chmod(0o755)
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)



def busy_cores(n: int = 2):
    """One spinning process per core while the block runs: the loaded machine (make bench's own)."""
    from benchmarks.determinism import BusyCores

    return BusyCores(n)
