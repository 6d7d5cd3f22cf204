"""What runs inside a student sandbox: load, parse or import a student's file, report as JSON.

Started isolated by the grader (``python -I``: :func:`hri_teleop.grading.judge.harness.isolated_module_argv`)
as ``probe rosparam-load|yaml-load FILE OUT``, ``probe launch-parse FILE OUT [name:=value ...]``,
``probe rosparam-commands COMMANDS OUT`` or ``probe teleop-parts FILE PLAN OUT``; never in the grader's own process (docs/grading-internals.md).
YAML goes through the bounded safe loader (:func:`hri_teleop.core.yamlfile.load_bounded_all`): no
Python tags, no eval, no alias blow-up.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import sys
import traceback
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import yaml

from hri_teleop.core.rosparam_model import file_reader, work_out, yaml_reader
from hri_teleop.core.yamlfile import BoundedYamlError, disarm_rosparam_tags, load_bounded, load_bounded_all
from hri_teleop.grading.run.records import (
    LaunchNode,
    LaunchParseResult,
    PartsCaseResult,
    PartsTick,
    ProbeResult,
    RosparamCommandsResult,
    RosparamResult,
    TeleopPartsPlan,
    TeleopPartsResult,
    YamlResult,
)
from hri_teleop.grading.run.student_guard import install as install_guard
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular

__all__ = ["main"]


def _plain(value: Any) -> Any:
    """A JSON-able copy that keeps YAML's int/float/bool/str distinction."""
    if isinstance(value, (bool, int, str)) or value is None:
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return {"__repr__": repr(value)[:200], "__type__": type(value).__name__}


def _write(out: Path, result: ProbeResult) -> None:
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result.to_json(), sort_keys=True), encoding="utf-8")


def _one_line(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}".strip()
    return " ".join(text.split())[:600]


#: graph.yaml lists a few nodes and topics.
GRAPH_CAP_BYTES = 100_000


def _rosparam_documents(path: Path) -> List[Tuple[Any, str]]:
    """What ``rosparam.load_file(path, default_namespace="/")`` returns -- each document and its namespace,
    ``_ns`` taken out -- read by the bounded loader instead of rosparam's, whose ``!radians`` runs eval."""
    from rosgraph.names import ns_join  # noqa: PLC0415 - the probe imports only what its command needs

    text = read_regular(path).decode("utf-8")
    documents = []
    for doc in load_bounded_all(text):
        if "_ns" in doc:  # rosparam's own test: a document that is None or a number fails here as there
            namespace = ns_join("/", doc.get("_ns", None))
            del doc["_ns"]
        else:
            namespace = "/"
        documents.append((doc, namespace))
    return documents


def rosparam_load(path: Path) -> RosparamResult:
    """``rosparam load FILE`` without a master, merged into '/': rosparam's reading (its tags, ``_ns``, several
    documents) through the bounded safe loader, so nothing in the file runs and no alias blows up."""
    try:
        loaded = _rosparam_documents(path)
    except Exception as exc:  # noqa: BLE001 - YAML, decoding, bounds, rosparam's type errors: "does not load"
        return RosparamResult(error=_one_line(exc))
    merged: Dict[str, Any] = {}
    for values, namespace in loaded:
        if not isinstance(values, dict):
            return RosparamResult(error=f"the top level is a {type(values).__name__}, not `key: value` lines")
        target = merged
        for part in [p for p in str(namespace).split("/") if p]:
            target = target.setdefault(part, {})
        target.update(values)
    return RosparamResult(ok=True, params=_plain(merged))


#: A file a notebook's command loads (robot_params.yaml is a few hundred bytes).
COMMAND_FILE_CAP_BYTES = 256 * 1024
_NOTES_KEPT = 20


def rosparam_commands(path: Path) -> RosparamCommandsResult:
    """A notebook's rosparam commands (``{"commands": [argv, ...]}`` in ``path``, written by the grader) worked
    out on a fresh server; the files they load are read from this folder as submitted files are."""
    try:
        data = json.loads(read_regular(path, COMMAND_FILE_CAP_BYTES * 4).decode("utf-8"))
        commands = [[str(a) for a in argv] for argv in data["commands"]]
        refused = {str(k): str(v) for k, v in dict(data.get("refused", {})).items()}
    except (OSError, ValueError, KeyError, TypeError) as exc:
        return RosparamCommandsResult(error=_one_line(exc))
    root = Path.cwd()

    def read(name: str) -> bytes:
        """As any submitted file (no link, no FIFO, capped); the messages name it from the student's folder."""
        if name in refused:
            raise OSError(refused[name])
        if not os.path.lexists(root / name):
            raise FileNotFoundError(name)
        try:
            return read_regular(root / name, COMMAND_FILE_CAP_BYTES, root=root)
        except UntrustedFileError as exc:
            raise OSError(str(exc).replace(f"{root}/", "")) from None

    tree, dumps, notes = work_out(commands, yaml_reader(load_bounded_all, (yaml.YAMLError, BoundedYamlError)),
                                  file_reader(read))
    return RosparamCommandsResult(ok=True, tree=_plain(tree), dumps=dumps, notes=notes[:_NOTES_KEPT])


def yaml_load(path: Path) -> YamlResult:
    """A student's graph.yaml through the bounded safe loader (one document), or why it cannot be read."""
    try:
        text = read_regular(path, GRAPH_CAP_BYTES).decode("utf-8")
    except UntrustedFileError as exc:
        if "larger than" in str(exc):
            return YamlResult(error=f"{path.name} is larger than {GRAPH_CAP_BYTES // 1000} kB; list only the "
                                    "pipeline's nodes and topics")
        return YamlResult(error=f"{path.name} cannot be read ({exc})")
    except UnicodeDecodeError as exc:
        return YamlResult(error=f"{path.name} cannot be read ({exc})")
    try:
        data = load_bounded(text)
    except BoundedYamlError as exc:
        return YamlResult(error=f"{path.name}: {exc}")
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        return YamlResult(error=f"{path.name} line {mark.line + 1 if mark else '?'}: {getattr(exc, 'problem', exc)}; "
                                "fix the YAML syntax")
    return YamlResult(ok=True, data=_plain(data))


def launch_parse(path: Path, args: Sequence[str]) -> LaunchParseResult:
    """roslaunch's own XmlLoader: the nodes, parameters and files a launch file resolves to."""
    import roslaunch.config  # noqa: PLC0415 - the probe imports only what its command needs
    import roslaunch.xmlloader  # noqa: PLC0415 - the probe imports only what its command needs
    import rosparam  # noqa: F401, PLC0415 - roslaunch imports it at the first <rosparam>, registering its tags

    disarm_rosparam_tags()  # then a <rosparam> block's !radians is arithmetic, not rosparam's eval

    config = roslaunch.config.ROSLaunchConfig()
    loader = roslaunch.xmlloader.XmlLoader(resolve_anon=False)
    try:
        loader.load(str(path), config, argv=["roslaunch", *args], verbose=False)
    except Exception as exc:  # noqa: BLE001 - XmlParseException, ResourceNotFound, SubstitutionException...
        return LaunchParseResult(error=_one_line(exc))
    nodes = [LaunchNode(name=n.name, namespace=n.namespace, package=n.package, type=n.type, args=n.args,
                        required=bool(n.required), remap=[list(r) for r in n.remap_args]) for n in config.nodes]
    params = {name: _plain(p.value) for name, p in config.params.items()}
    return LaunchParseResult(ok=True, nodes=nodes, params=params, files=list(config.roslaunch_files),
                             errors=list(config.config_errors))


# -- the student's parts of teleoperation.py -------------------------------------------------

_READS = ("gripper_width", "rotation_mode", "cartesian_velocity", "rumble")
_METHODS = ("update_gripper_width", "update_cartesian_velocity", "update_rumble")


def _number(value: Any) -> Any:
    if isinstance(value, bool):
        return value
    try:
        number = float(value)
    except (TypeError, ValueError):
        return {"__repr__": repr(value)[:100]}
    return number if math.isfinite(number) else repr(number)


def _read(obj: Any, name: str) -> Any:
    if not hasattr(obj, name):
        return {"__missing__": name}
    value = getattr(obj, name)
    if name == "cartesian_velocity":
        try:
            return [_number(v) for v in list(value)]
        except TypeError:
            return {"__repr__": repr(value)[:100]}
    if name == "rotation_mode":
        return value if isinstance(value, bool) else {"__repr__": repr(value)[:100]}
    return _number(value)


def _import_student(path: Path) -> Any:
    spec = importlib.util.spec_from_file_location("student_teleoperation", str(path))
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot import {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules["student_teleoperation"] = module
    spec.loader.exec_module(module)
    return module


def teleop_parts(path: Path, plan: TeleopPartsPlan) -> TeleopPartsResult:
    """Drive the student's Teleoperation object tick by tick through each case's events."""
    try:
        module = _import_student(path)
    except SystemExit as exc:
        return TeleopPartsResult(error=f"the file called sys.exit({exc.code!r}) while being imported; "
                                       "keep the start of the node under `if __name__ == \"__main__\":`")
    except BaseException as exc:  # noqa: BLE001 - anything the student's top level raises
        tb = traceback.extract_tb(exc.__traceback__)
        line = next((f" (line {f.lineno})" for f in reversed(tb) if f.filename == str(path)), "")
        return TeleopPartsResult(error=f"importing the file failed{line}: {_one_line(exc)}")
    cls = getattr(module, "Teleoperation", None)
    if cls is None:
        return TeleopPartsResult(error="the file has no class Teleoperation; keep the template's class name")
    cases: List[PartsCaseResult] = []
    for case in plan.cases:
        try:
            obj = cls(**case.gains.as_dict())
        except BaseException as exc:  # noqa: BLE001 - a student's constructor may raise anything
            cases.append(PartsCaseResult(case.label, construct_error=_one_line(exc)))
            continue
        result = PartsCaseResult(case.label)
        for index, tick in enumerate(case.ticks):
            for event in tick.events:
                try:
                    obj.handle_event(event)
                except BaseException as exc:  # noqa: BLE001 - toggle_mode raises from here
                    toggle = event.type == "JOYBUTTONDOWN" and event.button == "north"
                    _first_error(result, "toggle_mode" if toggle else "handle_event", exc, index)
            try:
                obj.force = tick.force
            except BaseException:  # noqa: BLE001 - a property without setter
                pass
            for method in _METHODS:
                try:
                    getattr(obj, method)()
                except BaseException as exc:  # noqa: BLE001 - a student's method may raise anything
                    _first_error(result, method, exc, index)
            result.ticks.append(PartsTick(**{name: _read(obj, name) for name in _READS}))
        cases.append(result)
    return TeleopPartsResult(ok=True, cases=cases)


def _first_error(result: PartsCaseResult, where: str, exc: BaseException, tick: int) -> None:
    """Keep the first error of ``where`` (a method, or handle_event) and the tick it came at."""
    if where not in result.errors:
        result.errors[where] = _one_line(exc)
        result.error_ticks[where] = tick


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    command, target = args[0], Path(args[1])
    install_guard()  # before anything of the student's is read: -I skips the sitecustomize that would
    if command == "rosparam-load":
        _write(Path(args[2]), rosparam_load(target))
    elif command == "yaml-load":
        _write(Path(args[2]), yaml_load(target))
    elif command == "rosparam-commands":
        _write(Path(args[2]), rosparam_commands(target))
    elif command == "launch-parse":
        _write(Path(args[2]), launch_parse(target, args[3:]))
    elif command == "teleop-parts":
        plan = TeleopPartsPlan.from_json(json.loads(Path(args[2]).read_text(encoding="utf-8")))
        out = Path(args[3])
        _write(out, teleop_parts(target, plan))
    else:
        print(f"unknown probe {command!r}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
