"""The checks: find the student's file, run it where it cannot hurt, compare, give points.

One function per handout deliverable, each returning a
:class:`~hri_teleop.grading.results.CheckResult`; ``grade_submission`` runs them all on a
student's package. The same functions serve ``hri-grade`` (CLI), ``make grade`` (many
submissions) and the notebooks' autograded cells (``check_*``: raise AssertionError with
the feedback when a part fails, so nbgrader shows the student what to fix).

Running is delegated (probes and sessions in sandboxes, :mod:`~hri_teleop.grading.run.sandbox`),
judging is :mod:`~hri_teleop.grading.judge.compare`; this module wires them together.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import yaml

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.grading.cases import inputs as C
from hri_teleop.grading.judge import compare, reuse
from hri_teleop.grading.judge.package_check import grade_catkin_package
from hri_teleop.grading.judge.reference_guard import reference_uses, refusal
from hri_teleop.grading.judge.robot_params import compare_robot_params
from hri_teleop.grading.results import CheckResult, GradingError, Part, feedback_text, not_judged
from hri_teleop.grading.run.sandbox import (
    DEFAULT_LIMITS,
    StudentProcess,
    describe_exit,
    sandbox_mode,
    session_argv,
    student_uid,
)
from hri_teleop.grading.run.workspace import (
    DELIVERABLES,
    REPO,
    Workspace,
    find_package_root,
    prepare_workspace,
    ros_package_path,
)
from hri_teleop.hardware.sim.sensor_profile import FSR_SENSOR_RATE_HZ
from hri_teleop.ros.master import lab_shell_env

__all__ = [
    "CHECKS", "grade", "grade_robot_params", "grade_mapping_node", "grade_sensor_launch", "grade_teleoperation",
    "grade_teleoperation_launch", "grade_graph", "grade_submission", "live_graph",
    "check_robot_params", "check_mapping_node", "check_sensor_launch", "check_teleoperation",
    "check_teleoperation_launch", "check_graph",
]

PathLike = Union[str, Path]
_PROBE_TIMEOUT_S = 20.0
TWIST_TOPIC = DEFAULT_TWIST_TOPIC


# -- shared machinery -----------------------------------------------------------------------

def _require_ros() -> None:
    for tool in ("roscore", "roslaunch"):
        if shutil.which(tool, path=_grader_env()["PATH"]) is None:
            raise GradingError(f"{tool} not found: run 'make setup' (it installs ROS 1) and source tools/env.sh")


def _grader_env(package_path: str = "") -> Dict[str, str]:
    """tools/env.sh's environment with ``package_path`` (default: the lab's hri_lab) and no outside master."""
    env = lab_shell_env(package_root=REPO)
    if package_path:
        env["ROS_PACKAGE_PATH"] = package_path
    for key in ("ROS_MASTER_URI", "ROS_IP"):
        env.pop(key, None)
    env["ROS_HOSTNAME"] = "127.0.0.1"
    env["PYTHONUNBUFFERED"] = "1"
    return env


_OPEN_RUNS: "List[_Run]" = []


def _closing(check: Callable[..., CheckResult]) -> Callable[..., CheckResult]:
    """Whatever happens inside a check, its scratch folder does not outlive it."""
    @functools.wraps(check)
    def wrapper(*args: Any, **kwargs: Any) -> CheckResult:
        try:
            return check(*args, **kwargs)
        finally:
            for run in list(_OPEN_RUNS):
                run.close()
    return wrapper


#: Keyword arguments that do not change a check's result (the lab's graph is the same from a cache).
_SAME_RESULT_KWARGS = {"seed", "out_dir", "graph_cache"}


def _reusable(check: str) -> Callable[[Callable[..., CheckResult]], Callable[..., CheckResult]]:
    """In make grade only: the files job stores each result, a notebook's check cell of the same
    package takes it (:mod:`hri_teleop.grading.judge.reuse`). A file given alone, or arguments that
    change what is judged (``node=False``), always run the check."""
    def decorate(grade_fn: Callable[..., CheckResult]) -> Callable[..., CheckResult]:
        @functools.wraps(grade_fn)
        def wrapper(path: PathLike, **kwargs: Any) -> CheckResult:
            write, read = os.environ.get(reuse.WRITE_ENV), os.environ.get(reuse.READ_ENV)
            given = Path(path).expanduser()
            if not (write or read) or not set(kwargs) <= _SAME_RESULT_KWARGS or not given.is_dir():
                return grade_fn(path, **kwargs)
            root = find_package_root(given)
            seed = C.seed_for(root) if kwargs.get("seed") is None else int(kwargs["seed"])
            if read and not write:
                found = reuse.load(Path(read), check, seed, root)
                if found is not None:
                    return found
            result = grade_fn(path, **kwargs)
            if write:
                reuse.store(Path(write), check, seed, root, result)
            return result
        return wrapper
    return decorate


class _Run:
    """One check's scratch folder (a fresh workspace) and where its plots and logs go."""

    def __init__(self, check: str, submission: PathLike, out_dir: Optional[PathLike], key: str,
                 single_file: Optional[Path], reference: Sequence[str] = ()) -> None:
        self.check = check
        self.session_dir = Path(tempfile.mkdtemp(prefix=f"hri-grade-{check}-"))
        # Without out_dir, plots of failed parts go to a fresh temp path (created only if one is drawn)
        # and the logs are not kept.
        self.keep_logs = out_dir is not None
        self.out_dir = Path(out_dir) / check if out_dir else \
            Path(tempfile.gettempdir()) / f"hri-grade-out-{check}-{os.getpid()}-{time.monotonic_ns()}"
        if out_dir:
            self.out_dir.mkdir(parents=True, exist_ok=True)
        self.uid = student_uid()
        self.closed = False
        _OPEN_RUNS.append(self)
        self.space: Workspace = prepare_workspace(submission, self.session_dir, self.uid, single_file, key,
                                                  reference=reference)
        self.started = time.monotonic()

    def close(self) -> None:
        """Keep the logs (256 kB each) next to the plots, delete the scratch folder; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        if self in _OPEN_RUNS:
            _OPEN_RUNS.remove(self)
        logs = self.session_dir / "logs"
        if logs.is_dir() and self.keep_logs:
            target = self.out_dir / "logs"
            target.mkdir(parents=True, exist_ok=True)
            for log in logs.glob("*.log"):
                with open(log, "rb") as src, open(target / log.name, "wb") as dst:
                    dst.write(src.read(256 * 1024))
        if not os.environ.get("HRI_GRADE_KEEP"):
            shutil.rmtree(self.session_dir, ignore_errors=True)

    def env(self) -> Dict[str, str]:
        return _grader_env(ros_package_path(self.space.ws))

    def probe(self, command: str, target: Path, name: str, plan: Optional[Path] = None
              ) -> Tuple[Optional[Dict[str, Any]], Dict[str, Any]]:
        """Run a probe as a student process (no network); (its JSON or None, facts about the process)."""
        out = self.space.grader_dir / f"{name}.json"
        env = self.env()
        env.update({"HOME": str(self.space.package), "ROS_HOME": str(self.space.package / ".ros"),
                    "PYTHONDONTWRITEBYTECODE": "1", "MPLBACKEND": "Agg", "SDL_VIDEODRIVER": "dummy",
                    "SDL_AUDIODRIVER": "dummy"})
        argv = [sys.executable, "-m", "hri_teleop.grading.run.probe", command, str(target)]
        argv += ([str(plan)] if plan is not None else []) + [str(out)]
        proc = StudentProcess(argv, self.space.package, env, self.session_dir / "logs" / f"{name}.log",
                              DEFAULT_LIMITS, uid=self.uid, nested=True, network=False)
        code = proc.wait(_PROBE_TIMEOUT_S)
        problem = "" if code is not None else f"was still running after {_PROBE_TIMEOUT_S:.0f} s (an endless loop?)"
        proc.stop()
        facts = {"exit_code": proc.returncode, "output_tail": proc.output_tail(), "output_bytes": proc.output_size(),
                 "problem": problem or (describe_exit(proc.returncode) if proc.returncode else "")}
        data: Optional[Dict[str, Any]] = None
        if out.is_file() and code == 0:
            try:
                data = json.loads(out.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                data = None
        return data, facts

    def session(self, plan: Dict[str, Any], timeout_s: float) -> Dict[str, Any]:
        """Run a session plan (sandboxed: own network namespace) and return its observation."""
        plan = dict(plan)
        plan.update({"session_dir": str(self.session_dir), "student_folder": str(self.space.package),
                     "uid": self.uid, "python": sys.executable, "env": dict(self.env(), TMPDIR=str(self.session_dir)),
                     "out": str(self.session_dir / f"{plan['kind']}.out.json"),
                     "limits": {"cpu_s": DEFAULT_LIMITS.cpu_s, "memory_bytes": DEFAULT_LIMITS.memory_bytes,
                                "file_bytes": DEFAULT_LIMITS.file_bytes, "processes": DEFAULT_LIMITS.processes,
                                "open_files": DEFAULT_LIMITS.open_files}})
        return run_session_plan(plan, self.session_dir, timeout_s)


def run_session_plan(plan: Dict[str, Any], session_dir: Path, timeout_s: float) -> Dict[str, Any]:
    """Start ``python -m hri_teleop.grading.run.session`` (in bubblewrap where it works), wait, read."""
    plan_path = session_dir / f"{plan['kind']}.plan.json"
    plan_path.write_text(json.dumps(plan), encoding="utf-8")
    out = Path(plan["out"])
    argv = session_argv([sys.executable, "-m", "hri_teleop.grading.run.session", str(plan_path)], session_dir)
    log = open(session_dir / f"{plan['kind']}.session.log", "wb")
    proc = subprocess.Popen(argv, env=plan["env"], stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True, cwd=str(session_dir))
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        for sig in (signal.SIGTERM, signal.SIGKILL):
            try:
                os.killpg(proc.pid, sig)
            except ProcessLookupError:
                break
            try:
                proc.wait(timeout=3)
                break
            except subprocess.TimeoutExpired:
                continue
        log.close()
        return {"session_error": f"the grading session did not finish within {timeout_s:.0f} s"}
    log.close()
    if not out.is_file():
        tail = (session_dir / f"{plan['kind']}.session.log").read_text(errors="replace")[-1500:]
        return {"session_error": f"the grading session ended without a result (status {proc.returncode}): {tail}"}
    return json.loads(out.read_text(encoding="utf-8"))


def _missing_result(check: str, key: str, table: Dict[str, Tuple[str, float]], root: Path, seed: Optional[int]) -> CheckResult:
    sub = DELIVERABLES[key]
    entries = list(table.values())
    parts = [Part(entries[0][0], entries[0][1], False, f"{sub} was not found in {root}: put it at {sub} in your "
                                                        "hri_lab package")]
    parts += [not_judged(name, points, f"{sub} was not found") for name, points in entries[1:]]
    return CheckResult(check, str(root / sub), parts, seed)


def _resolve(path: PathLike, key: str) -> Tuple[Path, Optional[Path], Optional[Path]]:
    """(package root, the file given explicitly or None, the file found or None)."""
    path = Path(path).expanduser()
    if not path.exists():
        raise GradingError(f"{path}: no such file or folder; give the student's {DELIVERABLES[key]} or their "
                           "hri_lab folder")
    root = find_package_root(path)
    if path.is_file():
        return root, path, path
    from hri_teleop.grading.run.workspace import locate

    return root, None, locate(root, key)


def _finish(check: str, run: _Run, parts: List[Part], seed: Optional[int], notes: Sequence[str] = ()) -> CheckResult:
    target = run.space.originals.get(_KEY[check])
    mode = sandbox_mode(warn=False)
    all_notes = list(notes) + ([] if mode == "bwrap" else ["student code ran without bubblewrap (limits only)"])
    if run.space.substituted:
        names = ", ".join(Path(DELIVERABLES[k]).name for k in run.space.substituted)
        all_notes.append(f"ran the lab's {names} in place of yours: each is graded in its own check, so a mistake "
                         "there costs points there only")
    result = CheckResult(check, str(target) if target else "", parts, seed, time.monotonic() - run.started,
                         tuple(all_notes))
    run.close()
    return result


#: Other exercises' deliverables a check's run needs: the lab's versions stand in for the student's.
_REFERENCE_FOR: Dict[str, Tuple[str, ...]] = {"sensor-launch": ("mapping_node", "robot_params"),
                                              "teleoperation-launch": ("mapping_node", "teleoperation")}
_KEY = {"robot-params": "robot_params", "mapping-node": "mapping_node", "sensor-launch": "sensor_launch",
        "teleoperation": "teleoperation", "teleoperation-launch": "teleoperation_launch", "graph": "graph"}


def _table_for(check: str) -> Dict[str, Tuple[str, float]]:
    if check == "robot-params":
        from hri_teleop.grading.judge.robot_params import part_table

        return part_table()
    return {"mapping-node": compare.MAPPING, "sensor-launch": compare.SENSOR_LAUNCH, "teleoperation": compare.TELEOP,
            "teleoperation-launch": compare.TELEOP_LAUNCH, "graph": compare.GRAPH}[check]


def _start(check: str, path: PathLike, out_dir: Optional[PathLike], seed: Optional[int]
           ) -> Tuple[Optional[_Run], Optional[CheckResult], int]:
    key = _KEY[check]
    root, given, found = _resolve(path, key)
    seed = C.seed_for(root) if seed is None else int(seed)
    if found is None:
        hidden = check in ("mapping-node", "teleoperation")
        return None, _missing_result(check, key, _table_for(check), root, seed if hidden else None), seed
    sandbox_mode()  # says once when bubblewrap is missing
    return _Run(check, root if given is None else given, out_dir, key, given or found,
                reference=_REFERENCE_FOR.get(check, ())), None, seed


def _refuse_reference(run: _Run, check: str, table: Dict[str, Tuple[str, float]], seed: Optional[int]
                      ) -> Optional[CheckResult]:
    """Every part failed when the student's file uses the lab's reference rules (None: it does not)."""
    target = run.space.files[_KEY[check]]
    try:
        uses = reference_uses(target.read_text(encoding="utf-8")) if target is not None else []
    except (OSError, UnicodeDecodeError):
        uses = []  # the check itself says the file cannot be read
    if not uses:
        return None
    entries = list(table.values())
    message = refusal(Path(DELIVERABLES[_KEY[check]]).name, uses)
    parts = [Part(entries[0][0], entries[0][1], False, message)]
    parts += [not_judged(name, points, "the file uses the lab's reference implementation") for name, points in entries[1:]]
    return _finish(check, run, parts, seed)


# -- the checks --------------------------------------------------------------------------------

@_reusable("robot-params")
@_closing
def grade_robot_params(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 4: Table 1's keys, YAML types and values; loaded with rosparam's own loader."""
    run, missing, seed = _start("robot-params", path, out_dir, seed)
    if run is None:
        return missing  # type: ignore[return-value]
    target = run.space.files["robot_params"]
    data, facts = run.probe("rosparam-load", target, "rosparam-load")
    if data is None:
        parts = compare_robot_params(None, compare.explain_process(facts, "loading robot_params.yaml"))
    elif not data.get("ok"):
        parts = compare_robot_params(None, f"`rosparam load` fails: {data.get('error')}")
    else:
        parts = compare_robot_params(data["params"])
    return _finish("robot-params", run, parts, None)


@_reusable("mapping-node")
@_closing
def grade_mapping_node(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                       reference_allowed: bool = False) -> CheckResult:
    """Ex. 5: the node for real on a private master: topics, type, every value, the range from the parameter.

    ``reference_allowed``: judge a file that uses the lab's reference rule too (the lab's own
    node, when the grader's agreement with it is tested); students' files never are.
    """
    _require_ros()
    run, missing, seed = _start("mapping-node", path, out_dir, seed)
    if run is None:
        return missing  # type: ignore[return-value]
    refused = None if reference_allowed else _refuse_reference(run, "mapping-node", compare.MAPPING, seed)
    if refused is not None:
        return refused
    cases = [C.public_mapping_case()] + C.hidden_mapping_cases(seed)
    plan = {"kind": "mapping-node", "script": str(run.space.files["mapping_node"]),
            "cases": [{"label": c.label, "max_sensor_force": c.max_sensor_force, "counts": list(c.counts)} for c in cases],
            "start_timeout_s": 10.0, "response_timeout_s": 1.5}
    observation = run.session(plan, timeout_s=120.0)
    parts = compare.compare_mapping(observation, cases, run.out_dir)
    return _finish("mapping-node", run, parts, seed)


def _parse_launch(run: _Run, key: str) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    data, facts = run.probe("launch-parse", run.space.files[key], f"parse-{key}")
    return (data if data is not None else {"ok": False, "error": ""}), facts


#: ``HRI_GRADE_CLOCK=real`` runs the nodes in real time, as before the grader owned the clock
#: (to compare, or to rule the clock out when a node behaves differently under grading).
CLOCK_ENV = "HRI_GRADE_CLOCK"


def grading_clock() -> str:
    """"grader" (the default: /use_sim_time, /clock stepped by the grader) or "real time"."""
    value = os.environ.get(CLOCK_ENV, "grader").strip() or "grader"
    if value not in ("grader", "real"):
        raise GradingError(f"{CLOCK_ENV} is {value!r}; use grader (the default: the grader owns /clock) or real "
                           "(the nodes run in real time)")
    return "grader" if value == "grader" else "real time"


def _full_name(node: Dict[str, Any]) -> str:
    """A parsed launch node's ROS name, ``/ns/name``."""
    return f"{node['namespace'].rstrip('/')}/{node['name']}"


@_reusable("sensor-launch")
@_closing
def grade_sensor_launch(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 6-7: parsed with roslaunch's loader, then launched: /force_mapped flows and stays in [0, 1]."""
    _require_ros()
    run, missing, seed = _start("sensor-launch", path, out_dir, seed)
    if run is None:
        return missing  # type: ignore[return-value]
    parsed, facts = _parse_launch(run, "sensor_launch")
    observation: Optional[Dict[str, Any]] = None
    if parsed.get("ok"):
        scripts = {n["type"] for n in parsed.get("nodes", [])}
        param_ok, _ = compare.check_max_param(parsed.get("params", {}))
        package = run.space.package
        run_mapping = "mapping_node.py" not in scripts and (package / "scripts" / "mapping_node.py").is_file()
        plan = {"kind": "sensor-launch", "launch_file": str(run.space.files["sensor_launch"]),
                "set_max_sensor_force": None if param_ok else C.PUBLIC_MAX_SENSOR_FORCE,
                "run_fsr_sensor": "FSR_sensor.py" not in scripts, "fsr_sensor": str(package / "scripts" / "FSR_sensor.py"),
                "run_mapping_node": run_mapping,
                "mapping_node": str(package / "scripts" / "mapping_node.py"),
                "start_timeout_s": 15.0, "record_s": 3.0,
                "record_messages": 10, "clock": grading_clock(), "settle_timeout_s": 10.0,
                "fsr_node": next((_full_name(n) for n in parsed.get("nodes", []) if n["type"] == "FSR_sensor.py"),
                                 "/FSR_sensor"),
                "default_fsr_rate_hz": FSR_SENSOR_RATE_HZ,
                "mapping_node_name": next((_full_name(n) for n in parsed.get("nodes", [])
                                           if n["type"] == "mapping_node.py"), "/mapping_node"),
                "expect_nodes": sorted({_full_name(n) for n in parsed.get("nodes", [])}
                                       | ({"/FSR_sensor"} if "FSR_sensor.py" not in scripts else set())
                                       | ({"/mapping_node"} if run_mapping else set()))}
        observation = run.session(plan, timeout_s=90.0)
    parts = compare.compare_sensor_launch(parsed, observation, facts)
    notes = _clock_notes(observation, "sensor.launch: ")
    return _finish("sensor-launch", run, parts, None, notes)


@_reusable("teleoperation")
@_closing
def grade_teleoperation(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                        node: bool = True) -> CheckResult:
    """Ex. 8-9: the student's parts against pad-event traces, then the node with the virtual pad."""
    from hri_teleop.core.gamepad.events import pad_events

    _require_ros()
    run, missing, seed = _start("teleoperation", path, out_dir, seed)
    if run is None:
        return missing  # type: ignore[return-value]
    refused = _refuse_reference(run, "teleoperation", compare.TELEOP, seed)
    if refused is not None:
        return refused
    cases = [C.public_teleop_parts_case(), C.hidden_teleop_parts_case(seed)]
    notes: List[str] = []
    plan_cases = []
    for case in cases:
        ticks, previous = [], None
        for tick in case.ticks:
            state = tick.state()
            events = [[e.type, e.button, e.axis, e.value] for e in pad_events(previous, state)]
            ticks.append({"events": events, "force": tick.force})
            previous = state
        plan_cases.append({"label": case.label, "gains": case.gains.as_dict(), "ticks": ticks})
    plan_path = run.space.grader_dir / "teleop-parts.plan.json"
    plan_path.write_text(json.dumps({"cases": plan_cases}), encoding="utf-8")
    if run.uid is not None:
        os.chown(plan_path, run.uid, run.uid)
    data, facts = run.probe("teleop-parts", run.space.files["teleoperation"], "teleop-parts", plan_path)
    parts = compare.compare_teleop_parts(data or {"ok": False, "error": ""}, cases, run.out_dir, facts)
    node_keys = [k for k in compare.TELEOP if k.startswith("node_")]
    if not node:
        parts += [not_judged(*compare.TELEOP[k], "the node was not run (node=False)") for k in node_keys]
    elif not (data or {}).get("ok"):
        parts += [not_judged(*compare.TELEOP[k], "the file could not be imported (see above)") for k in node_keys]
    else:
        node_case = C.hidden_teleop_node_case(seed)
        script_path = run.space.grader_dir / "pad_script.yaml"
        script_path.write_text(yaml.safe_dump([dict(step) for step in node_case.script]), encoding="utf-8")
        if run.uid is not None:
            os.chown(script_path, run.uid, run.uid)
        plan = {"kind": "teleop-node", "script": str(run.space.files["teleoperation"]), "pad_script": str(script_path),
                "gains": node_case.gains.as_dict(), "force": node_case.force, "start_timeout_s": 10.0,
                "run_s": node_case.quit_s + 4.0, "quit_grace_s": 5.0, "record": [TWIST_TOPIC, "/gripper_width"],
                "clock": grading_clock()}
        observation = run.session(plan, timeout_s=90.0)
        parts += compare.compare_teleop_node(observation, node_case, TWIST_TOPIC, run.out_dir)
        notes += _clock_notes(observation)
    return _finish("teleoperation", run, parts, seed, notes)


def _launch_sim_plan(run: _Run, parsed: Dict[str, Any]) -> Optional[Dict[str, Any]]:
    """The ``teleop-launch-sim`` session for a parsed teleoperation.launch; None without a teleoperation node."""
    from hri_teleop.grading.run.standins import BOARD_TOPIC

    node = compare.teleop_node_name(parsed)
    if node is None:
        return None
    scripts = compare.nodes_by_script(parsed)
    case = C.launch_sim_case()
    grader_dir = run.space.grader_dir
    scenario = grader_dir / "launch-sim.scenario.yaml"
    scenario.write_text(yaml.safe_dump(case.scenario(), sort_keys=False), encoding="utf-8")
    params = grader_dir / "launch-sim.params.launch"
    params.write_text("<launch>\n  <!-- hri-grade: no gamepad here; the teleoperation node gets a scripted virtual pad -->\n"
                      + "".join(f'  <param name="{node}/{k}" type="string" value="{v}"/>\n'
                                for k, v in (("pad", "virtual"), ("layout", "dualshock4"), ("pad_script", scenario)))
                      + "</launch>\n", encoding="utf-8")
    for path in (scenario, params):
        if run.uid is not None:
            os.chown(path, run.uid, run.uid)
    package = run.space.package
    supply: Dict[str, List[str]] = {}
    if not [n for n in scripts.get("serial_node.py", []) if n["package"] == "rosserial_python"]:
        supply["serial_node"] = [str(run.space.ws / "rosserial_python" / "scripts" / "serial_node.py"),
                                 "_port:=/dev/ttyACM0"]
    for script in ("mapping_node.py", "gripper_manager.py"):
        if not scripts.get(script) and (package / "scripts" / script).is_file():
            supply[script[:-3]] = [str(package / "scripts" / script)]
    param_ok, _ = compare.check_max_param(parsed.get("params", {}))
    return {"kind": "teleop-launch-sim", "launch_file": str(run.space.files["teleoperation_launch"]),
            "params_launch": str(params), "teleop_node": node, "twist_topic": TWIST_TOPIC, "supply": supply,
            "set_max_sensor_force": None if param_ok else C.PUBLIC_MAX_SENSOR_FORCE,
            "lab_sim": [str(REPO / "hri_lab" / "scripts" / "lab_sim.py"), "__name:=lab_sim",
                        f"_config:={REPO / 'hri_lab' / 'config' / 'sim.yaml'}", f"_scenario:={scenario}",
                        f"/pub_force:={BOARD_TOPIC}"],
            "record": [TWIST_TOPIC, "/force_mapped", "/pub_force", "/gripper_width", "/franka_gripper/joint_states",
                       "/lab_sim/ee_pose", "/lab_sim/object", f"{node}/rumble"],
            "start_timeout_s": 20.0, "run_s": case.quit_s + 12.0, "clock": grading_clock(), "settle_timeout_s": 10.0,
            "applied_topic": "/lab_sim/command_time_s", "sensor_chain": [BOARD_TOPIC, "/pub_force", "/force_mapped"],
            "expect_nodes": sorted({_full_name(n) for n in parsed.get("nodes", [])} | {f"/{name}" for name in supply}),
            "default_rate_hz": _lab_rate_hz()}


def _lab_rate_hz() -> float:
    """The teleoperation node's loop rate when the launch file sets none: the lab's teleop.yaml."""
    from hri_teleop.core.config import ConfigError, load_teleop_config
    from hri_teleop.core.teleop import TeleopParams

    path = REPO / "hri_lab" / "config" / "teleop.yaml"
    try:
        return load_teleop_config(path).params.rate_hz if path.is_file() else TeleopParams().rate_hz
    except ConfigError:
        return TeleopParams().rate_hz


def _clock_notes(observation: Optional[Dict[str, Any]], prefix: str = "") -> List[str]:
    """A note when the grader meant to own the clock and a node made it fall back to real time."""
    if not observation or observation.get("problem") or observation.get("session_error"):
        return []
    if observation.get("clock") == "real time" and grading_clock() == "grader":
        return [prefix + _REAL_TIME_NOTE]
    return []


_REAL_TIME_NOTE = ("the node did not tick with the grader's /clock (a loop paced by rospy.Rate does; time.sleep "
                   "does not), so it was run in real time")


@_reusable("teleoperation-launch")
@_closing
def grade_teleoperation_launch(path: PathLike, *, seed: Optional[int] = None,
                               out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 12-13: node set, serial_node with its port, /max_sensor_force, the controller include;
    then launched in simulation (the simulated lab in place of robot and board)."""
    _require_ros()
    run, missing, seed = _start("teleoperation-launch", path, out_dir, seed)
    if run is None:
        return missing  # type: ignore[return-value]
    parsed, facts = _parse_launch(run, "teleoperation_launch")
    parts = compare.compare_teleop_launch(parsed, facts)
    plan = _launch_sim_plan(run, parsed) if parsed.get("ok") else None
    observation = run.session(plan, timeout_s=120.0) if plan is not None else None
    parts.append(compare.compare_teleop_launch_sim(parsed, observation, C.launch_sim_case(), run.out_dir))
    notes = _clock_notes(observation, "teleoperation.launch: ")
    return _finish("teleoperation-launch", run, parts, None, notes)


_LIVE_GRAPH: Dict[str, Dict[str, Any]] = {}
LIVE_GRAPH_NODES = ("/FSR_sensor", "/mapping_node", "/gripper_manager", "/teleoperation")


def graph_cache_file(reference: Path = REPO / "hri_lab") -> Path:
    """Where the lab's live graph is kept between runs: named after what shapes it.

    The key is a digest of the reference package's launch, script and config files, the
    ROS distribution and the Python version, so a changed pipeline is read afresh.
    """
    import hashlib

    digest = hashlib.sha256(f"{os.environ.get('ROS_DISTRO', '')} {sys.version_info[:2]}".encode())
    for folder in ("launch", "scripts", "config"):
        for path in sorted((reference / folder).glob("*")):
            if path.is_file():
                digest.update(f"{folder}/{path.name}\0".encode() + path.read_bytes() + b"\0")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "hri-teleop" / f"live-graph-{digest.hexdigest()[:16]}.json"


def live_graph(cache_file: Optional[PathLike] = None) -> Dict[str, Any]:
    """The graph of the lab's pipeline (hri_lab teleoperation.launch without hardware), once per process.

    ``cache_file``: read it if it exists, else write it (``make grade`` computes it once for
    all). Without one, :func:`graph_cache_file` keeps it between runs (written if it can be).
    """
    if "graph" in _LIVE_GRAPH:
        return _LIVE_GRAPH["graph"]
    from hri_teleop.grading.run.workspace import REFERENCE_PACKAGE

    if cache_file is None and (REFERENCE_PACKAGE / "launch" / "teleoperation.launch").is_file():
        cache_file = graph_cache_file(REFERENCE_PACKAGE)
    if cache_file and Path(cache_file).is_file():
        try:
            _LIVE_GRAPH["graph"] = json.loads(Path(cache_file).read_text(encoding="utf-8"))
            return _LIVE_GRAPH["graph"]
        except (OSError, ValueError):
            pass  # unreadable or cut short: compute it again
    if not (REFERENCE_PACKAGE / "launch" / "teleoperation.launch").is_file():
        return _graph_of_running_master()  # the student bundle: the pipeline its notebook started
    _require_ros()
    session_dir = Path(tempfile.mkdtemp(prefix="hri-grade-graph-"))
    try:
        env = _grader_env()
        plan = {"kind": "live-graph", "session_dir": str(session_dir), "student_folder": "", "uid": None,
                "python": sys.executable, "env": dict(env, TMPDIR=str(session_dir)),
                "out": str(session_dir / "live-graph.out.json"),
                "launch_args": ["robot:=false", "arduino:=false", "pad:=virtual"], "nodes": list(LIVE_GRAPH_NODES),
                "start_timeout_s": 30.0}
        graph = run_session_plan(plan, session_dir, 90.0)
    finally:
        shutil.rmtree(session_dir, ignore_errors=True)
    if graph.get("session_error") or graph.get("problem"):
        raise GradingError(f"could not read the lab's live graph: {graph.get('session_error') or graph.get('problem')}")
    _LIVE_GRAPH["graph"] = graph
    if cache_file:
        try:
            Path(cache_file).parent.mkdir(parents=True, exist_ok=True)
            partial = Path(cache_file).with_suffix(f".{os.getpid()}.tmp")
            partial.write_text(json.dumps(graph, sort_keys=True), encoding="utf-8")
            partial.replace(cache_file)  # whole or not at all: graders running side by side read it
        except OSError:
            pass  # a read-only home: the graph is computed again next time
    return graph


def _graph_of_running_master() -> Dict[str, Any]:
    """The graph on this process's master (ROS_MASTER_URI), once two readings 0.3 s apart agree."""
    from hri_teleop.course.notebook_ros import NotebookRosError, master_call

    try:
        previous: Any = None
        for _ in range(50):
            pubs, subs, _services = master_call("getSystemState")
            reading = (sorted((t, sorted(n)) for t, n in pubs), sorted((t, sorted(n)) for t, n in subs))
            if reading == previous:
                break
            previous = reading
            time.sleep(0.3)
        types = dict(master_call("getTopicTypes"))
    except NotebookRosError as exc:
        raise GradingError(f"no pipeline to compare with: {exc}") from None
    running = {n for _t, names in pubs for n in names} | {n for _t, names in subs for n in names}
    missing = [n for n in LIVE_GRAPH_NODES if n not in running]
    if missing:
        raise GradingError(f"the pipeline is not running here ({', '.join(missing)} missing): run the cell that "
                           "starts it (start_pipeline()) first, then this check")
    return {"kind": "live-graph", "problem": "", "publishers": {t: sorted(n) for t, n in pubs},
            "subscribers": {t: sorted(n) for t, n in subs}, "types": types}


@_reusable("graph")
def grade_graph(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                graph_cache: Optional[PathLike] = None) -> CheckResult:
    """Ex. 15: the student's nodes, topics and types against the live graph of the lab's pipeline."""
    key = "graph"
    root, given, found = _resolve(path, key)
    started = time.monotonic()
    if found is None:
        return _missing_result("graph", key, compare.GRAPH, root, None)
    error, answer = "", None
    try:
        if found.stat().st_size > 100_000:
            error = "graph.yaml is larger than 100 kB; list only the pipeline's nodes and topics"
        else:
            answer = yaml.safe_load(found.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        error = f"graph.yaml cannot be read ({exc})"
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        error = f"graph.yaml line {mark.line + 1 if mark else '?'}: {getattr(exc, 'problem', exc)}; fix the YAML syntax"
    parts = compare.compare_graph(answer, live_graph(graph_cache) if not error and isinstance(answer, dict) else {},
                                  error)
    return CheckResult("graph", str(found), parts, None, time.monotonic() - started)


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


def grade_submission(folder: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                     graph_cache: Optional[PathLike] = None, checks: Sequence[str] = tuple(CHECKS)) -> List[CheckResult]:
    """Every check on one student's package (missing files give failed checks, not errors)."""
    folder = Path(folder).expanduser()
    if not folder.is_dir():
        raise GradingError(f"{folder}: not a folder; give the student's hri_lab package folder (or their submission)")
    root = find_package_root(folder)
    seed = C.seed_for(root) if seed is None else seed
    results = []
    for check in checks:
        kwargs: Dict[str, Any] = {"seed": seed, "out_dir": out_dir}
        if check == "graph":
            kwargs["graph_cache"] = graph_cache
        results.append(CHECKS[check](root, **kwargs))
    return results


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
