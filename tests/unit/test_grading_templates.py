"""Student templates generated from solutions/ (hri_teleop.grading.cases.templates)."""

from __future__ import annotations

import ast
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml

from hri_teleop.grading.cases.templates import (
    TemplateError,
    generate_templates,
    has_markers,
    kind_of,
    make_answer,
    make_template,
)

REPO = Path(__file__).resolve().parents[2]
SOLUTIONS = REPO / "solutions" / "hri_lab"

PY = """def f(x):
    # add one
    ### BEGIN SOLUTION
    y = x + 1
    return y
    ### END SOLUTION

z = 1
"""


def test_a_python_region_becomes_a_hint_that_raises_at_the_markers_indentation():
    out = make_template(PY, "python")
    assert out == "def f(x):\n    # add one\n    # YOUR CODE HERE\n    raise NotImplementedError()\n\nz = 1\n"
    namespace: dict = {}
    exec(compile(out, "<template>", "exec"), namespace)
    with pytest.raises(NotImplementedError):
        namespace["f"](1)


def test_yaml_and_xml_regions_become_comments_of_their_language():
    assert make_template("a: 1\n### BEGIN SOLUTION\nb: 2\n### END SOLUTION\n", "yaml") == "a: 1\n# YOUR CODE HERE\n"
    xml = "<launch>\n  <!-- ### BEGIN SOLUTION -->\n  <node name='x'/>\n  <!-- ### END SOLUTION -->\n</launch>\n"
    assert make_template(xml, "xml") == "<launch>\n  <!-- YOUR CODE HERE -->\n</launch>\n"


def test_the_answer_keeps_the_code_and_drops_only_the_markers():
    assert make_answer(PY) == "def f(x):\n    # add one\n    y = x + 1\n    return y\n\nz = 1\n"


@pytest.mark.parametrize("text, words", [
    ("### BEGIN SOLUTION\nx = 1\n", "never closed"),
    ("x = 1\n### END SOLUTION\n", "without a BEGIN"),
    ("### BEGIN SOLUTION\n### BEGIN SOLUTION\n### END SOLUTION\n", "inside the region"),
    ("x = 1  ### BEGIN SOLUTION\n", "not alone on its line"),
])
def test_unbalanced_markers_name_the_line_and_the_fix(text, words):
    with pytest.raises(TemplateError, match=words) as info:
        make_template(text, "python", "f.py")
    assert re.search(r"f\.py:\d+:", str(info.value))


def test_unknown_file_types_are_refused():
    with pytest.raises(TemplateError, match="no template rule"):
        kind_of("notes.txt")
    assert kind_of("hri_lab/CMakeLists.txt") == "cmake"


def test_the_provided_scripts_of_the_answer_key_are_the_labs_own():
    for name in ("FSR_sensor.py", "gripper_manager.py", "teleoperation_subscriber_publisher.py"):
        copy, lab = SOLUTIONS / "scripts" / name, REPO / "hri_lab" / "scripts" / name
        assert not copy.is_symlink(), f"{copy}: a real file (catkin_install_python cannot install a link)"
        assert copy.read_bytes() == lab.read_bytes(), f"{copy} differs from {lab}: copy the lab's over it"


PROVIDED = {"scripts/FSR_sensor.py", "scripts/gripper_manager.py", "scripts/teleoperation_subscriber_publisher.py",
            "package.xml"}


def test_templates_of_the_answer_key_hold_no_solution_and_still_parse(tmp_path):
    out = tmp_path / "templates" / "hri_lab"
    written = generate_templates(SOLUTIONS, out, not_executable=("scripts/teleoperation.py",))
    names = {w.target.relative_to(out).as_posix() for w in written}
    assert names == {"config/robot_params.yaml", "scripts/mapping_node.py", "scripts/teleoperation.py",
                     "launch/sensor.launch", "launch/teleoperation.launch", "graph.yaml", "CMakeLists.txt"} | PROVIDED
    for item in written:
        text = item.target.read_text()
        if item.target.relative_to(out).as_posix() in PROVIDED:
            assert item.regions == 0 and text == item.source.read_text(), "provided files ship as they are"
            continue
        assert item.regions >= 1, f"{item.source} has no solution region"
        assert not has_markers(text), item.target
        solution = item.source.read_text()
        region_lines = _region_lines(solution)
        leaked = [line for line in region_lines if line.strip() and line.strip() in
                  {t.strip() for t in text.splitlines()} and len(line.strip()) > 12]
        assert not leaked, f"{item.target} still holds solution lines: {leaked}"
        if item.target.suffix == ".py":
            ast.parse(text)
            assert "raise NotImplementedError()" in text
            executable = bool(item.target.stat().st_mode & 0o111)
            assert executable == (item.target.name != "teleoperation.py"), "only not_executable scripts lose the bit"
        elif item.target.suffix == ".yaml":
            assert yaml.safe_load(text) is None  # only comments left
        elif item.target.name == "CMakeLists.txt":
            assert "  # YOUR CODE HERE\n  DESTINATION" in text
        else:
            ET.fromstring(text)


def _region_lines(text: str) -> list:
    lines, inside = [], False
    for line in text.splitlines():
        if "BEGIN SOLUTION" in line:
            inside = True
        elif "END SOLUTION" in line:
            inside = False
        elif inside:
            lines.append(line)
    return lines


def test_the_output_folder_is_replaced_and_never_inside_the_answer_key(tmp_path):
    out = tmp_path / "t"
    (out / "stale.txt").parent.mkdir(parents=True)
    (out / "stale.txt").write_text("old")
    generate_templates(SOLUTIONS, out)
    assert not (out / "stale.txt").exists()
    with pytest.raises(TemplateError, match="inside the answer key"):
        generate_templates(SOLUTIONS, SOLUTIONS / "build")


def test_solution_lines_are_what_the_regions_hold_in_every_comment_style():
    from hri_teleop.grading.cases.templates import solution_lines

    text = "\n".join(["keep", "    # BEGIN SOLUTION", "    a = 1", "    # END SOLUTION", "keep too",
                      "<!-- ### BEGIN SOLUTION -->", "<node/>", "<!-- ### END SOLUTION -->", "## BEGIN SOLUTION",
                      "b: 2", "## END SOLUTION", "after"])
    assert solution_lines(text) == ["    a = 1", "<node/>", "b: 2"]
    assert solution_lines("no markers here") == []
