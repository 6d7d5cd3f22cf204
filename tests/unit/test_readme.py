"""The README's first screen: the two commands, a page per role, and the demo's picture; its
performance table is one current run (earlier runs live in docs/benchmarks.md)."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
README = (REPO / "README.md").read_text(encoding="utf-8")
FIRST_SCREEN = "\n".join(README.splitlines()[:40])


def test_the_first_screen_has_the_two_commands_and_a_page_for_each_role():
    assert "make demo" in FIRST_SCREEN and "make test" in FIRST_SCREEN
    for role, page in (("Students", "notebooks/bundle/README.md"), ("Instructors", "docs/instructors.md"),
                       ("Lab engineers", "docs/lab-day.md")):
        line = next((line for line in FIRST_SCREEN.splitlines() if line.startswith(f"- **{role}**")), "")
        assert page in FIRST_SCREEN[FIRST_SCREEN.index(line):], (role, page)
        assert (REPO / page).is_file(), page


def test_the_demos_timeline_picture_is_shown_and_is_a_png():
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", README)
    assert "docs/img/teleop_demo.png" in pictures
    assert (REPO / "docs" / "img" / "teleop_demo.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_performance_table_is_one_run_and_the_history_is_in_the_benchmarks_page():
    performance = README[README.index("## Performance"):README.index("## Other commands")]
    assert performance.count("Machine:") == 1
    assert "| benchmark | figure | reference (same run) | ratio | machine |" in performance
    assert "## Earlier runs" in (REPO / "docs" / "benchmarks.md").read_text(encoding="utf-8")
