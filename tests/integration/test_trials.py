"""Ex. 14's trial command: one simulated trial recorded with its metadata, then loaded and measured."""

from __future__ import annotations

import pytest
import yaml

from hri_teleop.apps.trial import main
from hri_teleop.core.attachment import Attachment
from hri_teleop.core.experiment.metrics import MetricsError, TrialMeta, trial_metrics
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master_api import running_nodes
from hri_teleop.ros.trial import METADATA_TOPIC, load_trials, record_trial
from hri_teleop.sim.operators import study_scenario

pytestmark = pytest.mark.ros


def test_a_no_feedback_trial_is_recorded_with_its_metadata_and_never_rumbles(tmp_path):
    scenario = tmp_path / "participant.yaml"
    scenario.write_text(yaml.safe_dump(study_scenario("no_feedback", 4, "egg", quick=True)))
    meta = TrialMeta("P07", "egg", "no_feedback", 3)
    bag, record = record_trial(meta, tmp_path / "trials", sim=True, scenario=scenario, timeout_s=60)
    assert bag.name == "P07_t03.bag" and record.ended_by == "quit"

    [trial] = load_trials(tmp_path / "trials")
    loaded, rec, rest = trial.meta, trial.record, trial.extra
    assert loaded == meta and rest["sim"] is True and rest["launch_args"]["feedback"] == "false"
    assert rest["master"] == "private" and rest["feedback_param"] is False and rest["max_sensor_force"] == 700
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
    assert main(["tlx", str(sidecar), "--mental", "40", "--physical", "10", "--temporal", "30", "--performance", "20",
                 "--effort", "45", "--frustration", "15"]) == 0
    data = yaml.safe_load(sidecar.read_text())
    assert data["tlx"]["raw_tlx"] == pytest.approx(160 / 6, abs=1e-4) and data["outcome"]["lifted"] is True
    assert "raw TLX 26.7" in capsys.readouterr().out
    assert main(["tlx", str(sidecar), "--mental", "42", "--physical", "10", "--temporal", "30", "--performance", "20",
                 "--effort", "45", "--frustration", "15"]) == 2
    assert "TLX mental is 42; rate 0..100 in steps of 5" in capsys.readouterr().err
    assert yaml.safe_load(sidecar.read_text())["tlx"]["mental"] == 40


def _record_args(tmp_path, *more):
    return ["record", "--participant", "P01", "--trial", "1", "--object", "egg", "--condition", "no_feedback",
            "--sim", "--out", str(tmp_path / "trials"), *more]


def test_recording_on_the_lab_master_without_one_running_says_how_to_start_it(tmp_path, capsys, monkeypatch):
    from hri_teleop.ros.master import free_port

    uri = f"http://127.0.0.1:{free_port()}/"
    assert main(_record_args(tmp_path, "--master-uri", uri)) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"trial: no ROS master is running at {uri}: start it with `roscore`")
    monkeypatch.delenv("ROS_MASTER_URI", raising=False)
    assert main(_record_args(tmp_path, "--lab")) == 1
    assert "ROS_MASTER_URI is not set" in capsys.readouterr().err
    assert main(_record_args(tmp_path, "--master-uri", "localhost:11311")) == 1
    assert "not of the form http://HOST:PORT/" in capsys.readouterr().err
    assert not (tmp_path / "trials").exists() or not list((tmp_path / "trials").iterdir())


@pytest.mark.parametrize("more", [["--sim"], ["--pad", "virtual"]])
def test_on_the_lab_master_a_simulated_or_scripted_trial_is_refused_before_anything_starts(foreign_roscore, tmp_path,
                                                                                         capsys, monkeypatch, more):
    monkeypatch.delenv("HRI_OWN_MASTER", raising=False)
    uri = foreign_roscore.uri
    before = running_nodes(uri=uri)
    args = [a for a in _record_args(tmp_path, "--master-uri", uri) if a != "--sim"] + more
    assert main(args) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("trial: refused to start trial P01 trial 1"), err
    assert "not started by this process" in err
    assert running_nodes(uri=uri) == before
    assert not (tmp_path / "trials").exists() or not list((tmp_path / "trials").glob("*.bag"))


def test_on_the_lab_master_a_running_teleoperation_is_refused_and_left_alone(ros_master, tmp_path, capsys,
                                                                            monkeypatch):
    """The condition is applied by launching teleoperation itself; a node of that name already there would be
    replaced (ROS kills the older one) or keep its own feedback setting, so the command stops before starting."""
    theirs = ros_master.run(["rostopic", "pub", "-r", "1", "/their/status", "std_msgs/String", "data: busy",
                             "__name:=teleoperation"], "their_teleoperation")
    ros_master.wait_for(lambda: "/teleoperation" in ros_master.node_names(), 30, "the running teleoperation")
    before = ros_master.node_names()
    for key in ("ROS_LOG_DIR", "ROS_HOME"):
        monkeypatch.setenv(key, ros_master.env[key])
    real_pad = [a for a in _record_args(tmp_path, "--master-uri", ros_master.uri) if a != "--sim"]
    assert main(real_pad + ["-a", "robot:=false"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert f"/teleoperation already running on {ros_master.uri}: stop that launch first" in err
    assert "feedback:=false" in err
    assert ros_master.node_names() == before and theirs.running
    assert not list((tmp_path / "trials").glob("*.bag*"))
    with pytest.raises(MetricsError, match="feedback:=true contradicts the condition no_feedback"):
        record_trial(TrialMeta("P01", "egg", "no_feedback", 1), tmp_path / "trials", launch_args={"feedback": "true"})
