"""docs/architecture.md tells the truth: its layer plan is drawn from the imports (tools/architecture.py),
every file or folder it names exists, and its facade table lists exactly what the facade offers."""

from __future__ import annotations

import re

import pytest
from test_import_graph import ARCHITECTURE, REPO

import hri_teleop.course as course

DOC = REPO / "docs" / "architecture.md"


def test_the_layer_plan_on_the_page_is_the_one_the_imports_draw():
    _, block, _ = ARCHITECTURE.split_doc(DOC.read_text(encoding="utf-8"))
    assert block == ARCHITECTURE.render(ARCHITECTURE.import_graph()), "stale: run python tools/architecture.py"


def test_the_check_mode_fails_on_a_stale_page_and_writing_mends_it(tmp_path, monkeypatch, capsys):
    head, block, tail = ARCHITECTURE.split_doc(DOC.read_text(encoding="utf-8"))
    stale = tmp_path / "architecture.md"
    stale.write_text(f"{head}{ARCHITECTURE.BEGIN}\n{block.replace('core/', 'kernel/')}\n{ARCHITECTURE.END}{tail}")
    monkeypatch.setattr(ARCHITECTURE, "DOC", stale)
    assert ARCHITECTURE.main(["--check"]) == 1 and "stale" in capsys.readouterr().err
    assert ARCHITECTURE.main([]) == 0 and ARCHITECTURE.main(["--check"]) == 0
    assert stale.read_text() == DOC.read_text(encoding="utf-8")


@pytest.mark.parametrize("groups, expected", [
    ({"a": set(), "b": {"a"}, "c": {"a"}, "d": {"b", "c"}}, [["a"], ["b", "c"], ["d"]]),
    ({"cases": set(), "batch": {"cases", "points"}, "points": {"batch"}, "cli": {"batch"}},
     [["cases"], ["batch ~ points"], ["cli"]]),
    ({"x": {"y"}, "y": {"z"}, "z": {"x"}}, [["x ~ y ~ z"]]),
])
def test_levels_put_each_group_above_what_it_imports_and_a_circle_in_one_place(groups, expected):
    assert ARCHITECTURE.levels(groups) == expected


def _named_paths(text: str):
    """Backquoted words on the page that name a file or folder of the checkout."""
    for word in re.findall(r"`([^`\s]+)`", text):
        word = word.rstrip(",.:")
        if re.fullmatch(r"[\w./-]+\.(py|md|yaml|yml|launch|ipynb|sh)|[\w.-]+(/[\w.-]+)*/", word):
            yield word


def test_every_file_and_folder_the_page_names_exists():
    text = DOC.read_text(encoding="utf-8")
    roots = [REPO, REPO / "hri_teleop", REPO / "hri_teleop" / "grading", REPO / "docs", REPO / "hri_lab" / "scripts",
             REPO / "tests" / "unit"]  # a bare script or test name: where the page's sentence puts it
    missing = [word for word in _named_paths(text) if "*" not in word
               and not any((root / word).exists() for root in roots)]
    assert sorted(set(_named_paths(text))), "the page names no files: the scan is broken"
    assert missing == []


def test_the_facade_table_lists_what_the_facade_offers():
    text = DOC.read_text(encoding="utf-8")
    table = text.split("## The notebooks' facade", 1)[1].split("\n\n", 2)[2].split("\n\n", 1)[0]
    listed = {name for row in table.splitlines()[2:] for name in re.findall(r"`(\w+)`", row.split("|")[1])}
    assert listed == set(course.__all__)
