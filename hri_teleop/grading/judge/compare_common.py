"""What every judge shares: message helpers, tolerances, and what a process' output says.

A process' output tells its exit, a crash, a write refused by the sandbox. Each exercise's parts and
points live in its own module.
"""

from __future__ import annotations

import math
import re
from typing import Any, Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.results import Part, not_judged
from hri_teleop.grading.run.records import ProcessFacts
from hri_teleop.grading.run.sandbox import OUTPUT_CAP_BYTES, describe_exit

#: Values on /force_mapped must be within this of the reference (Float32 carries ~7 digits).
TOLERANCE = 1e-6
TWIST_TOLERANCE = 1e-9

STUDENT_PACKAGES = ("hri_lab", "ros_intro")  # the handout has Ex. 2-6 done in ros_intro


def judged_part(table: Dict[str, Tuple[str, float]], key: str, passed: bool, message: str = "",
          plots: Sequence[str] = (), note: str = "") -> Part:
    name, points = table[key]
    return Part(name, points, passed, message, tuple(plots), note)


def not_judged_part(table: Dict[str, Tuple[str, float]], key: str, reason: str) -> Part:
    name, points = table[key]
    return not_judged(name, points, reason)


def fmt_value(value: Any) -> str:
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict) and "__repr__" in value:
        return str(value["__repr__"])
    if isinstance(value, dict) and "__missing__" in value:
        return f"no attribute {value['__missing__']}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(fmt_value(v) for v in value) + "]"
    return repr(value)


def as_float(value: Any) -> Optional[float]:
    if isinstance(value, bool) or value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


# -- what a process' output says ------------------------------------------------------------

_WRITE_ERROR = re.compile(r"(Read-only file system|Permission denied)\S*:?\s*'?([^'\n]*)")
#: A file outside the student's folder: not there at all while grading (the box shows the system, not the machine).
_ABSENT = re.compile(r"FileNotFoundError: \[Errno 2\] No such file or directory: '(/[^'\n]*)'")


def process_hints(facts: ProcessFacts) -> List[str]:
    """Student-readable reasons found in a process' exit and output (limits, writes outside...)."""
    tail = facts.output_tail
    hints: List[str] = []
    if facts.output_bytes >= OUTPUT_CAP_BYTES - 1024:
        hints.append(f"it printed more than the output limit of {OUTPUT_CAP_BYTES // (1024 * 1024)} MB and was "
                     "stopped: remove prints inside loops")
    match = _WRITE_ERROR.search(tail)
    if match:
        where = match.group(2).strip() or "a file"
        hints.append(f"it tried to write {where} outside its own folder: while grading (and on the lab PCs) "
                     "write only inside your package folder")
    absent = _ABSENT.search(tail)
    if absent and not match:
        hints.append(f"{absent.group(1)} is not there while grading, as nothing outside its own folder is: read and "
                     "write only inside your package folder (find it with rospkg or relative to __file__)")
    if "Resource temporarily unavailable" in tail or "can't start new thread" in tail:
        hints.append("it tried to start more processes or threads than allowed: do not fork or spawn in a loop")
    if "MemoryError" in tail or "Cannot allocate memory" in tail:
        hints.append("it used more memory than allowed (2 GB)")
    if "NotImplementedError" in tail:
        hints.append("a part marked YOUR CODE HERE still raises NotImplementedError: fill it in")
    return hints


#: The grader's workspace in a process' output: the student's files are named from their package instead.
_WORKSPACE_PATH = re.compile(r"/[^\s\"']*/ws/(?:hri_lab|ros_intro)/")


def _last_lines(text: str, n: int = 6) -> str:
    lines = [line for line in _WORKSPACE_PATH.sub("", str(text)).strip().splitlines() if line.strip()]
    return "\n".join("    " + line[:300] for line in lines[-n:])


def with_box_hints(crash_message: str, facts: ProcessFacts, what: str) -> str:
    """A crash's feedback, and what the box says about it: a write outside its folder, a fork loop at the process
    limit (the crash's own lines alone would not say why the call failed while grading)."""
    hints = [h for h in process_hints(facts) if "NotImplementedError" not in h]
    crowded = facts.problem if "processes and threads" in facts.problem else ""
    return (crash_message + ("\nhint: " + "; ".join(hints) if hints else "")
            + (f"\n{what} {crowded}" if crowded else ""))


def explain_process(facts: ProcessFacts, what: str) -> str:
    """'<what> <problem>. <hints>. Its last output: ...'"""
    problem = facts.problem or describe_exit(facts.exit_code)
    message = f"{what} {problem}"
    hints = process_hints(facts)
    if hints:
        message += "; " + "; ".join(hints)
    tail = _last_lines(facts.output_tail)
    if tail:
        message += "\n  its last output:\n" + tail
    return message
