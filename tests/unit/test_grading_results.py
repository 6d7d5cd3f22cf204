"""Check results, the Gradescope JSON and the feedback text (hri_teleop.grading.results)."""

from __future__ import annotations

import json

from hri_teleop.grading.results import CheckResult, Part, feedback_text, gradescope_json, not_judged


def _result() -> CheckResult:
    return CheckResult("mapping-node", "scripts/mapping_node.py", [
        Part("subscribes /pub_force", 3, True),
        Part("values", 4, False, "expected 0.5, got 0", ("/tmp/p.png",)),
        not_judged("hidden", 5, "the node did not run"),
    ], seed=7)


def test_scores_count_passed_parts_only():
    result = _result()
    assert (result.score, result.max_score, result.passed) == (3, 12, False)
    assert [p.name for p in result.failed_parts] == ["values", "hidden"]
    assert CheckResult.from_dict(json.loads(json.dumps(result.to_dict()))) == result


def test_gradescope_json_has_one_test_per_part_and_the_total():
    payload = gradescope_json([_result()])
    assert payload["score"] == 3
    assert [t["status"] for t in payload["tests"]] == ["passed", "failed", "failed"]
    failed = payload["tests"][1]
    assert failed["name"] == "mapping-node: values" and failed["max_score"] == 4 and failed["score"] == 0
    assert "expected 0.5, got 0" in failed["output"] and "/tmp/p.png" in failed["output"]
    assert "not judged" in payload["tests"][2]["output"]
    json.dumps(payload)


def test_feedback_names_every_failed_part_its_message_and_the_seed():
    text = feedback_text([_result()])
    assert "[FAIL] values (0/4)" in text and "expected 0.5, got 0" in text
    assert "--seed 7" in text and text.endswith("total: 3/12")
