"""One license everywhere: the LICENSE text, pyproject.toml's license field and the ROS package's."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_the_license_file_is_bsd_3_clause_as_the_packages_declare():
    text = (REPO / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("BSD 3-Clause License\n")
    assert "3. Neither the name of the copyright holder" in text  # the third clause, not the 2-clause text
    pyproject = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    assert re.search(r'^license = \{text = "BSD-3-Clause"\}$', pyproject, re.M), "pyproject.toml: no BSD-3-Clause license"
    for package in (REPO / "hri_lab" / "package.xml", REPO / "solutions" / "hri_lab" / "package.xml"):
        assert re.findall(r"<license>(.*?)</license>", package.read_text(encoding="utf-8")) == ["BSD"], package


def test_the_students_toolkit_carries_the_license(tmp_path):
    from hri_teleop.course.bundle import build_toolkit

    toolkit = build_toolkit(tmp_path / "toolkit")
    assert (toolkit / "LICENSE").read_bytes() == (REPO / "LICENSE").read_bytes()
