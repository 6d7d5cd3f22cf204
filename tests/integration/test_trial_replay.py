"""A recorded trial keeps the arm's joints: its bag's /joint_states replay in the 3D view, the hand where it went.

One quick simulated trial (``record_trial``: teleoperation.launch sim:=true on a private roscore,
rosbag); lab_sim publishes ``/joint_states`` at 30 Hz as franka_ros does. The bag must hold every
arm joint by name for the whole trial, and the analysis notebook's ``widgets.ArmView().replay(trials)``
must draw the hand where the simulation's own twist says it went.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from hri_teleop.core.experiment.metrics import TrialMeta
from hri_teleop.course.widgets.arm3d import ArmView, read_joint_states
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.trial import load_trials, record_trial
from hri_teleop.sim.operators import study_scenario

pytestmark = pytest.mark.ros


def test_a_recorded_trial_holds_the_arms_joints_and_the_view_replays_them(tmp_path):
    scenario = tmp_path / "participant.yaml"
    scenario.write_text(yaml.safe_dump(study_scenario("feedback", 4, "egg", quick=True)))
    bag, record = record_trial(TrialMeta("P01", "egg", "feedback", 1), tmp_path / "trials", sim=True,
                               scenario=scenario, timeout_s=60)
    times, q, missing = read_joint_states(bag)
    assert missing == ()
    # the joints from the trial's start to its end (at lab_sim's state_controller_rate_hz: how many is its speed)
    assert len(times) > 1 and times[-1] > 0.8 * record.duration_s(), (len(times), times[-1])
    assert np.ptp(q[:, :7], axis=0).max() > 0.05, "the arm's joints never moved in the trial"

    # Where the hand went, independently: lab_sim's end-effector twist, integrated over the trial.
    twists = read_topics(bag, ["/lab_sim/ee_twist"])["/lab_sim/ee_twist"]
    stamps = np.array([m.header.stamp.to_sec() for _, m in twists])
    velocity = np.array([[m.twist.linear.x, m.twist.linear.y, m.twist.linear.z] for _, m in twists])
    travelled = (velocity[:-1] * np.diff(stamps)[:, None]).sum(axis=0)

    [trial] = load_trials(tmp_path / "trials")
    view = ArmView().replay([trial])
    try:
        assert view.drawn and f"{len(times)} joint states" in view.status.value, view.status.value
        start = np.array(view.hand_position_m())
        view.slider.value = view.slider.max
        end = np.array(view.hand_position_m())
        assert np.linalg.norm(end - start) > 0.01
        np.testing.assert_allclose(end - start, travelled, atol=0.01)
    finally:
        view.close()
