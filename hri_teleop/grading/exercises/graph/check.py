"""Ex. 15's check: the student's computation graph against the lab's live one (cached per reference).

The student's graph.yaml is parsed by a probe in a student sandbox with the bounded safe loader
(an alias bomb or a 100 MB document never reaches the grader's own process); only its plain data
comes back.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Dict, Optional, Union

from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.exercises.graph.judge import PARTS, compare_graph
from hri_teleop.grading.exercises.graph.session import LiveGraphObservation, LiveGraphPlan
from hri_teleop.grading.judge.compare_common import explain_process
from hri_teleop.grading.judge.harness import (
    CheckRun,
    grader_shell_env,
    missing_result,
    refused_result,
    require_ros,
    resolve_deliverable,
    reusable,
    run_session_plan,
)
from hri_teleop.grading.results import CheckResult, GradingError
from hri_teleop.grading.run.records import SessionContext, YamlResult
from hri_teleop.grading.run.sandbox import DEFAULT_LIMITS
from hri_teleop.grading.run.workspace import (
    REFERENCE_PACKAGE,
    REPO,
)
from hri_teleop.ros.master_api import MasterApiError, master_call

__all__ = ["EXERCISE", "LIVE_GRAPH_NODES", "SENSOR_NODES", "graph_cache_file", "live_graph", "graph_of_running_master", "grade_graph"]

PathLike = Union[str, Path]


_LIVE_GRAPH: Dict[str, LiveGraphObservation] = {}
LIVE_GRAPH_NODES = ("/FSR_sensor", "/mapping_node", "/gripper_manager", "/teleoperation")
#: The board's node on a running master: its simulation at home, the Arduino's serial_node in the lab.
SENSOR_NODES = ("/FSR_sensor", "/serial_node")


def graph_cache_file(reference: Path = REPO / "hri_lab") -> Path:
    """Where the lab's live graph is kept between runs: named after what shapes it.

    The key is a digest of the reference package's launch, script and config files, the
    ROS distribution and the Python version, so a changed pipeline is read afresh.
    """
    digest = hashlib.sha256(f"{os.environ.get('ROS_DISTRO', '')} {sys.version_info[:2]}".encode())
    for folder in ("launch", "scripts", "config"):
        for path in sorted((reference / folder).glob("*")):
            if path.is_file():
                digest.update(f"{folder}/{path.name}\0".encode() + path.read_bytes() + b"\0")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "hri-teleop" / f"live-graph-{digest.hexdigest()[:16]}.json"


def live_graph(cache_file: Optional[PathLike] = None) -> LiveGraphObservation:
    """The graph of the lab's pipeline (hri_lab teleoperation.launch without hardware), once per process.

    ``cache_file``: read it if it exists, else write it (``make grade`` computes it once for
    all). Without one, :func:`graph_cache_file` keeps it between runs (written if it can be).
    """
    if "graph" in _LIVE_GRAPH:
        return _LIVE_GRAPH["graph"]

    if cache_file is None and (REFERENCE_PACKAGE / "launch" / "teleoperation.launch").is_file():
        cache_file = graph_cache_file(REFERENCE_PACKAGE)
    if cache_file and Path(cache_file).is_file():
        try:
            _LIVE_GRAPH["graph"] = LiveGraphObservation.from_json(json.loads(Path(cache_file).read_text(encoding="utf-8")))
            return _LIVE_GRAPH["graph"]
        except (OSError, ValueError):
            pass  # unreadable, cut short or of another version (RecordError): compute it again
    if not (REFERENCE_PACKAGE / "launch" / "teleoperation.launch").is_file():
        return graph_of_running_master()  # the student bundle: the pipeline its notebook started
    require_ros()
    session_dir = Path(tempfile.mkdtemp(prefix="hri-grade-graph-"))
    try:
        context = SessionContext(session_dir=str(session_dir), student_folder="", uid=None, python=sys.executable,
                                 env=dict(grader_shell_env(), TMPDIR=str(session_dir)),
                                 out=str(session_dir / "live-graph.out.json"), limits=DEFAULT_LIMITS)
        plan = LiveGraphPlan(launch_args=["robot:=false", "arduino:=false", "pad:=virtual"],
                             nodes=list(LIVE_GRAPH_NODES), start_timeout_s=30.0)
        graph = run_session_plan(context, plan, session_dir, 90.0)
    finally:
        shutil.rmtree(session_dir, ignore_errors=True)
    if graph.session_error or graph.problem:
        raise GradingError(f"could not read the lab's live graph: {graph.session_error or graph.problem}")
    _LIVE_GRAPH["graph"] = graph
    if cache_file:
        try:
            Path(cache_file).parent.mkdir(parents=True, exist_ok=True)
            partial = Path(cache_file).with_suffix(f".{os.getpid()}.tmp")
            partial.write_text(json.dumps(graph.to_json(), sort_keys=True), encoding="utf-8")
            partial.replace(cache_file)  # whole or not at all: graders running side by side read it
        except OSError:
            pass  # a read-only home: the graph is computed again next time
    return graph


def graph_of_running_master() -> LiveGraphObservation:
    """The graph on this process's master (ROS_MASTER_URI), once two readings 0.3 s apart agree."""
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
    except MasterApiError as exc:
        raise GradingError(f"no pipeline to compare with: {exc}") from None
    running = {n for _t, names in pubs for n in names} | {n for _t, names in subs for n in names}
    missing = [n for n in LIVE_GRAPH_NODES if n not in running and n not in SENSOR_NODES]
    if not running & set(SENSOR_NODES):
        missing.insert(0, " or ".join(SENSOR_NODES))
    if missing:  # counted, not named: the names are what Ex. 15 asks the student to find
        raise GradingError(f"the pipeline is not running here ({len(missing)} of its {len(LIVE_GRAPH_NODES)} nodes are "
                           "not up; `rosnode list` shows which run): start it first -- at home the cell with "
                           "lab.start_pipeline(), in the lab your launch file (roslaunch hri_lab teleoperation.launch) "
                           "-- then this check")
    return LiveGraphObservation(problem="", publishers={t: sorted(n) for t, n in pubs},
                                subscribers={t: sorted(n) for t, n in subs}, types=types)


@reusable("graph")
def grade_graph(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                graph_cache: Optional[PathLike] = None) -> CheckResult:
    """Ex. 15: the student's nodes, topics and types against the live graph of the lab's pipeline."""
    key = EXERCISE.key
    root, given, found, refused = resolve_deliverable(path, key)
    started = time.monotonic()
    if refused:
        return refused_result(EXERCISE, root, refused, None)
    if found is None:
        return missing_result(EXERCISE, root, None)
    run = CheckRun(EXERCISE.check, root if given is None else given, out_dir, key, given or found)
    try:
        data, facts = run.probe("yaml-load", run.space.file(key), "graph-load", YamlResult)
    finally:
        run.close()
    if data is None:
        error, answer = explain_process(facts, "reading graph.yaml"), None
    else:
        error, answer = data.error, data.data
    parts = compare_graph(answer, live_graph(graph_cache) if not error and isinstance(answer, dict)
                          else LiveGraphObservation(), error)
    return CheckResult(EXERCISE.check, str(found), parts, None, time.monotonic() - started)


EXERCISE = Exercise(key="graph", handout="Ex. 15", assignment="lab", parts=PARTS, grade=grade_graph, session_s=5.0,
                    grade_kwargs=("graph_cache",), batch_cache=live_graph,
                    notebook_calls={"graph": grade_graph}, whole_check_calls=("graph",))
