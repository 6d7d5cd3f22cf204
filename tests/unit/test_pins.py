"""One set of exact versions per term: constraints.txt pins every dependency on Python 3.8 and 3.11,
and every path that installs the toolkit takes it (tools/setup.sh, which the bundle and Gradescope run)."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import tomllib
from packaging.markers import Marker
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

REPO = Path(__file__).resolve().parents[2]


def _pins_module():
    spec = importlib.util.spec_from_file_location("_tools_pins", REPO / "tools" / "pins.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


pins = _pins_module()


def test_a_version_installed_on_both_pythons_is_one_row_for_both():
    assert pins.merge({"3.11": {"pyyaml": "6.0.2"}, "3.8": {"pyyaml": "6.0.2"}}) == [
        'pyyaml==6.0.2; python_version == "3.8" or python_version == "3.11"']


def test_versions_that_differ_are_a_row_each():
    assert pins.merge({"3.11": {"numpy": "2.4.6"}, "3.8": {"numpy": "1.24.4"}}) == [
        'numpy==1.24.4; python_version == "3.8"', 'numpy==2.4.6; python_version == "3.11"']


def test_a_package_of_one_python_only_holds_there_only():
    assert pins.merge({"3.11": {"nbgrader": "0.9.6", "anyio": "4.16.0"}, "3.8": {}}) == [
        'anyio==4.16.0; python_version == "3.11"', 'nbgrader==0.9.6; python_version == "3.11"']


def test_the_freeze_keeps_exact_versions_only_by_their_canonical_names():
    text = ("Jupyter_Server==2.14.0\n-e git+https://example.org/x.git@abc#egg=x\nfoo @ file:///home/me/foo.whl\n"
            "# comment\nruamel.yaml==0.18.6\n")
    assert pins.parse_freeze(text) == {"jupyter-server": "2.14.0", "ruamel-yaml": "0.18.6"}


def _rows():
    rows = []
    for line in (REPO / "constraints.txt").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            requirement = Requirement(line)
            rows.append(requirement)
    return rows


def _dependencies():
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    lists = re.findall(r'^(?:dependencies|test) = \[\n(.*?)^\]', text, re.M | re.S)
    return [Requirement(item) for block in lists for item in re.findall(r'^\s+"((?:[^"\\]|\\.)*)",', block, re.M)
            for item in [item.replace('\\"', '"')]]


def test_every_dependency_is_pinned_once_on_each_python_it_installs_on():
    rows = _rows()
    for python in ("3.8", "3.11"):
        env = {"python_version": python, "python_full_version": python + ".0", "extra": ""}
        for dependency in _dependencies():
            if dependency.marker is not None and not dependency.marker.evaluate(env):
                continue
            name = canonicalize_name(dependency.name)
            held = [r for r in rows if canonicalize_name(r.name) == name and r.marker is not None and r.marker.evaluate(env)]
            assert len(held) == 1, (python, name, [str(r) for r in held])
            version = str(held[0].specifier).lstrip("=")
            assert dependency.specifier.contains(version, prereleases=True), (python, str(dependency), version)


def test_every_row_is_an_exact_version_for_a_named_python():
    for row in _rows():
        assert re.fullmatch(r"==[^,]+", str(row.specifier)), str(row)
        assert row.marker is not None and not Marker(str(row.marker)).evaluate({"python_version": "3.12"}), str(row)


def test_the_requirements_tool_reads_pyprojects_arrays_as_toml_does():
    spec = importlib.util.spec_from_file_location("_tools_requirements", REPO / "tools" / "requirements.py")
    assert spec is not None and spec.loader is not None
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    project = tomllib.loads(text)["project"]
    assert tool.array(text, "dependencies") == project["dependencies"]
    assert tool.array(text, "test") == project["optional-dependencies"]["test"]
    assert tool.array('test = [\n    "a>=1",  # why\n    # a comment\n    "b; python_version < \\"3.9\\"",\n]\n', "test") == \
        ["a>=1", 'b; python_version < "3.9"']


def test_every_install_of_the_toolkit_takes_the_constraints():
    setup = (REPO / "tools" / "setup.sh").read_text(encoding="utf-8")
    installs = [line for line in setup.splitlines() if "pip install" in line and ('-e "' in line or " -r " in line)]
    assert len(installs) == 2  # .venv (the project, editable) and .venv38 (the project's requirements)
    assert all('${pins[@]+"${pins[@]}"}' in line for line in installs), installs
    assert "pins=(-c constraints.txt)" in setup
    from hri_teleop.course.bundle import TOOLKIT_FILES
    from hri_teleop.grading.gradescope.build import SOURCE_PATHS

    assert "constraints.txt" in TOOLKIT_FILES and "constraints.txt" in SOURCE_PATHS
    gradescope = (REPO / "hri_teleop" / "grading" / "gradescope" / "files" / "setup.sh").read_text(encoding="utf-8")
    assert "bash tools/setup.sh" in gradescope
