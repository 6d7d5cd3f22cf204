"""Ex. 14 from trial to figure: a simulated study recorded through the lab's ROS nodes, analysed, plotted.

Two participants (AB/BA), one object (the egg), quick trials: four real recordings
(``teleoperation.launch sim:=true``: teleoperation, mapping_node, gripper_manager and
lab_sim; rosbag) on a *running* master that stands in for the lab PC's roscore, with a
node of "the lab" on it that must survive.  The first trial is recorded as a lab engineer
does it (``trial record --master-uri``), the other three by ``rehearse --resume`` on the
same master.  The simulated participants' seeds are chosen so that P01 squeezes 8 taps
without feedback (the egg cracks) and P02 7 taps (a gentle grasp), and both stop at the
rumble with feedback.

What the analysis says is checked against what the simulation knows, read from the
bags independently of the metrics code: lifted/crushed against lab_sim's ``~object``
status (and against the lock-step runner's prediction for the same scripts), the peak
FSR force in N against the simulated spring force between the fingers (5 % + 0.02 N: the
ADC's resolution and noise near 1.3 N), time to grasp against the first simulated
contact force (0.1 s: board and state topics at 100 Hz, receive-time jitter), time from
grasp to lift against the lock-step run (0.5 s: the node's tick clock under load).
Then the figure (a PNG with the four panels and both conditions' colours) and the
analysis notebook, executed headless on the recorded folder.
"""

from __future__ import annotations

import contextlib
import io
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np
import pytest
import yaml

from hri_teleop.apps.trial import main
from hri_teleop.core.attachment import Attachment
from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.experiment.analysis import StudyResult
from hri_teleop.core.run_record import LabRecord
from hri_teleop.plots.study import COLOURS, PANEL_TITLES
from hri_teleop.ros import master as master_module
from hri_teleop.ros.bags import read_topics
from hri_teleop.ros.master import PrivateMaster, RunningMaster
from hri_teleop.ros.trial import rehearse, trial_seed
from hri_teleop.sim.config import world_config_from_dict
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.lab import run_lab
from hri_teleop.sim.operators import squeeze_taps, study_operator, study_scenario
from hri_teleop.sim.virtual_pad import parse_script

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
NOTEBOOK = REPO / "notebooks" / "experiment" / "analysis.ipynb"
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
PARTICIPANTS = ["P01", "P02"]
#: What the lab's master holds as /max_sensor_force before the session (the simulated FSR's full travel
#: reads 700; one count more changes the newtons by 0.3 %, and shows the session's value was used).
SESSION_CALIBRATION = 701
#: (participant, trial) -> condition: P01 AB, P02 BA (hri_teleop.core.experiment.plan).
CONDITIONS = {("P01", 1): "feedback", ("P01", 2): "no_feedback", ("P02", 1): "no_feedback", ("P02", 2): "feedback"}


def _ros_env() -> dict:
    from conftest import _ros_env as env  # tests/conftest.py, on sys.path under pytest

    return env()


def _base_seed() -> int:
    """The first base seed whose no-feedback participants squeeze 8 taps (P01, trial 2) and 7 (P02, trial 1)."""
    for base in range(10_000):
        taps = [squeeze_taps(study_operator("no_feedback", trial_seed(base, i, n))) for i, n in ((0, 2), (1, 1))]
        if taps == [8, 7]:
            return base
    raise AssertionError("no seed gives the wanted participants")


def _predicted(scenario: Path, condition: str) -> LabRecord:
    """The lock-step runner's run of the same scenario: what the ROS run should reproduce."""
    data = yaml.safe_load(scenario.read_text())
    params = replace(CONFIG.params, feedback=(condition == "feedback"))
    return run_lab(parse_script(data["steps"]), world_config_from_dict(data["world"]), params, CONFIG.limits,
                   max_sensor_force=Attachment().full_travel_count)


@dataclass
class Study:
    folder: Path
    result: StudyResult
    predicted: Dict[Tuple[str, int], LabRecord]
    cli_code: int
    cli_out: str
    nodes_before: set
    nodes_after: set
    lab_node_alive: bool
    left_running: List[str]
    record_s: float
    analyse_s: float


@contextlib.contextmanager
def _lab_pc_priority():
    """The recording ahead of the suite's other workers for the CPU, as on the lab PC, where nothing else runs.

    The trials run in real time and the operator's script is timed: on a machine busy with the rest of the suite
    (load 17 on 2 cores in a full run) the lab's nodes were starved, the arm came down late and the hand closed
    above the egg (CI of this stop: P01's first trial not lifted; a lift 0.8 s late). Its processes inherit the
    priority; where it cannot be raised (not root) the study runs as before.
    """
    before = os.getpriority(os.PRIO_PROCESS, 0)
    try:
        os.setpriority(os.PRIO_PROCESS, 0, -10)
    except OSError:
        pass
    try:
        yield
    finally:
        try:
            os.setpriority(os.PRIO_PROCESS, 0, before)
        except OSError:
            pass


@pytest.fixture(scope="module")
def study(tmp_path_factory) -> Study:
    with _lab_pc_priority():
        yield from _record_study(tmp_path_factory)


def _record_study(tmp_path_factory):
    work = tmp_path_factory.mktemp("study")
    lab = PrivateMaster(base_env=_ros_env(), work_dir=work / "ros")  # stands in for the lab PC's roscore
    lab.start()
    try:
        lab_node = lab.run(["rostopic", "pub", "-r", "1", "/lab/status", "std_msgs/String", "data: lab PC",
                            "__name:=lab_monitor"], "lab_monitor")
        lab.wait_for(lambda: "/lab_monitor" in lab.node_names(), 30, "the lab's own node")
        lab.set_param("/max_sensor_force", SESSION_CALIBRATION)  # the calibration widget's, this morning
        before = lab.node_names()
        base = _base_seed()
        out = work / "trials"
        started = time.monotonic()
        # Trial 1 as the lab engineer records it, on the running master.
        scenario = work / "P01_t01.yaml"
        scenario.write_text(yaml.safe_dump(study_scenario("feedback", trial_seed(base, 0, 1), "egg", quick=True)))
        with pytest.MonkeyPatch.context() as mp, contextlib.redirect_stdout(io.StringIO()) as printed:
            for key in ("ROS_LOG_DIR", "ROS_HOME"):
                mp.setenv(key, lab.env[key])
            code = main(["record", "--participant", "P01", "--trial", "1", "--object", "egg", "--condition",
                         "feedback", "--sim", "--scenario", str(scenario), "--master-uri", lab.uri,
                         "--out", str(out), "--timeout", "60"])
        # The rest of the session: the rehearsal records what is missing, on the same master, then analyses.
        running = RunningMaster(lab.uri, base_env=lab.env).start()
        try:
            rehearse(PARTICIPANTS, ["egg"], out, seed=base, quick=True, resume=True, master=running, timeout_s=60,
                     progress=lambda m: print(m, flush=True), analyse=False)
        finally:
            running.stop()
        record_s = time.monotonic() - started
        from hri_teleop.ros.trial import analyse_folder

        started = time.monotonic()
        result = analyse_folder(out)
        analyse_s = time.monotonic() - started
        predicted = {("P01", 1): _predicted(scenario, "feedback")}
        for (p, n), condition in CONDITIONS.items():
            if (p, n) != ("P01", 1):
                predicted[p, n] = _predicted(out / "scenarios" / f"{p}_t{n:02d}.yaml", condition)
        after = lab.node_names()
        left = [" ".join(proc.argv) for proc in list(master_module.LIVE_PROCESSES)
                if proc not in lab.core_processes and proc is not lab_node]
        print(f"\nstudy: 4 trials recorded in {record_s:.1f} s, analysed in {analyse_s:.1f} s")
        yield Study(out, result, predicted, code, printed.getvalue(), before, after, lab_node.running, left,
                    record_s, analyse_s)
    finally:
        lab.stop()
        leftover = [" ".join(p.argv) for p in lab.started if p.anything_left]
        assert not leftover, f"still running after the study: {leftover}"


def _by_trial(study: Study):
    return {(t.meta.participant, t.meta.trial): (t, m) for t, m in zip(study.result.trials, study.result.metrics)}


def test_the_session_was_recorded_on_the_running_master_and_left_it_as_it_was(study):
    assert study.cli_code == 0, study.cli_out
    assert "P01 trial 1 (egg, feedback):" in study.cli_out and "lifted, intact" in study.cli_out
    assert study.nodes_after == study.nodes_before == {"/rosout", "/lab_monitor"}
    assert study.lab_node_alive and study.left_running == []
    assert sorted(p.name for p in study.folder.glob("*.bag")) == ["P01_t01.bag", "P01_t02.bag", "P02_t01.bag",
                                                                 "P02_t02.bag"]
    for t in study.result.trials:
        assert t.extra["master"].startswith("http://127.0.0.1:") and t.extra["sim"] is True
        assert t.extra["feedback_param"] is (t.meta.condition == "feedback")  # the condition reached the node
        assert t.extra["launch_args"]["feedback"] == str(t.meta.condition == "feedback").lower()
        assert t.extra["max_sensor_force"] == SESSION_CALIBRATION and t.extra["ended_by"] == "quit"
        assert t.extra["launch_args"]["max_sensor_force"] == str(SESSION_CALIBRATION)  # the session's value kept
    assert "operator" not in study.result.trials[0].extra  # recorded by hand, not by the rehearsal
    assert study.result.trials[1].extra["operator"]["kind"] == "study_operator"


def test_outcomes_agree_with_what_the_simulation_knows(study):
    for (p, n), (trial, m) in _by_trial(study).items():
        objects = read_topics(trial.sidecar.with_suffix(".bag"), ["/lab_sim/object"])["/lab_sim/object"]
        final = {kv.key: kv.value for kv in objects[-1][1].values}
        assert (m.lifted, m.crushed) == (final["lifted"] == "true", final["crushed"] == "true"), (p, n)
        expected = study.predicted[p, n]
        assert (m.lifted, m.crushed) == (expected.lifted, expected.crushed), \
            f"{p} trial {n}: the ROS run and the lock-step run of the same script disagree"
        assert m.success == (m.lifted and not m.crushed)
        if m.crushed:
            assert float(final["peak_grip_force_n"]) >= OBJECTS["egg"].breaking_force_n
    metrics = {(m.meta.participant, m.meta.trial): m for m in study.result.metrics}
    assert metrics["P01", 2].crushed and metrics["P02", 1].success  # 8 taps crack the egg, 7 hold it
    rates = study.result.rates()
    assert (rates["feedback"]["success_rate"], rates["feedback"]["crush_rate"]) == (1.0, 0.0)
    assert (rates["no_feedback"]["success_rate"], rates["no_feedback"]["crush_rate"]) == (0.5, 0.5)


def test_forces_and_times_agree_with_the_simulated_physics(study):
    full_travel_n = Attachment().full_travel_force_n
    for (p, n), (trial, m) in _by_trial(study).items():
        rec = trial.record
        if m.crushed:
            # The shell gives way within ~10 ms of the piston bottoming out and the force drops to 0: the
            # board (100 Hz) sees that transient at most once. Its peak lies between the force held before
            # the crushing tap and the piston's full travel.
            crush_s = max(rec.grip_force, key=lambda s: s[1])[0]
            held_n = max(v for t, v in rec.grip_force if t < crush_s - 0.03)
            assert held_n - 0.05 <= m.peak_force_n <= full_travel_n * 1.02, (p, n, held_n)
        else:
            spring_peak_n = max(v for _, v in rec.grip_force)  # below full travel, grip = spring = FSR
            assert m.peak_force_n == pytest.approx(spring_peak_n, rel=0.05, abs=0.02), (p, n)
        first_contact_s = next(t for t, v in rec.grip_force if v > 0.0) - rec.start_s()
        assert m.time_to_grasp_s == pytest.approx(first_contact_s, abs=0.1), (p, n)
        expected = study.predicted[p, n]
        if m.lifted:
            offline_lift = next(t for t, h in expected.object_height if h > 0.005)
            offline_grasp = next(t for t, c in expected.count if c > 7)
            assert m.time_to_lift_s - m.time_to_grasp_s == pytest.approx(offline_lift - offline_grasp, abs=0.5)
            assert 0 < m.time_to_grasp_s < m.time_to_lift_s < m.duration_s
        else:
            assert m.time_to_lift_s is None
        if m.meta.condition == "feedback":
            assert m.rumble_s > 0.5 and m.saturated_s == 0.0
        else:
            assert m.rumble_s == 0.0 and max(v for _, v in rec.rumble) == 0.0


def test_the_paired_comparison_sees_the_harder_squeeze_and_states_its_assumptions(study):
    c = study.result.peak_force
    assert c is not None and c.n_pairs == 2
    peak = {(m.meta.participant, m.meta.condition): m.peak_force_n for m in study.result.metrics}
    differences = [peak[p, "no_feedback"] - peak[p, "feedback"] for p in PARTICIPANTS]
    assert differences[0] > -0.05  # P01's crush read at least the force the rumble stopped the other grasp at
    assert c.median_difference == pytest.approx(sum(differences) / 2)  # no feedback minus feedback, per participant
    assert c.p_value >= 0.5  # two pairs can never be significant, and the exact test knows it
    assert c.n_nonzero == sum(d != 0 for d in differences) and -1.0 <= c.rank_biserial <= 1.0
    report = study.result.report()
    assert "Wilcoxon signed-rank, exact, two-sided" in report and "rank-biserial r = " in report
    assert "symmetric about their median" in report


def test_the_figure_is_a_png_with_the_four_panels_and_both_conditions(study):
    import matplotlib.image

    path = study.result.figure
    assert path == study.folder / "study.png" and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert study.result.figure_panels == PANEL_TITLES
    pixels = matplotlib.image.imread(str(path))
    assert pixels.shape[:2] == (800, 1100)
    from matplotlib.colors import to_rgb

    for condition, colour in COLOURS.items():
        near = np.all(np.abs(pixels[:, :, :3] - np.array(to_rgb(colour))) < 0.02, axis=2)
        assert near.sum() > 500, f"{condition}'s colour ({colour}) is hardly in the figure"
    assert (study.folder / "metrics.csv").read_text().count("\n") == 5


def test_the_analyse_command_prints_the_table_and_the_test(study, capsys):
    assert main(["analyse", str(study.folder), "--figure", str(study.folder / "again.png")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].split()[:4] == ["participant", "trial", "object", "condition"]
    assert "Wilcoxon signed-rank" in out and (study.folder / "again.png").exists()


def test_the_analysis_notebook_runs_on_the_recorded_folder(study, monkeypatch):
    import nbformat
    from nbclient import NotebookClient

    from hri_teleop.ros.kernel import KERNEL_NAME, install_kernelspec, ipc_kernel_config

    install_kernelspec()
    monkeypatch.setenv("HRI_TRIALS", str(study.folder))
    nb = nbformat.read(str(NOTEBOOK), as_version=4)
    assert all(not c.get("outputs") for c in nb.cells if c.cell_type == "code"), "commit the notebook without outputs"
    started = time.monotonic()
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=120, startup_timeout=120, kernel_name=KERNEL_NAME).execute()
    print(f"\nanalysis notebook: {time.monotonic() - started:.1f} s")
    cells = {c.get("id"): c for c in nb.cells}

    def text(cell_id: str) -> str:
        return "".join(o.get("text", "") for o in cells[cell_id].outputs if o.output_type == "stream")

    assert text("setup").strip() == str(study.folder)
    assert len(text("trials").splitlines()) == 4
    table = text("metrics").splitlines()
    assert table[0].split()[:4] == ["participant", "trial", "object", "condition"] and len(table) == 6
    assert any("image/png" in o.get("data", {}) for o in cells["figure"].outputs)
    assert "Wilcoxon signed-rank, exact" in text("comparison") and "assumptions:" in text("comparison")
    assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {}) for o in cells["tlx"].outputs)


def test_a_fresh_analysis_notebook_offers_a_rehearsal_and_says_in_one_line_what_is_missing(tmp_path, monkeypatch):
    import nbformat
    from nbclient import NotebookClient

    from hri_teleop.ros.kernel import KERNEL_NAME, install_kernelspec, ipc_kernel_config

    install_kernelspec()
    empty = tmp_path / "no_trials_yet"
    monkeypatch.setenv("HRI_TRIALS", str(empty))
    nb = nbformat.read(str(NOTEBOOK), as_version=4)
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=120, startup_timeout=120, kernel_name=KERNEL_NAME,
                       allow_errors=True).execute()
    cells = {c.get("id"): c for c in nb.cells}
    setup = cells["setup"].outputs
    assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {}) for o in setup), "no rehearsal offer"
    trials_text = "".join(o.get("text", "") for o in cells["trials"].outputs if o.output_type == "stream")
    assert trials_text.startswith(f"no trials in {empty} yet: press Rehearse")
    errors = [o for o in cells["metrics"].outputs if o.output_type == "error"]
    assert len(errors) == 1 and errors[0]["ename"] == "MetricsError"
    assert errors[0]["traceback"] == ["MetricsError: no trials to analyse; record some first "
                                      "(python -m hri_teleop.apps.trial rehearse)"]
