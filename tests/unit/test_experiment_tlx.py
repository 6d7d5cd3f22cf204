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
