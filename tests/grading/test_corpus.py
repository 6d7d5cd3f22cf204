"""A corpus of mistakes students really make: each fails the part it breaks, names it, and nothing else.

tests/grading/corpus/<entry>/ holds a student's file(s) at the handout's place and
expect.yaml: the check, and for every part that must fail a phrase its message must
contain. Every other part of that check must pass. The entries that need ROS are graded
two at a time, each by its own `hri-grade submission` process (as `make grade` does).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from hri_teleop.grading import feedback_text, grade

from grading_helpers import CORPUS, corpus_entries, expectation, hri_grade, load_checks, part_keys

pytestmark = pytest.mark.ros

_IN_PROCESS = ("robot-params", "teleoperation-launch", "teleoperation")  # quick: no master needed (node=False)


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """entry -> its CheckResult; ROS entries graded in parallel subprocesses, the rest in-process."""
    out = tmp_path_factory.mktemp("corpus")
    entries = corpus_entries()
    results = {}

    def run(name: str):
        exp = expectation(name)
        proc = hri_grade("submission", str(CORPUS / name), "--checks", exp["check"], "--out", str(out / name))
        assert proc.returncode in (0, 1), f"{name}: hri-grade failed: {proc.stderr}"
        return name, load_checks(out / name)[0]

    slow = [n for n in entries if expectation(n)["check"] not in _IN_PROCESS]
    with ThreadPoolExecutor(max_workers=2) as pool:
        for name, result in pool.map(run, slow):
            results[name] = result
    for name in entries:
        if name not in results:
            exp = expectation(name)
            kwargs = {"node": False} if exp["check"] == "teleoperation" else {}
            results[name] = grade(exp["check"], CORPUS / name, out_dir=out / name, **kwargs)
    return results


@pytest.mark.parametrize("name", corpus_entries())
def test_the_mistake_fails_exactly_its_parts_with_a_message_naming_it(graded, name):
    exp = expectation(name)
    result = graded[name]
    keys = part_keys(exp["check"])
    failed = {keys[p.name]: p for p in result.parts if not p.passed and not p.message.startswith("not judged: the node was not run")}
    assert set(failed) == set(exp["fails"]), f"{name}: expected to fail {sorted(exp['fails'])}\n{feedback_text([result])}"
    for key, words in exp["fails"].items():
        assert words in failed[key].message, f"{name}: part {key} should mention {words!r}:\n{failed[key].message}"
    for part in failed.values():
        if "trace" in part.name or "hidden" in part.name or "maps" in part.name or "clips" in part.name:
            if not part.message.startswith("not judged"):
                assert part.plots and all(Path(p).is_file() for p in part.plots), f"{name}: no plot for {part.name}"
