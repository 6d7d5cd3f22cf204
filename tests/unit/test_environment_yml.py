"""environment.yml (students' conda env) and pyproject.toml must not drift apart."""

from __future__ import annotations

import re
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[2]


def _pyproject_dependencies() -> list:
    try:
        import tomllib  # Python >= 3.11
    except ImportError:  # pragma: no cover - Python 3.8..3.10
        import tomli as tomllib  # type: ignore
    with open(REPO / "pyproject.toml", "rb") as fh:
        return list(tomllib.load(fh)["project"]["dependencies"])


def _conda_pip_dependencies() -> list:
    env = yaml.safe_load((REPO / "environment.yml").read_text())
    pip_sections = [d["pip"] for d in env["dependencies"] if isinstance(d, dict) and "pip" in d]
    assert len(pip_sections) == 1, "environment.yml needs exactly one pip: section"
    return [d for d in pip_sections[0] if not d.startswith("-")]


def _normalise(req: str) -> str:
    return re.sub(r"\s+", "", req).lower()


def test_conda_pip_dependencies_equal_pyproject_dependencies():
    assert sorted(map(_normalise, _conda_pip_dependencies())) == sorted(map(_normalise, _pyproject_dependencies()))


def test_conda_environment_brings_ros_noetic_from_robostack():
    env = yaml.safe_load((REPO / "environment.yml").read_text())
    assert env["channels"][0] == "robostack-noetic"  # RoboStack's Noetic channel (robostack-staging was its old name)
    names = [d for d in env["dependencies"] if isinstance(d, str)]
    assert "ros-noetic-ros-core" in names
