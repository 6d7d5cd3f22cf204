"""mypy finds nothing in the package, strictly: the command `make lint` runs, with pyproject.toml's [tool.mypy]."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

pytest.importorskip("mypy", reason="mypy no longer runs on Python 3.8")


def _mypy(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mypy", *args], cwd=cwd, capture_output=True, text=True)


def test_mypy_finds_nothing_in_the_package():
    proc = _mypy()
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert "Success" in proc.stdout


def test_mypy_runs_strictly_on_the_package(tmp_path):
    """Guard against a configuration that checks nothing: an untyped function, a wrong return type and
    an ignore that silences nothing fail."""
    (tmp_path / "pyproject.toml").write_text((REPO / "pyproject.toml").read_text())
    (tmp_path / "hri_teleop").mkdir()
    (tmp_path / "hri_teleop" / "__init__.py").write_text("")
    (tmp_path / "hri_teleop" / "bad.py").write_text(
        "def untyped(x):\n    return x\n\n\ndef wrong() -> int:\n    return 'a'\n\n\n"
        "def fine() -> int:\n    return 1  # type: ignore[return-value]\n")
    proc = _mypy("--cache-dir", str(tmp_path / ".cache"), cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout
    for code in ("no-untyped-def", "return-value", "unused-ignore"):
        assert code in proc.stdout, proc.stdout
