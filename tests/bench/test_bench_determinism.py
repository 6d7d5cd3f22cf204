"""Benchmark 6 (grading determinism): the wrong packages are wrong where they should be, and the
smoke run grades the answer key idle and loaded with the same part scores."""

from __future__ import annotations

import pytest

from benchmarks.determinism import WRONG_PACKAGES, package_variants, part_scores, run
from benchmarks.report import BenchOptions


def test_each_wrong_package_differs_from_the_answer_key_in_its_one_file(tmp_path):
    packages = package_variants(tmp_path)
    key = packages.pop("answer-key")
    assert sorted(packages) == sorted(WRONG_PACKAGES)
    for name, folder in packages.items():
        changed = [p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()
                   and p.read_bytes() != (key / p.relative_to(folder)).read_bytes()]
        assert changed == [WRONG_PACKAGES[name][0]], name
    assert "### BEGIN SOLUTION" not in (key / "scripts" / "mapping_node.py").read_text()


def test_part_scores_are_keyed_by_check_and_part():
    tests = [{"name": "mapping-node: clips", "score": 0.0}, {"name": "graph: format", "score": 1}]
    assert part_scores(tests) == {"mapping-node: clips": 0.0, "graph: format": 1.0}


@pytest.mark.ros
def test_the_smoke_run_gives_the_answer_key_the_same_scores_idle_and_loaded(tmp_path):
    messages = []
    [row] = run(BenchOptions(out_dir=tmp_path, smoke=True, jobs=2), messages.append)
    assert row.values == {"runs": 2.0, "packages": 1.0, "steady_packages": 1.0, "busy_cores": 2.0}
    assert row.ratio == 1.0 and "totals answer-key 22" in row.figure, row.figure
    assert any("loaded" in m for m in messages)
