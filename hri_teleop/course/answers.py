"""``hand_in``: an autograded cell hands the student's values out as plain data; the grader judges them.

The cell's output carries the values as JSON under the course's own MIME type
(:data:`hri_teleop.grading.judge.notebook_answers.MIME`) beside a line of text. After nbgrader's autograde the
grader applies the cell's rule to that output in its own process (:mod:`hri_teleop.grading.batch.notebook_judge`):
nothing the kernel decides gives a point. At home ``hand_in`` runs the same rule, so the student sees the verdict
(a wrong answer: one line saying why). Ex. 3 and 4's values are worked out from the cells this kernel ran
(:mod:`hri_teleop.core.rosparam_model`), as in the grader, not read back from the server. Runs on Python 3.8.
"""

from __future__ import annotations

import json
import math
from typing import Any, Dict, List

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.course.errors import CourseError
from hri_teleop.grading.judge.notebook_answers import (
    COMMAND_CELLS,
    MAX_ANSWER_BYTES,
    MIME,
    command_values,
    has_rule,
    judge,
)

__all__ = ["hand_in", "plain", "WrongAnswer"]

_MAX_TEXT = 2000      # characters of one string handed in
_MAX_ITEMS = 1000     # items of one list or dict
_MAX_DEPTH = 8        # nesting of lists and dicts
_SHOWN = 60           # characters of one value in the cell's text


class WrongAnswer(HriTeleopError, AssertionError):
    """The rule of the cell says no: one line naming the cause and what to do (no traceback)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


def plain(value: Any, depth: int = 0) -> Any:
    """``value`` as JSON data (numbers, strings, lists, dicts, bools, None), bounded.

    numpy scalars and arrays become their Python values; a NaN or infinity its text ("nan");
    anything else its ``repr``, cut short. Long strings, lists and dicts are cut at a bound.
    """
    if value is None or isinstance(value, (bool, str)):
        return value[:_MAX_TEXT] if isinstance(value, str) else value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        return float(value) if math.isfinite(value) else repr(float(value))
    if depth >= _MAX_DEPTH:
        return repr(value)[:_SHOWN]
    if isinstance(value, dict):
        return {str(k)[:_MAX_TEXT]: plain(v, depth + 1) for k, v in list(value.items())[:_MAX_ITEMS]}
    if isinstance(value, (list, tuple)):
        return [plain(v, depth + 1) for v in list(value)[:_MAX_ITEMS]]
    for convert in ("item", "tolist"):  # numpy scalars, then arrays
        method = getattr(value, convert, None)
        if callable(method):
            try:
                return plain(method(), depth + 1)
            except (TypeError, ValueError):
                continue
    return repr(value)[:_SHOWN]


def _shown(values: Dict[str, Any]) -> str:
    parts = []
    for name, value in values.items():
        text = json.dumps(value, ensure_ascii=False) if not isinstance(value, float) else f"{value:g}"
        parts.append(f"{name} = {text if len(text) <= _SHOWN else text[:_SHOWN - 3] + '...'}")
    return ", ".join(parts) or "nothing"


def _publish(payload: Dict[str, Any], text: str) -> None:
    try:
        from IPython import get_ipython  # noqa: PLC0415 - only in a kernel
        from IPython.display import publish_display_data  # noqa: PLC0415 - as above
    except ImportError:
        print(text)
        return
    if get_ipython() is None:
        print(text)
        return
    publish_display_data({MIME: payload, "text/plain": text})


_FILE_CAP_BYTES = 256 * 1024


def _read_capped(name: str) -> bytes:
    with open(name, "rb") as fh:
        data = fh.read(_FILE_CAP_BYTES + 1)
    if len(data) > _FILE_CAP_BYTES:
        raise OSError(f"larger than {_FILE_CAP_BYTES // 1024} kB")
    return data


def _worked_out(grade_id: str) -> Any:
    """The values of a command cell (Ex. 3, 4) from the rosparam commands of the cells this kernel ran, as the
    grader works them out from the notebook; None outside a kernel (a script keeps the values it passes)."""
    try:
        from IPython import get_ipython  # noqa: PLC0415 - only in a kernel
    except ImportError:
        return None
    shell = get_ipython()
    if shell is None:
        return None
    import yaml  # noqa: PLC0415 - only for the cells of Ex. 3 and 4

    from hri_teleop.core.rosparam_model import file_reader, shell_commands, work_out, yaml_reader  # noqa: PLC0415 - as above
    from hri_teleop.core.yamlfile import BoundedYamlError, load_bounded_all  # noqa: PLC0415 - as above

    commands = shell_commands(str(cell) for cell in shell.history_manager.input_hist_raw)
    tree, dumps, notes = work_out(commands, yaml_reader(load_bounded_all, (yaml.YAMLError, BoundedYamlError)),
                                  file_reader(_read_capped))
    return command_values(grade_id, tree, dumps, notes)


def hand_in(grade_id: str, **values: Any) -> None:
    """Hand the student's ``values`` of the autograded cell ``grade_id`` to the grader, and show its verdict.

    The grader judges what this hands out (its rule, in its own process); here the same rule runs on the
    same data, so a wrong value ends the cell with :class:`WrongAnswer` and the reason, as it will be graded.
    """
    if not has_rule(grade_id):
        raise CourseError(f"hand_in: no graded cell {grade_id!r}; use the grade id of the cell's nbgrader metadata")
    if grade_id in COMMAND_CELLS:
        worked_out = _worked_out(grade_id)
        if worked_out is not None:
            values = worked_out
    data = {name: plain(value) for name, value in values.items()}
    encoded = json.dumps({"grade_id": grade_id, "values": data}, ensure_ascii=False, allow_nan=False)
    if len(encoded.encode("utf-8")) > MAX_ANSWER_BYTES:
        raise CourseError(f"hand_in: the values are {len(encoded.encode('utf-8'))} bytes as JSON, more than "
                          f"{MAX_ANSWER_BYTES}; hand in the numbers the cell asks for, not whole records")
    payload = json.loads(encoded)  # exactly what the grader will read
    _publish(payload, f"handed in for the grader: {_shown(payload['values'])}")
    verdict = judge(grade_id, payload["values"])
    if not verdict.passed:
        raise WrongAnswer(verdict.message)
    print(f"the grader's rule says: {verdict.message}")
