"""A corpus of mistakes students really make: each fails the part it breaks, names it, and nothing else.

tests/grading/corpus/<entry>/expect.yaml holds one mistake as a change of the answer key, so
that the corpus follows solutions/hri_lab/ instead of drifting from a copy of it:

* ``check``: the check that grades it; ``node: false`` where it runs without a ROS node;
* ``file``: the answer-key file the student got wrong (its place in the handout's package);
* ``mutate``: ops applied in order to that file as make_answer gives it (the solution
  markers dropped): ``replace``/``with`` or ``delete_line`` (every line that contains the
  text), each of which must match exactly ``count`` times (default 1); or, only where no
  change of the answer key can express the mistake, the whole file as ``text``;
* ``unchanged``: further answer-key files the entry hands in as they are;
* ``fails``: for every part that must fail a phrase its message must contain. Every other
  part of that check must pass.

The entries are written to a temporary folder at test time. The ones that need ROS are
graded two at a time, longest first, each by its own `hri-grade submission` process (as
`make grade` does), while the quick ones are graded in this process meanwhile.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from grading_helpers import (
    CorpusError,
    answer_text,
    corpus_entries,
    corpus_files,
    expectation,
    hri_grade,
    load_checks,
    part_keys,
    write_corpus_entry,
)

from hri_teleop.grading import feedback_text, grade


def _quick(exp: dict) -> bool:
    """Graded in this process: no master needed (robot-params, or a check run with node: false)."""
    return exp["check"] == "robot-params" or exp.get("node") is False


@pytest.mark.parametrize("name", corpus_entries())
def test_the_mutation_still_applies_to_the_answer_key(name):
    corpus_files(name)  # CorpusError names the entry, the op and the text the answer key no longer has


@pytest.mark.parametrize("name", corpus_entries())
def test_the_mistake_changes_the_answer_key(name):
    relative = expectation(name)["file"]
    assert corpus_files(name)[relative] != answer_text(relative), f"{name}: {relative} is the answer key unchanged"


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """entry -> its CheckResult (or why it could not be written); ROS entries in parallel subprocesses."""
    submissions = tmp_path_factory.mktemp("corpus")
    out = tmp_path_factory.mktemp("corpus-out")
    results = {}
    written = []
    for name in corpus_entries():
        try:
            write_corpus_entry(name, submissions)
            written.append(name)
        except CorpusError as error:
            results[name] = str(error)

    def run(name: str):
        exp = expectation(name)
        proc = hri_grade("submission", str(submissions / name), "--checks", exp["check"], "--out", str(out / name))
        assert proc.returncode in (0, 1), f"{name}: hri-grade failed: {proc.stderr}"
        return name, load_checks(out / name)[0]

    slow = [n for n in written if not _quick(expectation(n))]
    slow.sort(key=lambda n: expectation(n)["check"] != "teleoperation-launch")  # the longest first
    with ThreadPoolExecutor(max_workers=2) as pool:
        running = pool.map(run, slow)
        for name in written:  # the quick ones while the pool runs ROS
            exp = expectation(name)
            if _quick(exp):
                kwargs = {"node": False} if exp.get("node") is False else {}
                results[name] = grade(exp["check"], submissions / name, out_dir=out / name, **kwargs)
        results.update(running)
    return results


@pytest.mark.ros
@pytest.mark.parametrize("name", corpus_entries())
def test_the_mistake_fails_exactly_its_parts_with_a_message_naming_it(graded, name):
    exp = expectation(name)
    result = graded[name]
    if isinstance(result, str):
        pytest.fail(result)
    keys = part_keys(exp["check"])
    failed = {keys[p.name]: p for p in result.parts if not p.passed and not p.message.startswith("not judged: the node was not run")}
    assert set(failed) == set(exp["fails"]), f"{name}: expected to fail {sorted(exp['fails'])}\n{feedback_text([result])}"
    for key, words in exp["fails"].items():
        assert words in failed[key].message, f"{name}: part {key} should mention {words!r}:\n{failed[key].message}"
    for part in failed.values():
        if "trace" in part.name or "hidden" in part.name or "maps" in part.name or "clips" in part.name:
            if not part.message.startswith("not judged"):
                assert part.plots and all(Path(p).is_file() for p in part.plots), f"{name}: no plot for {part.name}"
