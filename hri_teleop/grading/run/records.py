"""The typed records the grader's processes hand each other as JSON: plans, observations, results.

Session plans and observations, probe plans and results. Each has ``to_json()`` / ``from_json()``;
reading one with a key missing or unknown raises :class:`RecordError`.
"""

from __future__ import annotations

import dataclasses
import functools
import typing
from dataclasses import dataclass, field
from typing import (
    Any,
    Callable,
    ClassVar,
    Dict,
    Generic,
    List,
    Mapping,
    NamedTuple,
    Optional,
    Protocol,
    Tuple,
    Type,
    TypeVar,
)

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gamepad.events import PadEvent
from hri_teleop.grading.run.gains import TeleopGains
from hri_teleop.grading.run.sandbox import Limits

__all__ = [
    "RecordError", "Record", "Obs", "Message", "Response", "Topic", "ProcessFacts", "NodeFacts", "Observation",
    "ClockedObservation", "LaunchObservation", "TeleopLaunchSimObservation", "SessionContext", "SessionPlan",
    "LaunchPlan", "TeleopLaunchSimPlan", "SessionRequest", "ProbeResult", "RosparamResult", "YamlResult",
    "LaunchNode", "LaunchParseResult", "PartsTick", "PartsCaseResult", "TeleopPartsResult", "PartsPlanTick",
    "PartsPlanCase", "TeleopPartsPlan",
]


class RecordError(HriTeleopError, ValueError):
    """A JSON record lacks keys of its type, has others, or a value of another type: writer and reader differ."""


# -- to and from JSON ---------------------------------------------------------------------------------

class _Dataclass(Protocol):
    __dataclass_fields__: ClassVar[Dict[str, dataclasses.Field[Any]]]


D = TypeVar("D", bound=_Dataclass)
R = TypeVar("R", bound="Record")


def _dump(value: object) -> object:
    """A JSON-able copy: dataclasses as objects, tuples (NamedTuples too) as lists."""
    if isinstance(value, Record):
        return value.to_json()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _dump(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, (list, tuple)):
        return [_dump(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _dump(v) for k, v in value.items()}
    return value


@functools.lru_cache(maxsize=None)
def _hints(cls: type) -> Dict[str, object]:
    return dict(typing.get_type_hints(cls))


def _fields_of(cls: Type[D], data: object, where: str, skip: Tuple[str, ...] = ()) -> D:
    """``cls`` (a dataclass) from a JSON object with exactly its fields' keys (and those in ``skip``)."""
    if not isinstance(data, dict):
        raise RecordError(f"{where}: expected a JSON object, got {type(data).__name__}")
    names = [f.name for f in dataclasses.fields(cls) if f.init]
    missing = [n for n in names if n not in data]
    unknown = sorted(str(k) for k in data if k not in names and k not in skip)
    if missing or unknown:
        found = [f"missing key(s) {', '.join(missing)}"] if missing else []
        found += [f"unknown key(s) {', '.join(unknown)}"] if unknown else []
        raise RecordError(f"{where}: {'; '.join(found)}")
    hints = _hints(cls)
    make: Callable[..., D] = cls
    return make(**{n: _load(hints[n], data[n], f"{where}.{n}") for n in names})


def _load(hint: object, value: object, where: str) -> object:
    """``value`` read from JSON as ``hint`` says: records, NamedTuples, lists, dicts, Optional, scalars."""
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is Any or hint is object:
        return value
    if isinstance(hint, type) and issubclass(hint, Record):
        return hint.from_json(value, where)
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return _fields_of(hint, value, where)
    if isinstance(hint, type) and issubclass(hint, tuple):  # a NamedTuple
        hints = _hints(hint)  # the NamedTuple's fields, in order
        names = tuple(hints)
        if not isinstance(value, list) or len(value) != len(names):
            raise RecordError(f"{where}: expected a list of {len(names)} ({', '.join(names)}), got {value!r:.80}")
        make: Callable[..., object] = hint
        return make(*(_load(hints[n], v, f"{where}.{n}") for n, v in zip(names, value)))
    if origin is typing.Union:
        if value is None and type(None) in args:
            return None
        (inner,) = [a for a in args if a is not type(None)]
        return _load(inner, value, where)
    if origin is list:
        if not isinstance(value, list):
            raise RecordError(f"{where}: expected a list, got {type(value).__name__}")
        return [_load(args[0], v, f"{where}[{i}]") for i, v in enumerate(value)]
    if origin is dict:
        if not isinstance(value, dict):
            raise RecordError(f"{where}: expected a JSON object, got {type(value).__name__}")
        return {k: _load(args[1], v, f"{where}[{k!r}]") for k, v in value.items()}
    return _scalar(hint, value, where)


def _scalar(hint: object, value: object, where: str) -> object:
    if hint is float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    elif hint is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(hint, type) and isinstance(value, hint)
    if not ok:
        raise RecordError(f"{where}: expected {getattr(hint, '__name__', hint)}, got {value!r:.80}")
    return value  # an int stays one where a float is expected, as it was written


@dataclass(frozen=True)
class Record:
    """A frozen dataclass written and read as a JSON object (with ``kind`` when its class has a KIND)."""

    KIND: ClassVar[str] = ""

    def to_json(self) -> Dict[str, object]:
        data: Dict[str, object] = {"kind": self.KIND} if self.KIND else {}
        data.update((f.name, _dump(getattr(self, f.name))) for f in dataclasses.fields(self))
        return data

    @classmethod
    def from_json(cls: Type[R], data: object, where: str = "") -> R:
        where = where or cls.__name__
        if cls.KIND:
            kind = data.get("kind") if isinstance(data, dict) else None
            if kind != cls.KIND:
                raise RecordError(f"{where}: kind {kind!r}, expected {cls.KIND!r}")
        return _fields_of(cls, data, where, ("kind",) if cls.KIND else ())


# -- what sessions and probes report about a process ----------------------------------------------------

class Message(NamedTuple):
    """One recorded message: when (s), its type, its decoded value."""

    t_s: float
    kind: str
    value: Any


class Response(NamedTuple):
    """One message that came back for a count: its type and decoded value."""

    kind: str
    value: Any


class Topic(NamedTuple):
    name: str
    type: str


@dataclass(frozen=True)
class ProcessFacts(Record):
    """How a student process (a probe, a node, roslaunch) ended and what it printed last."""

    exit_code: Optional[int] = None
    output_tail: str = ""
    output_bytes: int = 0
    problem: str = ""
    exited_by_itself: bool = False


@dataclass(frozen=True)
class NodeFacts(ProcessFacts):
    """A student's node as the master saw it: its names and the topics it subscribed and advertised."""

    started: bool = False
    nodes: List[str] = field(default_factory=list)
    subscriptions: List[Topic] = field(default_factory=list)
    publications: List[Topic] = field(default_factory=list)


# -- observations: what a session saw (python -m hri_teleop.grading.session) ---------------------

@dataclass(frozen=True)
class Observation(Record):
    """What every session reports: why it failed (``session_error``, empty when it did not) and the
    wall seconds from its start to each phase."""

    session_error: str = ""
    traceback: str = ""
    phases_s: Dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class ClockedObservation(Observation):
    """A session of student nodes: why they could not be observed, and the clock they ran on
    ("grader" or "real time")."""

    problem: str = ""
    clock: str = ""


@dataclass(frozen=True)
class LaunchObservation(ClockedObservation):
    """A student's launch file run by roslaunch: what the grader supplied, the nodes and types seen."""

    supplied: List[str] = field(default_factory=list)
    nodes: List[str] = field(default_factory=list)
    types: Dict[str, str] = field(default_factory=dict)
    launch: ProcessFacts = field(default_factory=ProcessFacts)


@dataclass(frozen=True)
class TeleopLaunchSimObservation(LaunchObservation):
    KIND: ClassVar[str] = "teleop-launch-sim"

    quit_in_time: bool = False
    run_s: float = 0.0
    teleop_publications: List[Topic] = field(default_factory=list)
    publishers: Dict[str, List[str]] = field(default_factory=dict)
    subscribers: Dict[str, List[str]] = field(default_factory=dict)
    messages: Dict[str, List[Message]] = field(default_factory=dict)
    lab_sim_log: str = ""


Obs = TypeVar("Obs", bound=Observation)


# -- plans: what a session is to do ---------------------------------------------------------------------

@dataclass(frozen=True)
class SessionContext(Record):
    """Where and as whom a session runs; ``out`` is its observation's file."""

    session_dir: str
    student_folder: str
    uid: Optional[int]
    python: str
    env: Dict[str, str]
    out: str
    limits: Limits
    #: the reference guard's policy for its student processes (student_guard; "" for none)
    guard: str = ""


@dataclass(frozen=True)
class SessionPlan(Record, Generic[Obs]):
    """What every plan has; each kind of plan names the kind of observation it gets back."""

    start_timeout_s: float

    def observation_type(self) -> Type[Obs]:
        raise NotImplementedError


@dataclass(frozen=True)
class LaunchPlan(SessionPlan[Obs]):
    """A student's launch file, run on the grader's clock or in real time (``clock``)."""

    launch_file: str
    set_max_sensor_force: Optional[int]
    clock: str
    settle_timeout_s: float
    expect_nodes: List[str]


@dataclass(frozen=True)
class TeleopLaunchSimPlan(LaunchPlan[TeleopLaunchSimObservation]):
    KIND: ClassVar[str] = "teleop-launch-sim"

    params_launch: str
    teleop_node: str
    twist_topic: str
    supply: Dict[str, List[str]]
    lab_sim: List[str]
    record: List[str]
    run_s: float
    applied_topic: str
    sensor_chain: List[str]
    default_rate_hz: float

    def observation_type(self) -> Type[TeleopLaunchSimObservation]:
        return TeleopLaunchSimObservation



@dataclass(frozen=True)
class _RequestJson:
    context: object
    plan: object


@dataclass(frozen=True)
class SessionRequest:
    """The file a session starts from: where it runs and its plan (of any kind)."""

    context: SessionContext
    plan: SessionPlan[Any]

    def to_json(self) -> Dict[str, object]:
        return {"context": self.context.to_json(), "plan": self.plan.to_json()}

    @classmethod
    def from_json(cls, data: object, plan_types: Mapping[str, Type[SessionPlan[Any]]]) -> SessionRequest:
        """Read a request whose plan is one of ``plan_types`` (kind -> plan type: the sessions' registry)."""
        where = cls.__name__
        raw = _fields_of(_RequestJson, data, where)
        kind = raw.plan.get("kind") if isinstance(raw.plan, dict) else None
        if not isinstance(kind, str) or kind not in plan_types:
            raise RecordError(f"{where}.plan: kind {kind!r}, expected one of {', '.join(plan_types)}")
        return cls(SessionContext.from_json(raw.context, f"{where}.context"),
                   plan_types[kind].from_json(raw.plan, f"{where}.plan"))


# -- probes: what python -m hri_teleop.grading.run.probe reports ----------------------------------------

@dataclass(frozen=True)
class ProbeResult(Record):
    """``ok``: the file loaded (or imported); else ``error`` says why not."""

    ok: bool = False
    error: str = ""


@dataclass(frozen=True)
class RosparamResult(ProbeResult):
    """``rosparam load FILE``: the parameters, merged into '/' (YAML's types kept)."""

    params: Dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class RosparamCommandsResult(ProbeResult):
    """A notebook's ``rosparam`` commands worked out on a fresh server (:mod:`hri_teleop.core.rosparam_model`):
    the tree they leave, each dump (``file``, ``namespace``, ``keys``: the dumped tree's top-level names) and a
    note for each command that fails as rosparam would."""

    tree: Dict[str, Any] = field(default_factory=dict)
    dumps: List[Dict[str, Any]] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)


@dataclass(frozen=True)
class YamlResult(ProbeResult):
    """A student's YAML (graph.yaml) read with the bounded safe loader: its one document as plain data
    (mapping keys as strings; ``{"__repr__": ...}`` for what JSON has no type for)."""

    data: Any = None


@dataclass(frozen=True)
class LaunchNode(Record):
    """A <node> of a launch file as roslaunch's loader resolves it (``type``: the script)."""

    name: str
    namespace: str
    package: str
    type: str
    args: str = ""
    required: bool = False
    remap: List[List[str]] = field(default_factory=list)

    @property
    def full_name(self) -> str:
        """The node's ROS name, ``/ns/name``."""
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class LaunchParseResult(ProbeResult):
    """A launch file as roslaunch's XmlLoader resolves it: its nodes, parameters and files."""

    nodes: List[LaunchNode] = field(default_factory=list)
    params: Dict[str, Any] = field(default_factory=dict)
    files: List[str] = field(default_factory=list)
    errors: List[str] = field(default_factory=list)


@dataclass(frozen=True)
class PartsTick(Record):
    """The student's Teleoperation object after one tick: each attribute as read (a number, a
    list, or ``{"__repr__": ...}`` / ``{"__missing__": name}`` for what is not one)."""

    gripper_width: Any
    rotation_mode: Any
    cartesian_velocity: Any
    rumble: Any


@dataclass(frozen=True)
class PartsCaseResult(Record):
    """One case of the teleop-parts probe: the ticks, and each method's first error and its tick."""

    label: str
    ticks: List[PartsTick] = field(default_factory=list)
    errors: Dict[str, str] = field(default_factory=dict)
    error_ticks: Dict[str, int] = field(default_factory=dict)
    construct_error: str = ""


@dataclass(frozen=True)
class TeleopPartsResult(ProbeResult):
    cases: List[PartsCaseResult] = field(default_factory=list)


@dataclass(frozen=True)
class PartsPlanTick(Record):
    """The pad events of one tick and the force set before the tick's updates."""

    events: List[PadEvent]
    force: float


@dataclass(frozen=True)
class PartsPlanCase(Record):
    label: str
    gains: TeleopGains
    ticks: List[PartsPlanTick]


@dataclass(frozen=True)
class TeleopPartsPlan(Record):
    """What the teleop-parts probe drives the student's Teleoperation object through."""

    cases: List[PartsPlanCase]
