"""Ex. 14's trial command: one simulated trial recorded with its metadata, then loaded and measured."""

from __future__ import annotations

import pytest
import yaml

from hri_teleop.experiment.metrics import MetricsError, TrialMeta, trial_metrics
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.trial import METADATA_TOPIC, load_trials, main, record_trial
from hri_teleop.sim.hand import Attachment
from hri_teleop.sim.operators import script_to_yaml_data, study_operator

pytestmark = pytest.mark.ros


def test_a_no_feedback_trial_is_recorded_with_its_metadata_and_never_rumbles(tmp_path):
    scenario = tmp_path / "participant.yaml"
    scenario.write_text(yaml.safe_dump(script_to_yaml_data(study_operator("no_feedback", 4))))
    meta = TrialMeta("P07", "egg", "no_feedback", 3)
    bag, record = record_trial(meta, tmp_path / "trials", sim=True, scenario=scenario, timeout_s=60)
    assert bag.name == "P07_t03.bag" and record.ended_by == "quit"

    [(loaded, rec, rest)] = load_trials(tmp_path / "trials")
    assert loaded == meta and rest["sim"] is True and rest["launch_args"]["feedback"] == "false"
    inside = read_topics(bag, [METADATA_TOPIC])[METADATA_TOPIC]
    assert yaml.safe_load(inside[0][1].data)["participant"] == "P07"

    m = trial_metrics(rec, loaded, Attachment().full_travel_count)
    assert m.rumble_s == 0.0 and max(v for _, v in rec.rumble) == 0.0  # feedback off reached the node
    assert max(v for _, v in rec.mapped) > 0.5  # ... although the piston was pressed
    assert m.crushed == rec.crushed and m.lifted == rec.lifted and m.time_to_grasp_s > 0

    with pytest.raises(MetricsError, match="already recorded"):
        record_trial(meta, tmp_path / "trials", sim=True, scenario=scenario)


def test_plan_and_outcome_commands(tmp_path, capsys):
    assert main(["plan", "--participants", "P01", "P02", "--objects", "egg", "sponge", "--out",
                 str(tmp_path / "plan.csv")]) == 0
    assert len((tmp_path / "plan.csv").read_text().splitlines()) == 1 + 2 * 2 * 2
    sidecar = tmp_path / "P01_t01.yaml"
    sidecar.write_text(yaml.safe_dump({"participant": "P01", "object_name": "egg", "condition": "feedback",
                                       "trial": 1}))
    assert main(["outcome", str(sidecar), "--lifted", "yes", "--crushed", "no"]) == 0
    assert yaml.safe_load(sidecar.read_text())["outcome"] == {"lifted": True, "crushed": False}
