"""Helpers shared by the grader's tests: the answer key, the corpus, and running hri-grade as a program."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Dict, List, Optional

import pytest
import yaml

REPO = Path(__file__).resolve().parents[2]
SOLUTIONS = REPO / "solutions" / "hri_lab"
CORPUS = Path(__file__).resolve().parent / "corpus"


def grader_env(**extra: str) -> Dict[str, str]:
    """tools/env.sh's environment (venv first on PATH, hri_lab findable) for hri-grade subprocesses."""
    env = dict(os.environ)
    venv_bin = str(REPO / ".venv" / "bin")
    if venv_bin not in env.get("PATH", "").split(":"):
        env["PATH"] = venv_bin + ":" + env.get("PATH", "")
    paths = [p for p in env.get("ROS_PACKAGE_PATH", "").split(":") if p]
    if str(REPO) not in paths:
        paths.insert(0, str(REPO))
    if not env.get("ROS_DISTRO") and "/usr/share" not in paths:
        paths.append("/usr/share")
    env["ROS_PACKAGE_PATH"] = ":".join(paths)
    env.update(extra)
    return env


def hri_grade(*args: str, timeout: float = 300, env: Optional[Dict[str, str]] = None) -> subprocess.CompletedProcess:
    """Run ``hri-grade ARGS`` (the installed console script) and capture its output."""
    exe = Path(sys.executable).with_name("hri-grade")
    if not exe.exists():
        pytest.fail("hri-grade is not installed: run 'make setup' (pyproject.toml [project.scripts])")
    return subprocess.run([str(exe), *args], capture_output=True, text=True, timeout=timeout,
                          env=env or grader_env(), stdin=subprocess.DEVNULL)


def answer_text(relative: str) -> str:
    """A file of the answer key with the solution markers dropped (what a good student hands in)."""
    from hri_teleop.grading.templates import make_answer

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


def part_keys(check: str) -> Dict[str, str]:
    """part name -> key of the check's table (robot-params: Table 1 keys and 'load')."""
    from hri_teleop.grading.checks import _table_for

    return {name: key for key, (name, _) in _table_for(check).items()}


def load_checks(out_dir: Path):
    from hri_teleop.grading.results import CheckResult

    return [CheckResult.from_dict(d) for d in json.loads((out_dir / "checks.json").read_text())]
