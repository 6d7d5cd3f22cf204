"""The checks: find the student's file, run it where it cannot hurt, compare, give points.

One function per handout deliverable, each returning a :class:`~hri_teleop.grading.results.CheckResult`;
``grade_submission`` runs them all. They serve ``hri-grade``, ``make grade`` and the notebooks'
autograded cells (``check_*`` raise AssertionError with the feedback). Running is delegated to
probes and sessions in sandboxes, judging to :mod:`~hri_teleop.grading.judge.compare`.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

import yaml

from hri_teleop.core.config import ConfigError, load_teleop_config
from hri_teleop.core.gamepad.events import pad_events
from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.core.teleop import TeleopParams
from hri_teleop.grading.cases import inputs as C
from hri_teleop.grading.cases.templates import TemplateError, kind_of, make_template
from hri_teleop.grading.judge import compare
from hri_teleop.grading.judge.compare_common import STUDENT_PACKAGES
from hri_teleop.grading.judge.compare_mapping import TEMPLATE_NOTE
from hri_teleop.grading.judge.compare_teleop_node import real_time_note
from hri_teleop.grading.judge.graph import grade_graph, live_graph
from hri_teleop.grading.judge.harness import (
    TWIST_TOPIC,
    CheckRun,
    closing_scratch,
    finish_check,
    grading_clock,
    parse_launch,
    refuse_reference,
    require_ros,
    reusable,
    start_check,
)
from hri_teleop.grading.judge.package_check import grade_catkin_package
from hri_teleop.grading.judge.robot_params import compare_robot_params
from hri_teleop.grading.judge.tracebacks import is_template
from hri_teleop.grading.results import CheckResult, GradingError, feedback_text, not_judged
from hri_teleop.grading.run.jobs import run_all
from hri_teleop.grading.run.records import (
    ClockedObservation,
    LaunchParseResult,
    MappingCasePlan,
    MappingNodePlan,
    PartsPlanCase,
    PartsPlanTick,
    RosparamResult,
    SensorLaunchObservation,
    SensorLaunchPlan,
    TeleopLaunchSimObservation,
    TeleopLaunchSimPlan,
    TeleopNodePlan,
    TeleopPartsPlan,
    TeleopPartsResult,
)
from hri_teleop.grading.run.standins import BOARD_TOPIC
from hri_teleop.grading.run.untrusted_files import read_regular
from hri_teleop.grading.run.workspace import (
    DELIVERABLES,
    REPO,
    find_package_root,
)
from hri_teleop.sim.sensor_profile import FSR_SENSOR_RATE_HZ

__all__ = [
    "CHECKS", "grade", "grade_robot_params", "grade_mapping_node", "grade_sensor_launch", "grade_teleoperation",
    "grade_teleoperation_launch", "grade_graph", "grade_submission", "default_check_jobs", "live_graph",
    "check_robot_params", "check_mapping_node", "check_sensor_launch", "check_teleoperation",
    "check_teleoperation_launch", "check_graph",
]

PathLike = Union[str, Path]


# -- the checks --------------------------------------------------------------------------------

@reusable("robot-params")
@closing_scratch
def grade_robot_params(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 4: Table 1's keys, YAML types and values; loaded with rosparam's own loader."""
    run, seed = start_check("robot-params", path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    target = run.space.file("robot_params")
    data, facts = run.probe("rosparam-load", target, "rosparam-load", RosparamResult)
    if data is None:
        parts = compare_robot_params(None, compare.explain_process(facts, "loading robot_params.yaml"))
    elif not data.ok:
        parts = compare_robot_params(None, f"`rosparam load` fails: {data.error}")
    else:
        parts = compare_robot_params(data.params)
    return finish_check("robot-params", run, parts, None)


@reusable("mapping-node")
@closing_scratch
def grade_mapping_node(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                       reference_allowed: bool = False) -> CheckResult:
    """Ex. 5: the node for real on a private master: topics, type, every value, the range from the parameter.

    ``reference_allowed``: judge a file that uses the lab's reference rule too (the lab's own
    node, when the grader's agreement with it is tested); students' files never are.
    """
    require_ros()
    run, seed = start_check("mapping-node", path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    run.space.guarded = not reference_allowed  # the lab's own node imports the rule it is the reference of
    refused = None if reference_allowed else refuse_reference(run, "mapping-node", compare.MAPPING, seed)
    if refused is not None:
        return refused
    cases = [C.public_mapping_case()] + C.hidden_mapping_cases(seed)
    plan = MappingNodePlan(script=str(run.space.file("mapping_node")),
                           cases=[MappingCasePlan(c.label, c.max_sensor_force, list(c.counts)) for c in cases],
                           start_timeout_s=10.0, response_timeout_s=1.5)
    observation = run.session(plan, timeout_s=120.0)
    parts = compare.compare_mapping(observation, cases, run.out_dir, str(run.space.package),
                                    _left_as_template(run, "mapping_node"))
    return finish_check("mapping-node", run, parts, seed)


def _left_as_template(run: CheckRun, key: str, submission: Optional[Path] = None) -> bool:
    """The student's deliverable is still the template handed out (every part YOUR CODE HERE unfilled): its
    workspace copy, or with ``submission`` (the package's folder) the file handed in (the lab's may stand in)."""
    target = run.space.originals.get(key) if submission is not None else run.space.files.get(key)
    solution = SOLUTIONS / DELIVERABLES[key]
    try:
        root = submission if submission is not None else run.space.package
        text = read_regular(target, root=root).decode("utf-8") if target is not None else ""
        template = make_template(solution.read_text(encoding="utf-8"), kind_of(solution)) if solution.is_file() else ""
    except (OSError, UnicodeDecodeError, TemplateError):  # UntrustedFileError is an OSError
        return False
    return is_template(text, template)


@reusable("sensor-launch")
@closing_scratch
def grade_sensor_launch(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 6-7: parsed with roslaunch's loader, then launched: /force_mapped flows and stays in [0, 1]."""
    require_ros()
    run, seed = start_check("sensor-launch", path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    parsed, facts = parse_launch(run, "sensor_launch")
    observation: Optional[SensorLaunchObservation] = None
    if parsed.ok:
        scripts = {n.type for n in parsed.nodes if n.package in STUDENT_PACKAGES}  # another package's: supplied
        param_ok, _ = compare.check_max_param(parsed.params)
        package = run.space.package
        run_mapping = "mapping_node.py" not in scripts and (package / "scripts" / "mapping_node.py").is_file()
        plan = SensorLaunchPlan(
            launch_file=str(run.space.file("sensor_launch")),
            set_max_sensor_force=None if param_ok else C.PUBLIC_MAX_SENSOR_FORCE,
            run_fsr_sensor="FSR_sensor.py" not in scripts, fsr_sensor=str(package / "scripts" / "FSR_sensor.py"),
            run_mapping_node=run_mapping, mapping_node=str(package / "scripts" / "mapping_node.py"),
            start_timeout_s=15.0, record_s=3.0, record_messages=10, clock=grading_clock(), settle_timeout_s=10.0,
            fsr_node=next((n.full_name for n in parsed.nodes if n.type == "FSR_sensor.py"), "/FSR_sensor"),
            default_fsr_rate_hz=FSR_SENSOR_RATE_HZ,
            mapping_node_name=next((n.full_name for n in parsed.nodes if n.type == "mapping_node.py"), "/mapping_node"),
            expect_nodes=sorted({n.full_name for n in parsed.nodes}
                                | ({"/FSR_sensor"} if "FSR_sensor.py" not in scripts else set())
                                | ({"/mapping_node"} if run_mapping else set())))
        observation = run.session(plan, timeout_s=90.0)
    parts = compare.compare_sensor_launch(parsed, observation, facts)
    notes = _clock_notes(observation, "sensor.launch: ")
    return finish_check("sensor-launch", run, parts, None, notes)


@reusable("teleoperation")
@closing_scratch
def grade_teleoperation(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                        node: bool = True) -> CheckResult:
    """Ex. 8-9: the student's parts against pad-event traces, then the node with the virtual pad."""
    require_ros()
    run, seed = start_check("teleoperation", path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    refused = refuse_reference(run, "teleoperation", compare.TELEOP, seed)
    if refused is not None:
        return refused
    cases = [C.public_teleop_parts_case(), C.hidden_teleop_parts_case(seed)]
    notes: List[str] = []
    plan_cases = []
    for case in cases:
        ticks, previous = [], None
        for tick in case.ticks:
            state = tick.state()
            ticks.append(PartsPlanTick(pad_events(previous, state), tick.force))
            previous = state
        plan_cases.append(PartsPlanCase(case.label, case.gains, ticks))
    plan_path = run.space.grader_dir / "teleop-parts.plan.json"
    plan_path.write_text(json.dumps(TeleopPartsPlan(plan_cases).to_json()), encoding="utf-8")
    if run.uid is not None:
        os.chown(plan_path, run.uid, run.uid)
    data, facts = run.probe("teleop-parts", run.space.file("teleoperation"), "teleop-parts", TeleopPartsResult,
                            plan_path)
    parts = compare.compare_teleop_parts(data or TeleopPartsResult(), cases, run.out_dir, facts)
    node_keys = [k for k in compare.TELEOP if k.startswith("node_")]
    if not node:
        parts += [not_judged(*compare.TELEOP[k], "the node was not run (node=False)") for k in node_keys]
    elif data is None or not data.ok:
        parts += [not_judged(*compare.TELEOP[k], "the file could not be imported (see above)") for k in node_keys]
    else:
        node_case = C.hidden_teleop_node_case(seed)
        script_path = run.space.grader_dir / "pad_script.yaml"
        script_path.write_text(yaml.safe_dump([dict(step) for step in node_case.script]), encoding="utf-8")
        if run.uid is not None:
            os.chown(script_path, run.uid, run.uid)
        plan = TeleopNodePlan(script=str(run.space.file("teleoperation")), pad_script=str(script_path),
                              gains=node_case.gains, force=node_case.force, start_timeout_s=10.0,
                              run_s=node_case.quit_s + 4.0, quit_grace_s=5.0, record=[TWIST_TOPIC, "/gripper_width"],
                              clock=grading_clock())
        observation = run.session(plan, timeout_s=90.0)
        parts += compare.compare_teleop_node(observation, node_case, TWIST_TOPIC, run.out_dir, str(run.space.package))
        notes += _clock_notes(observation, note=real_time_note(observation, node_case, TWIST_TOPIC))
    return finish_check("teleoperation", run, parts, seed, notes)


def scripted_pad_launch(node: str, scenario: PathLike) -> str:
    """The parameter launch file that gives the teleoperation ``node`` the grader's scripted virtual pad."""
    return ("<launch>\n  <!-- hri-grade: no gamepad here; the teleoperation node gets a scripted virtual pad -->\n"
            + "".join(f'  <param name="{node}/{k}" type="string" value="{v}"/>\n'
                      for k, v in (("pad", "virtual"), ("layout", "dualshock4"), ("pad_script", scenario)))
            + "</launch>\n")


def lab_sim_argv(scenario: PathLike) -> List[str]:
    """The grader's lab_sim (the lab's, trusted) with ``scenario``'s world, its board on the stand-in's topic."""
    return [str(REPO / "hri_lab" / "scripts" / "lab_sim.py"), "__name:=lab_sim",
            f"_config:={REPO / 'hri_lab' / 'config' / 'sim.yaml'}", f"_scenario:={scenario}",
            f"/pub_force:={BOARD_TOPIC}"]


def _launch_sim_plan(run: CheckRun, parsed: LaunchParseResult) -> Optional[TeleopLaunchSimPlan]:
    """The ``teleop-launch-sim`` session for a parsed teleoperation.launch; None without a teleoperation node."""
    node = compare.teleop_node_name(parsed)
    if node is None:
        return None
    scripts = compare.nodes_by_script(parsed)
    case = C.launch_sim_case()
    grader_dir = run.space.grader_dir
    scenario = grader_dir / "launch-sim.scenario.yaml"
    scenario.write_text(yaml.safe_dump(case.scenario(), sort_keys=False), encoding="utf-8")
    params = grader_dir / "launch-sim.params.launch"
    params.write_text(scripted_pad_launch(node, scenario), encoding="utf-8")
    for path in (scenario, params):
        if run.uid is not None:
            os.chown(path, run.uid, run.uid)
    package = run.space.package
    supply: Dict[str, List[str]] = {}
    if not [n for n in scripts.get("serial_node.py", []) if n.package == "rosserial_python"]:
        supply["serial_node"] = [str(run.space.ws / "rosserial_python" / "scripts" / "serial_node.py"),
                                 "_port:=/dev/ttyACM0"]
    for script in ("mapping_node.py", "gripper_manager.py"):
        if not [n for n in scripts.get(script, []) if n.package == "hri_lab"] and (package / "scripts" / script).is_file():
            supply[script[:-3]] = [str(package / "scripts" / script)]
    param_ok, _ = compare.check_max_param(parsed.params)
    return TeleopLaunchSimPlan(
        launch_file=str(run.space.file("teleoperation_launch")), params_launch=str(params), teleop_node=node,
        twist_topic=TWIST_TOPIC, supply=supply, set_max_sensor_force=None if param_ok else C.PUBLIC_MAX_SENSOR_FORCE,
        lab_sim=lab_sim_argv(scenario),
        record=[TWIST_TOPIC, "/force_mapped", "/pub_force", "/gripper_width", "/franka_gripper/joint_states",
                "/lab_sim/ee_pose", "/lab_sim/object", f"{node}/rumble"],
        start_timeout_s=20.0, run_s=case.quit_s + 12.0, clock=grading_clock(), settle_timeout_s=10.0,
        applied_topic="/lab_sim/command_time_s", sensor_chain=[BOARD_TOPIC, "/pub_force", "/force_mapped"],
        expect_nodes=sorted({n.full_name for n in parsed.nodes} | {f"/{name}" for name in supply}),
        default_rate_hz=lab_rate_hz())


def lab_rate_hz() -> float:
    """The teleoperation node's loop rate when the launch file sets none: the lab's teleop.yaml."""
    path = REPO / "hri_lab" / "config" / "teleop.yaml"
    try:
        return load_teleop_config(path).params.rate_hz if path.is_file() else TeleopParams().rate_hz
    except ConfigError:
        return TeleopParams().rate_hz


def _clock_notes(observation: Optional[ClockedObservation], prefix: str = "", note: str = "") -> List[str]:
    """A note when the grader meant to own the clock and a node made it fall back to real time (``note``: why)."""
    if observation is None or observation.problem or observation.session_error:
        return []
    if observation.clock == "real time" and grading_clock() == "grader":
        return [prefix + (note or _REAL_TIME_NOTE)]
    return []


_REAL_TIME_NOTE = ("a node did not publish at every tick of the grader's /clock (a loop kept by rospy.Rate, or by "
                   "time.sleep in your files, follows it), so it was run in real time")


@reusable("teleoperation-launch")
@closing_scratch
def grade_teleoperation_launch(path: PathLike, *, seed: Optional[int] = None,
                               out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 12-13: node set, serial_node with its port, /max_sensor_force, the controller include;
    then launched in simulation (the simulated lab in place of robot and board)."""
    require_ros()
    run, seed = start_check("teleoperation-launch", path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    parsed, facts = parse_launch(run, "teleoperation_launch")
    parts = compare.compare_teleop_launch(parsed, facts)
    plan = _launch_sim_plan(run, parsed) if parsed.ok else None
    observation: Optional[TeleopLaunchSimObservation] = run.session(plan, timeout_s=120.0) if plan is not None else None
    parts.append(compare.compare_teleop_launch_sim(parsed, observation, C.launch_sim_case(), run.out_dir))
    notes = _clock_notes(observation, "teleoperation.launch: ")
    if _left_as_template(run, "mapping_node", find_package_root(path)):
        notes.append(TEMPLATE_NOTE)  # the lab's ran in its place: Ex. 12 d) would go unnoticed
    return finish_check("teleoperation-launch", run, parts, None, notes)


CHECKS: Dict[str, Callable[..., CheckResult]] = {
    "robot-params": grade_robot_params,
    "mapping-node": grade_mapping_node,
    "sensor-launch": grade_sensor_launch,
    "teleoperation": grade_teleoperation,
    "teleoperation-launch": grade_teleoperation_launch,
    "graph": grade_graph,
    "catkin-package": grade_catkin_package,
}


def grade(check: str, path: PathLike, **kwargs: Any) -> CheckResult:
    """Run the check named ``check`` (one of CHECKS) on ``path``."""
    if check not in CHECKS:
        raise GradingError(f"unknown check {check!r}; use one of {', '.join(CHECKS)}")
    return CHECKS[check](path, **kwargs)


#: The checks that run ROS sessions, longest first: side by side, the longest starts first.
LONGEST_FIRST = ("teleoperation-launch", "teleoperation", "mapping-node", "sensor-launch", "graph")


def default_check_jobs(cpu_count: Optional[int]) -> int:
    """How many checks of one submission run at once by default: one more than the cores (1 if unknown).

    A check waits on process starts and sockets part of its time (the answer key's seven checks keep
    2 cores 75 % busy at one per core): answer key, 2 cores, idle, wall time at 2 / 3 / 4 checks at
    once: 7.8 / 6.4 / 7.3 s.
    """
    return max(1, cpu_count or 1) + 1


def grade_submission(folder: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                     graph_cache: Optional[PathLike] = None, checks: Sequence[str] = tuple(CHECKS),
                     jobs: int = 1) -> List[CheckResult]:
    """Every check on one student's package (missing files give failed checks, not errors), ``jobs``
    checks at a time (each has its own sandbox, master and clock: the verdicts do not depend on it)."""
    folder = Path(folder).expanduser()
    if not folder.is_dir():
        raise GradingError(f"{folder}: not a folder; give the student's hri_lab package folder (or their submission)")
    if jobs < 1:
        raise GradingError(f"--jobs {jobs}: give how many checks may run at once, at least 1")
    root = find_package_root(folder)
    seed = C.default_seed(root) if seed is None else seed

    def one(check: str) -> Callable[[], CheckResult]:
        kwargs: Dict[str, Any] = {"seed": seed, "out_dir": out_dir}
        if check == "graph":
            kwargs["graph_cache"] = graph_cache
        return lambda: CHECKS[check](root, **kwargs)

    if jobs == 1:
        return [one(check)() for check in checks]
    order = sorted(checks, key=lambda c: LONGEST_FIRST.index(c) if c in LONGEST_FIRST else len(LONGEST_FIRST))
    done: Dict[str, CheckResult] = {}
    failed: List[BaseException] = []

    def collect(check: str, result: Optional[CheckResult], error: Optional[BaseException]) -> None:
        if error is not None:
            failed.append(error)
        elif result is not None:
            done[check] = result

    run_all([(check, one(check)) for check in order], jobs, collect)
    if failed:
        raise failed[0]
    return [done[check] for check in checks]


# -- for notebooks: assertions with the student's messages -----------------------------------------

def _assert(result: CheckResult) -> CheckResult:
    if not result.passed:
        raise AssertionError("\n" + feedback_text([result]))
    return result


def check_robot_params(path: PathLike, **kwargs: Any) -> CheckResult:
    """For an autograded cell: AssertionError with the feedback unless every part passes."""
    return _assert(grade_robot_params(path, **kwargs))


def check_mapping_node(path: PathLike, **kwargs: Any) -> CheckResult:
    return _assert(grade_mapping_node(path, **kwargs))


def check_sensor_launch(path: PathLike, **kwargs: Any) -> CheckResult:
    return _assert(grade_sensor_launch(path, **kwargs))


def check_teleoperation(path: PathLike, **kwargs: Any) -> CheckResult:
    return _assert(grade_teleoperation(path, **kwargs))


def check_teleoperation_launch(path: PathLike, **kwargs: Any) -> CheckResult:
    return _assert(grade_teleoperation_launch(path, **kwargs))


def check_graph(path: PathLike, **kwargs: Any) -> CheckResult:
    return _assert(grade_graph(path, **kwargs))
