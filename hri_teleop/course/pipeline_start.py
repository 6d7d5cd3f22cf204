"""Starting Ex. 15's pipeline: when it has settled, and, when a node of it ended, why -- in one message.

The pipeline runs the student's own ``mapping_node.py`` and ``teleoperation.py`` (in the student
bundle) beside the lab's provided nodes. A node that ends while the pipeline starts is named with
what to do: a file that is still the template names the exercise to finish first, a crash shows the
node's own last traceback lines. The graph has settled when the master has every registration the
pipeline's nodes make; it is asked of the master, and what it expects is never shown (drawing
that graph is the student's exercise).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Iterable, List, Mapping, Optional, Sequence, Set, Tuple

__all__ = ["PIPELINE_WIRING", "STUDENT_GRACE_S", "registrations", "lab_nodes_settled", "students_registered", "settled", "crash_lines", "template_exercise", "explain_ended",
           "without_terminal_titles"]

#: (topic, publishing node, subscribing node) of the pipeline without hardware.
PIPELINE_WIRING: Tuple[Tuple[str, str, str], ...] = (
    ("/pub_force", "/FSR_sensor", "/mapping_node"),
    ("/force_mapped", "/mapping_node", "/teleoperation"),
    ("/gripper_width", "/teleoperation", "/gripper_manager"),
)

#: Once the lab's nodes are up, how long a student node may take to register both a publisher and a
#: subscriber (one that never subscribes, say, is then drawn as it is rather than failing the start).
STUDENT_GRACE_S = 5.0

#: The exercises that write a student node, for a template whose unfinished part names none.
NODE_EXERCISES = {"mapping_node.py": "Ex. 5", "teleoperation.py": "Ex. 8 and 9"}

Registration = Tuple[str, str, str]  # (topic, node, "pub" | "sub")

_TITLE = re.compile(r"\x1b\][^\x07\x1b]*(?:\x07|\x1b\\)")
_FRAME = re.compile(r'^\s*File "(?P<file>[^"]+)", line (?P<line>\d+), in (?P<func>\S+)')
_EXERCISE = re.compile(r"\bEx\. ?(\d+)")


def without_terminal_titles(text: str) -> str:
    """``text`` without terminal-title escapes (ESC ] ... BEL), which a notebook shows as boxes."""
    return _TITLE.sub("", text)


def registrations(state: Sequence[Any]) -> Set[Registration]:
    """Every (topic, node, pub/sub) of a master's ``getSystemState``."""
    found: Set[Registration] = set()
    for kind, section in (("pub", state[0]), ("sub", state[1])):
        for topic, nodes in section:
            found.update((topic, node, kind) for node in nodes)
    return found


def lab_nodes_settled(state: Sequence[Any], student_nodes: Iterable[str] = (),
                      wiring: Sequence[Tuple[str, str, str]] = PIPELINE_WIRING) -> bool:
    """True when the lab's nodes (all but ``student_nodes``) have made every registration of ``wiring``."""
    found = registrations(state)
    students = set(student_nodes)
    expected = {(topic, pub, "pub") for topic, pub, _sub in wiring} | {(topic, sub, "sub") for topic, _pub, sub in wiring}
    return all(reg in found for reg in expected if reg[1] not in students)


def students_registered(state: Sequence[Any], student_nodes: Iterable[str]) -> bool:
    """True when each student node has a publisher and a subscriber at the master, whatever their topics
    (a student's node may use other topics than the lab's)."""
    found = registrations(state)
    return all({kind for _topic, who, kind in found if who == node} == {"pub", "sub"} for node in student_nodes)


def settled(state: Sequence[Any], student_nodes: Iterable[str] = (),
            wiring: Sequence[Tuple[str, str, str]] = PIPELINE_WIRING) -> bool:
    """True when every registration of the pipeline's nodes is at the master: the lab's nodes' of
    ``wiring``, and a publisher and a subscriber of each student node."""
    students = list(student_nodes)
    return lab_nodes_settled(state, students, wiring) and students_registered(state, students)


def _traceback(output: str) -> List[str]:
    lines = output.splitlines()
    starts = [i for i, line in enumerate(lines) if line.startswith("Traceback (most recent call last)")]
    return lines[starts[-1] + 1:] if starts else []


def _frames(trace: List[str]) -> List[Tuple[str, int, str, List[str]]]:
    """(file, line, function, the frame's lines) of a traceback's body, in order."""
    frames: List[Tuple[str, int, str, List[str]]] = []
    for line in trace:
        match = _FRAME.match(line)
        if match:
            frames.append((match.group("file"), int(match.group("line")), match.group("func"), [line]))
        elif frames and line.startswith("    "):
            frames[-1][3].append(line)
    return frames


def _exception(trace: List[str]) -> List[str]:
    tail: List[str] = []
    for line in reversed(trace):
        if not line.strip() or line.startswith(" "):
            break
        tail.insert(0, line)
    return tail


def crash_lines(output: str, script: Optional[Path] = None, keep: int = 6) -> List[str]:
    """The node's own last traceback lines: the frames in ``script`` (all frames if none is) and the
    exception; without a traceback the last ``keep`` lines it printed."""
    trace = _traceback(output)
    if not trace:
        return [line for line in output.splitlines() if line.strip()][-keep:]
    frames = _frames(trace)
    own = [f for f in frames if script is not None and Path(f[0]).name == script.name] or frames[-1:]
    shown: List[str] = []
    for file, _line, _func, lines in own[-2:]:
        shown.extend([lines[0].replace(file, Path(file).name)] + lines[1:])
    return shown + _exception(trace)


def template_exercise(output: str, script: Path) -> Optional[str]:
    """"Ex. N" to finish first when ``script`` ended on a part still marked YOUR CODE HERE, else None."""
    trace = _traceback(output)
    if not any(line.startswith("NotImplementedError") for line in _exception(trace)):
        return None
    inside = [f for f in _frames(trace) if Path(f[0]).name == script.name]
    if inside and script.is_file():
        lines = script.read_text(errors="replace").splitlines()
        stop = inside[-1][1]
        start = max((i for i in range(min(stop, len(lines))) if lines[i].lstrip().startswith("def ")), default=0)
        named = _EXERCISE.findall("\n".join(lines[start:stop]))
        if named:
            return f"Ex. {named[-1]}"
    return NODE_EXERCISES.get(script.name, "the exercise that writes it")


def _one(name: str, process: Any, script: Optional[Path]) -> str:
    output = without_terminal_titles(process.output())
    code = process.popen.returncode if hasattr(process, "popen") else None
    node = name if name.endswith(".launch") else f"/{name.lstrip('/')}"
    lines = crash_lines(output, script)
    detail = "\n".join("    " + line.rstrip()[:300] for line in lines)
    detail = f"\n  its last lines:\n{detail}" if detail else ""
    exercise = template_exercise(output, script) if script is not None else None
    if script is not None and exercise:
        return (f"{node} ended: {script.name} is still the template (a part marked YOUR CODE HERE raises "
                f"NotImplementedError): finish {exercise} first, then run this cell again{detail}")
    what = f"{script.name} crashed" if script is not None and _traceback(output) else "it ended"
    status = f" (exit status {code})" if code not in (None, 0) else ""
    fix = f": fix {script.name} (its check cell judges it), then run this cell again" if script is not None else ""
    return f"{node} ended while starting{status}: {what}{fix}{detail}"


def explain_ended(processes: Mapping[str, Any], scripts: Optional[Mapping[str, Path]] = None) -> str:
    """One message naming each node of ``processes`` that ended, and what to do about it."""
    scripts = scripts or {}
    parts = [_one(name, processes[name], scripts.get(name)) for name in ended_nodes(processes)]
    return "the pipeline did not start: " + "\n".join(parts) + "\n(everything the pipeline started is stopped)"


def ended_nodes(processes: Mapping[str, Any]) -> List[str]:
    """The names of ``processes`` that no longer run."""
    return [name for name, process in processes.items() if not process.running]
