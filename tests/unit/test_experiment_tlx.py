"""Raw NASA-TLX scoring and the trial sidecar it is stored in (atomic, other keys kept, one-line errors)."""

from __future__ import annotations

import os

import pytest
import yaml

from hri_teleop.core.experiment.metrics import MetricsError, TrialMeta
from hri_teleop.core.experiment.sidecar import (
    meta_from_sidecar,
    read_sidecar,
    sidecar_data,
    update_sidecar,
    write_sidecar,
)
from hri_teleop.core.experiment.tlx import (
    SUBSCALE_KEYS,
    TlxError,
    TlxRatings,
    optional_tlx,
    store_tlx,
    tlx_from_dict,
)

ANSWERS = {"mental": 40, "physical": 10, "temporal": 30, "performance": 20, "effort": 45, "frustration": 15}


def _sidecar(tmp_path, **extra):
    path = tmp_path / "P01_t03.yaml"
    write_sidecar(path, sidecar_data(TrialMeta("P01", "egg", "no_feedback", 3),
                                     {"sim": True, "max_sensor_force": 700, **extra}))
    return path


def test_the_raw_tlx_score_is_the_mean_of_the_six_ratings():
    ratings = TlxRatings(**ANSWERS)
    assert ratings.raw_tlx == pytest.approx(160 / 6)
    assert TlxRatings(**dict.fromkeys(SUBSCALE_KEYS, 100)).raw_tlx == 100.0
    assert TlxRatings(**dict.fromkeys(SUBSCALE_KEYS, 0)).raw_tlx == 0.0
    assert ratings.to_dict() == {**ANSWERS, "raw_tlx": round(160 / 6, 4)}
    assert SUBSCALE_KEYS == ("mental", "physical", "temporal", "performance", "effort", "frustration")


@pytest.mark.parametrize("bad, match", [(-5, "0..100"), (105, "0..100"), (42, "steps of 5"), (True, "number"),
                                        ("40", "number"), (float("nan"), "number"), (None, "number")])
def test_a_rating_off_the_scale_is_refused_naming_the_subscale(bad, match):
    with pytest.raises(TlxError, match=f"effort.*{match}"):
        TlxRatings(**{**ANSWERS, "effort": bad})


def test_ratings_read_back_from_a_sidecar_mapping_recompute_the_score():
    ratings = tlx_from_dict({**ANSWERS, "raw_tlx": 99.0}, "x.yaml")  # a hand-edited score is ignored
    assert ratings == TlxRatings(**ANSWERS) and ratings.raw_tlx == pytest.approx(160 / 6)
    assert ratings.mental == 40 and isinstance(TlxRatings(**{**ANSWERS, "mental": 40.0}).mental, int)


@pytest.mark.parametrize("data, match", [
    ({k: v for k, v in ANSWERS.items() if k != "temporal"}, "lacks temporal"),
    ({**ANSWERS, "mentl": 40}, "unknown key.*mentl"),
    ([40, 10], "mapping"),
    ({**ANSWERS, "physical": 7}, "x.yaml: TLX physical"),
])
def test_a_malformed_questionnaire_names_the_file_and_the_problem(data, match):
    with pytest.raises(TlxError, match=match):
        tlx_from_dict(data, "x.yaml")


def test_storing_the_answers_keeps_every_other_key_and_leaves_no_temporary_file(tmp_path):
    path = _sidecar(tmp_path, outcome={"lifted": True, "crushed": False}, launch_args={"feedback": "false"})
    before = read_sidecar(path)
    store_tlx(path, TlxRatings(**ANSWERS))
    after = read_sidecar(path)
    assert {k: v for k, v in after.items() if k != "tlx"} == before
    assert list(after)[:4] == ["participant", "object_name", "condition", "trial"]  # order kept
    assert optional_tlx(after, str(path)) == TlxRatings(**ANSWERS)
    store_tlx(path, TlxRatings(**{**ANSWERS, "mental": 90}))  # answering again replaces
    assert read_sidecar(path)["tlx"]["mental"] == 90
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P01_t03.yaml"]


def test_a_failed_write_leaves_the_old_sidecar_whole(tmp_path, monkeypatch):
    path = _sidecar(tmp_path)
    before = path.read_text()

    def full_disk(*_args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", full_disk)
    with pytest.raises(MetricsError, match=r"P01_t03.yaml: cannot write \(No space left on device\)"):
        store_tlx(path, TlxRatings(**ANSWERS))
    assert path.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P01_t03.yaml"]


def test_sidecar_errors_name_the_file_and_the_fix(tmp_path):
    broken = tmp_path / "P02_t01.yaml"
    broken.write_text("participant: P02\ncondition: [feedback\n")
    with pytest.raises(MetricsError, match=r"P02_t01.yaml:\d+: .*fix the YAML syntax"):
        read_sidecar(broken)
    empty = tmp_path / "P02_t02.yaml"
    empty.write_text("")
    with pytest.raises(MetricsError, match="P02_t02.yaml: not a trial's sidecar .it is empty"):
        read_sidecar(empty)
    with pytest.raises(MetricsError, match="trial sidecar not found: .*P09_t01.yaml"):
        store_tlx(tmp_path / "P09_t01.yaml", TlxRatings(**ANSWERS))
    assert not (tmp_path / "P09_t01.yaml").exists()
    other = tmp_path / "notes.yaml"
    other.write_text("todo: buy eggs\n")
    with pytest.raises(MetricsError, match="notes.yaml: not a trial's metadata .no participant"):
        update_sidecar(other, {"tlx": ANSWERS})
    assert yaml.safe_load(other.read_text()) == {"todo": "buy eggs"}
    with pytest.raises(MetricsError, match="x.yaml: not a trial's metadata"):
        meta_from_sidecar({"participant": "P01", "object_name": "egg", "condition": "fb", "trial": 1}, "x.yaml")


def _message(call, *args) -> str:
    with pytest.raises(MetricsError) as info:
        call(*args)
    return str(info.value)


def test_a_missing_sidecar_or_one_whose_top_level_is_not_a_mapping_is_named_with_the_fix(tmp_path):
    missing = tmp_path / "P09_t01.yaml"
    assert _message(read_sidecar, missing) == (f"trial sidecar not found: {missing}; give the .yaml written beside the "
                                               "trial's .bag (e.g. trials/P01_t01.yaml)")
    listed = tmp_path / "P02_t03.yaml"
    listed.write_text("- participant\n- P02\n")
    assert _message(read_sidecar, listed) == (f"{listed}: not a trial's sidecar (the top level is a list, not a "
                                              "mapping); restore it from the recording's /trial/metadata or record "
                                              "the trial again")
    empty = tmp_path / "P02_t02.yaml"
    empty.write_text("")
    assert _message(read_sidecar, empty) == (f"{empty}: not a trial's sidecar (it is empty); restore it from the "
                                             "recording's /trial/metadata or record the trial again")


def test_the_metadata_is_read_as_text_and_a_whole_trial_number():
    meta = meta_from_sidecar({"participant": 7, "object_name": 3, "condition": "feedback", "trial": "4",
                              "sim": True}, "x.yaml")
    assert meta == TrialMeta("7", "3", "feedback", 4)
    assert meta_from_sidecar({"participant": "P01", "object_name": "egg", "condition": "no_feedback", "trial": 2.0},
                             "x.yaml").trial == 2


@pytest.mark.parametrize("key", ["participant", "object_name", "condition", "trial"])
def test_metadata_without_one_of_its_four_keys_names_that_key(key):
    data = {"participant": "P01", "object_name": "egg", "condition": "feedback", "trial": 1}
    del data[key]
    assert _message(meta_from_sidecar, data, "x.yaml") == (f"x.yaml: not a trial's metadata (no {key}); it needs "
                                                           "participant, object_name, condition, trial")


@pytest.mark.parametrize("change, cause", [
    ({"condition": "fb"}, "condition must be one of feedback, no_feedback, got 'fb'"),
    ({"trial": "three"}, "invalid literal for int() with base 10: 'three'"),
    ({"participant": " "}, "participant code is empty; use a pseudonym such as P01"),
])
def test_metadata_with_a_wrong_value_says_what_trial_and_condition_must_be(change, cause):
    data = {"participant": "P01", "object_name": "egg", "condition": "feedback", "trial": 1, **change}
    assert _message(meta_from_sidecar, data, "x.yaml") == (f"x.yaml: not a trial's metadata ({cause}); trial must be "
                                                           "a number, condition feedback or no_feedback")
    with pytest.raises(MetricsError, match=r"^x.yaml: not a trial's metadata \(int\(\) argument must be .*\); trial"):
        meta_from_sidecar({**data, "condition": "feedback", "participant": "P01", "trial": None}, "x.yaml")


def test_a_new_sidecar_is_written_metadata_first_in_the_order_given(tmp_path):
    data = sidecar_data(TrialMeta("P01", "egg", "no_feedback", 3), {"sim": True, "max_sensor_force": 700})
    assert list(data.items()) == [("participant", "P01"), ("object_name", "egg"), ("condition", "no_feedback"),
                                  ("trial", 3), ("sim", True), ("max_sensor_force", 700)]
    path = write_sidecar(tmp_path / "P01_t03.yaml", {"zeta": 1, **data})
    assert path == tmp_path / "P01_t03.yaml"
    assert path.read_text() == ("zeta: 1\nparticipant: P01\nobject_name: egg\ncondition: no_feedback\ntrial: 3\n"
                                "sim: true\nmax_sensor_force: 700\n")


def test_updating_a_sidecar_returns_and_writes_the_old_keys_with_the_new_values(tmp_path):
    path = _sidecar(tmp_path, outcome=None)
    data = update_sidecar(path, {"outcome": {"lifted": True, "crushed": False}, "note": "shell cracked late"})
    assert data == {"participant": "P01", "object_name": "egg", "condition": "no_feedback", "trial": 3, "sim": True,
                    "max_sensor_force": 700, "outcome": {"lifted": True, "crushed": False},
                    "note": "shell cracked late"}
    assert read_sidecar(path) == data and list(read_sidecar(path)) == list(data)
    stored = store_tlx(path, TlxRatings(**ANSWERS))
    assert stored == {**data, "tlx": {**ANSWERS, "raw_tlx": 26.6667}} and read_sidecar(path) == stored


def test_a_sidecar_in_a_missing_folder_cannot_be_written_and_says_where(tmp_path):
    path = tmp_path / "gone" / "P01_t01.yaml"
    assert _message(write_sidecar, path, {"participant": "P01"}) == (
        f"{path}: cannot write (No such file or directory); check that {path.parent} exists, is writable and has "
        "free space")


def test_each_rating_from_0_to_100_in_steps_of_5_is_taken_and_anything_else_refused():
    for value in (0, 5, 95, 100, 50.0):
        assert TlxRatings(**{**ANSWERS, "mental": value}).mental == int(value)
    assert type(TlxRatings(**{**ANSWERS, "mental": 50.0}).mental) is int
    for value in (-5, -0.5, 0.5, 4, 6, 99, 100.5, 101, 105):
        with pytest.raises(TlxError) as info:
            TlxRatings(**{**ANSWERS, "mental": value})
        assert str(info.value) == f"TLX mental is {value!r}; rate 0..100 in steps of 5 (0, 5, ..., 100)"


@pytest.mark.parametrize("value", [True, False, "40", None, float("nan"), [40]])
def test_a_rating_that_is_not_a_number_says_the_scale(value):
    with pytest.raises(TlxError) as info:
        tlx_from_dict({**ANSWERS, "effort": value}, "P01_t03.yaml")
    assert str(info.value) == f"P01_t03.yaml: TLX effort must be a number 0..100 in steps of 5, got {value!r}"


def test_the_score_is_the_mean_of_six_ratings_stored_to_4_decimals():
    ratings = TlxRatings(mental=5, physical=0, temporal=0, performance=0, effort=0, frustration=0)
    assert ratings.raw_tlx == 5 / 6 and ratings.to_dict()["raw_tlx"] == 0.8333
    mixed = TlxRatings(mental=100, physical=0, temporal=5, performance=10, effort=15, frustration=20)
    assert mixed.raw_tlx == 25.0
    assert list(mixed.to_dict()) == ["mental", "physical", "temporal", "performance", "effort", "frustration",
                                     "raw_tlx"]


@pytest.mark.parametrize("data, message", [
    ([40, 10], "x.yaml: tlx must be a mapping of the six ratings (mental, physical, temporal, performance, effort, "
               "frustration), got [40, 10]"),
    ({**ANSWERS, "mentl": 40, "0": 1}, "x.yaml: tlx has unknown key(s) 0, mentl; the subscales are mental, "
                                       "physical, temporal, performance, effort, frustration"),
    ({**ANSWERS, "mentl": 40, 0: 1, True: 5}, "x.yaml: tlx has unknown key(s) 0, True, mentl; the subscales are "
                                              "mental, physical, temporal, performance, effort, frustration"),
    ({"mental": 40, "effort": 10}, "x.yaml: tlx lacks physical, temporal, performance, frustration; rate all six "
                                   "subscales (0..100 in steps of 5)"),
])
def test_a_malformed_questionnaire_is_one_line_with_the_fix(data, message):
    with pytest.raises(TlxError) as info:
        tlx_from_dict(data, "x.yaml")
    assert str(info.value) == message


def test_without_a_source_the_messages_start_with_the_problem():
    with pytest.raises(TlxError) as info:
        tlx_from_dict({"mental": 40})
    assert str(info.value).startswith("tlx lacks physical")
    with pytest.raises(TlxError) as info:
        tlx_from_dict({**ANSWERS, "mental": 41})
    assert str(info.value) == "TLX mental is 41; rate 0..100 in steps of 5 (0, 5, ..., 100)"
    with pytest.raises(TlxError) as info:
        optional_tlx({"tlx": {**ANSWERS, "mental": 41}})
    assert str(info.value) == "TLX mental is 41; rate 0..100 in steps of 5 (0, 5, ..., 100)"


def test_no_questionnaire_is_none_and_one_is_read_with_its_source():
    assert optional_tlx({"sim": True}, "P01_t03.yaml") is None
    assert optional_tlx({"tlx": None}, "P01_t03.yaml") is None
    assert optional_tlx({"tlx": ANSWERS}, "P01_t03.yaml") == TlxRatings(**ANSWERS)
    with pytest.raises(TlxError) as info:
        optional_tlx({"tlx": {**ANSWERS, "mental": 41}}, "P01_t03.yaml")
    assert str(info.value).startswith("P01_t03.yaml: TLX mental is 41")
