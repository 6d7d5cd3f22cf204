"""ruff finds nothing in the toolkit and its tests: the command `make lint` runs, with the rules
of pyproject.toml's [tool.ruff] (pyflakes, pycodestyle, import order, bugbear, blind excepts)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def _ruff(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run([str(Path(sys.executable).with_name("ruff")), "check", "--no-cache", *args],
                          cwd=cwd, capture_output=True, text=True)


def test_ruff_finds_nothing_in_the_toolkit_and_its_tests():
    proc = _ruff("hri_teleop", "tests")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_runs_with_the_projects_rules(tmp_path):
    """Guard against a configuration that checks nothing: a closure over a loop variable and an
    unused import fail."""
    (tmp_path / "pyproject.toml").write_text((REPO / "pyproject.toml").read_text())
    bad = tmp_path / "bad.py"
    bad.write_text("import os\n\nfns = []\nfor i in range(3):\n    fns.append(lambda: i)\n")
    proc = _ruff(str(bad), cwd=tmp_path)
    assert proc.returncode == 1 and "F401" in proc.stdout and "B023" in proc.stdout, proc.stdout
