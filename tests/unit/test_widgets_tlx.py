"""TlxWidget: six sliders on the raw TLX scale, saved into the chosen trial's sidecar."""

from __future__ import annotations

import os
import time

import pytest

from hri_teleop.core.experiment.metrics import TrialMeta
from hri_teleop.core.experiment.sidecar import read_sidecar, sidecar_data, write_sidecar
from hri_teleop.core.experiment.tlx import SUBSCALE_KEYS, TlxRatings
from hri_teleop.course.widgets._base import WidgetError
from hri_teleop.course.widgets.tlx import TlxWidget, trial_sidecars

ANSWERS = {"mental": 40, "physical": 10, "temporal": 30, "performance": 20, "effort": 45, "frustration": 15}


def _trial(folder, participant, number, age_s=0.0, **extra):
    path = folder / f"{participant}_t{number:02d}.yaml"
    write_sidecar(path, sidecar_data(TrialMeta(participant, "egg", "feedback", number),
                                     {"sim": True, "max_sensor_force": 700, **extra}))
    (folder / f"{participant}_t{number:02d}.bag").write_bytes(b"")
    stamp = time.time() - age_s
    os.utime(path, (stamp, stamp))
    return path


def test_the_sliders_are_the_raw_tlx_scale_and_the_score_follows_them(tmp_path):
    widget = TlxWidget(_trial(tmp_path, "P01", 1))
    assert list(widget.sliders) == list(SUBSCALE_KEYS)
    for slider in widget.sliders.values():
        assert (slider.min, slider.max, slider.step, slider.value) == (0, 100, 5, 50)
    widget.set_ratings(**ANSWERS)
    assert widget.ratings() == TlxRatings(**ANSWERS)
    assert "raw TLX 26.7" in widget.score.value
    with pytest.raises(WidgetError, match="unknown TLX subscale.*mentl"):
        widget.set_ratings(mentl=10)


def test_saving_writes_the_answers_into_the_sidecar_and_keeps_the_rest(tmp_path):
    path = _trial(tmp_path, "P01", 1, outcome={"lifted": True, "crushed": False})
    widget = TlxWidget(path)
    widget.set_ratings(**ANSWERS)
    widget.save_button.click()
    data = read_sidecar(path)
    assert data["tlx"] == {**ANSWERS, "raw_tlx": round(160 / 6, 4)}
    assert data["outcome"] == {"lifted": True, "crushed": False} and data["max_sensor_force"] == 700
    assert "saved to" in widget.status.value and "26.7" in widget.status.value
    again = TlxWidget(path)  # a stored trial shows its answers
    assert again.ratings() == TlxRatings(**ANSWERS) and "rated (raw TLX 26.7)" in again.status.value


def test_from_a_folder_the_newest_unrated_trial_is_chosen(tmp_path):
    _trial(tmp_path, "P01", 1, age_s=30)
    _trial(tmp_path, "P01", 2, age_s=20)
    _trial(tmp_path, "P02", 1, age_s=10, tlx=ANSWERS)
    (tmp_path / "plan.yaml").write_text("not: a trial\n")  # no bag beside it: not offered
    assert [p.name for p in trial_sidecars(tmp_path)] == ["P01_t01.yaml", "P01_t02.yaml", "P02_t01.yaml"]
    widget = TlxWidget(folder=tmp_path)
    assert widget.path.name == "P01_t02.yaml" and widget.ratings().mental == 50
    widget.trial.value = str(tmp_path / "P02_t01.yaml")  # choosing a rated trial shows its answers
    assert widget.ratings() == TlxRatings(**ANSWERS)
    _trial(tmp_path, "P02", 2)
    widget.refresh_button.click()
    assert widget.path.name == "P02_t02.yaml"


def test_bad_input_is_one_line_in_the_status(tmp_path):
    broken = tmp_path / "P01_t01.yaml"
    broken.write_text("participant: [P01\n")
    widget = TlxWidget(broken)
    assert "P01_t01.yaml:" in widget.status.value and "fix the YAML syntax" in widget.status.value
    widget.save_button.click()
    assert "color:#b00020" in widget.status.value and broken.read_text() == "participant: [P01\n"
    empty = TlxWidget(folder=tmp_path / "none")
    assert "no such folder of trials" in empty.status.value
    with pytest.raises(WidgetError, match="give the trial's sidecar"):
        TlxWidget()
