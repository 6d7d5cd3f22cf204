"""Every command in hri_teleop/apps/ runs as ``python -m hri_teleop.apps.NAME``: a main() and the
guard that calls it (a module without the guard imports, does nothing and exits 0), and each is
listed in docs/commands.md."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
APPS = sorted(p for p in (REPO / "hri_teleop" / "apps").glob("*.py") if p.name != "__init__.py")


def _runs_main(path: Path) -> bool:
    tree = ast.parse(path.read_text())
    has_main = any(isinstance(n, ast.FunctionDef) and n.name == "main" for n in tree.body)
    guarded = any(isinstance(n, ast.If) and "__main__" in ast.unparse(n.test) and "main(" in ast.unparse(n)
                  for n in tree.body)
    return has_main and guarded


@pytest.mark.parametrize("path", APPS, ids=lambda p: p.stem)
def test_each_app_has_a_main_that_runs_as_a_module(path):
    assert _runs_main(path), f"{path.name}: define main() and end with `if __name__ == \"__main__\": sys.exit(main())`"


def test_a_module_without_the_guard_is_found(tmp_path):
    bare = tmp_path / "bare.py"
    bare.write_text("def main():\n    return 0\n")
    assert not _runs_main(bare)


def test_every_app_is_in_docs_commands():
    table = (REPO / "docs" / "commands.md").read_text()
    assert [p.stem for p in APPS if f"| `{p.stem}` |" not in table] == []


@pytest.mark.parametrize("name", ["course", "lab_twin"])
def test_python_m_answers_help(name):
    out = subprocess.run([sys.executable, "-m", f"hri_teleop.apps.{name}", "--help"], capture_output=True,
                         text=True, cwd=REPO, timeout=120)
    assert out.returncode == 0 and "usage:" in out.stdout, out.stdout + out.stderr
