"""The pre-commit hooks run what they say: the notebook hook strips a notebook's outputs, and the
ruff and mypy hooks are `make lint`'s commands; all from the project's .venv (local hooks, no download)."""

from __future__ import annotations

import json
import shlex
import subprocess
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[2]


def _hooks():
    config = yaml.safe_load((REPO / ".pre-commit-config.yaml").read_text())
    return {hook["id"]: hook for repo in config["repos"] for hook in repo["hooks"]}


def test_every_hook_is_local_and_its_command_exists():
    config = yaml.safe_load((REPO / ".pre-commit-config.yaml").read_text())
    assert [repo["repo"] for repo in config["repos"]] == ["local"]
    for hook in _hooks().values():
        assert hook["language"] == "system"
        assert (REPO / shlex.split(hook["entry"])[0]).is_file(), hook["entry"]


def test_the_notebook_hook_strips_outputs_and_execution_counts(tmp_path):
    source = next((REPO / "notebooks" / "source" / "preparation").glob("*.ipynb"))
    notebook = json.loads(source.read_text())
    code = next(cell for cell in notebook["cells"] if cell["cell_type"] == "code")
    code["outputs"] = [{"output_type": "stream", "name": "stdout", "text": ["an answer\n"]}]
    code["execution_count"] = 7
    dirty = tmp_path / source.name
    dirty.write_text(json.dumps(notebook))
    hook = _hooks()["strip-notebook-outputs"]
    subprocess.run([*shlex.split(hook["entry"]), str(dirty)], cwd=REPO, check=True, capture_output=True)
    cleaned = json.loads(dirty.read_text())
    assert all(c.get("outputs", []) == [] and c.get("execution_count") is None
               for c in cleaned["cells"] if c["cell_type"] == "code")
    assert "an answer" not in dirty.read_text()


def test_the_ruff_and_mypy_hooks_are_make_lints_commands():
    makefile = (REPO / "Makefile").read_text()
    assert _hooks()["ruff"]["entry"] == ".venv/bin/ruff check"
    assert "ruff check ." in makefile
    assert _hooks()["mypy"]["entry"] == ".venv/bin/python -m mypy" and _hooks()["mypy"]["pass_filenames"] is False
    assert "$(PY) -m mypy" in makefile
