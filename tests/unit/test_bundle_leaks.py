"""The student bundle's leak check (hri_teleop.course.bundle.bundle_leaks) on small bundles built here.

A solution line leaks as a whole line, and a distinctive one (long, code-like) also inside a longer
line: a grader hint's string that quotes the answer. Paths and commands the handout names do not.
"""

from __future__ import annotations

import json
from pathlib import Path

from hri_teleop.core.paths import NOTEBOOKS, SOLUTIONS
from hri_teleop.course.bundle import bundle_leaks, distinctive, solution_texts

#: A line of the answer key's mapping_node.py (inside its solution region).
ANSWER_LINE = 'self.publisher = rospy.Publisher("/force_mapped", Float32, queue_size=10)'


def _bundle(tmp_path: Path, files: dict) -> Path:
    root = tmp_path / "task4"
    for relative, text in files.items():
        (root / relative).parent.mkdir(parents=True, exist_ok=True)
        (root / relative).write_text(text, encoding="utf-8")
    return root


def test_the_answer_line_is_a_solution_line_of_the_answer_key():
    texts = solution_texts(SOLUTIONS, NOTEBOOKS)
    assert any(line.strip() == ANSWER_LINE for lines in texts.values() for line in lines)
    assert distinctive(ANSWER_LINE)


def test_a_solution_line_planted_in_a_string_literal_is_caught(tmp_path):
    hint = f"HINT = 'in __init__ write {ANSWER_LINE} and keep it'\n"
    bundle = _bundle(tmp_path, {"toolkit/hri_teleop/grading/hints.py": "from __future__ import annotations\n" + hint})
    leaks = bundle_leaks(bundle, solution_texts(SOLUTIONS, NOTEBOOKS))
    assert len(leaks) == 1 and "hints.py" in leaks[0] and "inside a longer line" in leaks[0] \
        and "mapping_node.py" in leaks[0], leaks


def test_a_solution_line_in_a_notebook_cell_string_is_caught(tmp_path):
    cell = {"cell_type": "code", "metadata": {}, "outputs": [], "execution_count": None,
            "source": [f"print('try: {ANSWER_LINE}')"]}
    notebook = json.dumps({"cells": [cell], "metadata": {}, "nbformat": 4, "nbformat_minor": 5})
    bundle = _bundle(tmp_path, {"lab/ex99.ipynb": notebook})
    leaks = bundle_leaks(bundle, {"answer": [ANSWER_LINE]})
    assert len(leaks) == 1 and "ex99.ipynb" in leaks[0], leaks


def test_a_whole_line_leak_is_reported_once(tmp_path):
    bundle = _bundle(tmp_path, {"preparation/hri_lab/scripts/mapping_node.py": f"        {ANSWER_LINE}\n"})
    leaks = bundle_leaks(bundle, {"answer": [ANSWER_LINE]})
    assert len(leaks) == 1 and "inside a longer line" not in leaks[0], leaks


def test_paths_commands_and_short_lines_inside_longer_lines_are_no_leak(tmp_path):
    texts = {"answer": ["scripts/teleoperation.py", "!rostopic type /pub_force", "rate = self.rate"]}
    readme = ("The files: `scripts/teleoperation.py`, then `!rostopic type /pub_force`; "
              "x_rate = self.rate_hz\n")
    assert not any(distinctive(line) for line in texts["answer"])
    assert bundle_leaks(_bundle(tmp_path, {"README.md": readme}), texts) == []


def test_an_installed_virtual_environment_is_not_scanned(tmp_path):
    site = "toolkit/.venv/lib/python3/site-packages/somepkg/module.py"
    bundle = _bundle(tmp_path, {site: f"EXAMPLE = '{ANSWER_LINE}'\n"})
    assert bundle_leaks(bundle, {"answer": [ANSWER_LINE]}) == []
