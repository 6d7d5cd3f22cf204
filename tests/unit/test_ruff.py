"""ruff finds nothing in the checkout (package, tests, benchmarks, lab scripts, notebooks): the command
`make lint` runs, with the rules of pyproject.toml's [tool.ruff]."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def _ruff(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run([str(Path(sys.executable).with_name("ruff")), "check", "--no-cache", *args],
                          cwd=cwd, capture_output=True, text=True)


def test_ruff_finds_nothing_in_the_checkout():
    proc = _ruff(".")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_runs_with_the_projects_rules(tmp_path):
    """Guard against a configuration that checks nothing: a closure over a loop variable, an unused
    import, an import hidden in a function and a noqa that silences nothing fail."""
    (tmp_path / "pyproject.toml").write_text((REPO / "pyproject.toml").read_text())
    bad = tmp_path / "bad.py"
    bad.write_text("import os\n\nfns = []\nfor i in range(3):\n    fns.append(lambda: i)\n\n\n"
                   "def f():\n    import json\n\n    return json.dumps(1)  # noqa: E501\n")
    proc = _ruff(str(bad), cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout
    for rule in ("F401", "B023", "PLC0415", "RUF100"):
        assert rule in proc.stdout, proc.stdout


def test_a_test_may_import_inside_a_case(tmp_path):
    (tmp_path / "pyproject.toml").write_text((REPO / "pyproject.toml").read_text())
    (tmp_path / "tests").mkdir()
    case = tmp_path / "tests" / "test_x.py"
    case.write_text("def test_x():\n    import json\n\n    assert json.dumps(1) == '1'\n")
    proc = _ruff(str(case.relative_to(tmp_path)), cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout
