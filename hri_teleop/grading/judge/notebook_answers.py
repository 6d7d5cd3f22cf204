"""The rules of the notebooks' autograded cells: grade id -> a verdict on the values the cell handed in.

A graded cell hands the student's values out as plain data (:func:`hri_teleop.course.answers.hand_in`); the
grader judges them in its own process (:mod:`hri_teleop.grading.batch.notebook_judge`) against
:func:`expectations` it computes itself. A rule is pure, never raises on what a student hands in, and its
message names the cause, never the value to find; the kernel runs it at home only to show the verdict (Python
3.8). Ex. 3 and 4 (:data:`COMMAND_CELLS`): the grader works the notebook's ``rosparam`` commands out itself
(:mod:`hri_teleop.core.rosparam_model`, in a box), so a hook in the kernel has nothing to report that counts.
"""

from __future__ import annotations

import functools
import math
import posixpath
from dataclasses import dataclass
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError

__all__ = ["MIME", "MAX_ANSWER_BYTES", "Verdict", "AnswerRuleError", "RULES", "TOLERANCES", "expectations",
           "judge", "apply_rule", "has_rule", "COMMAND_CELLS", "DUMP_FILE", "WORKED_OUT", "command_values"]

#: The MIME type of a cell's answer output: a JSON object {"grade_id": ..., "values": {...}}.
MIME = "application/vnd.hri-teleop.answer+json"
#: The largest answer (its JSON) a cell may hand in; a larger one is not judged.
MAX_ANSWER_BYTES = 64 * 1024
RIGHT = "right"


class AnswerRuleError(HriTeleopError, KeyError):
    """A grade id without a rule (one line: which, and where rules are written)."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class Verdict:
    """The grader's word on one cell: passed or not, and one line saying why."""

    passed: bool
    message: str


Values = Mapping[str, Any]
Rule = Callable[[Values, Mapping[str, Any]], Verdict]

#: The tolerances of the rules (rtol, atol as numpy.allclose: |a - e| <= atol + rtol * |e|).
TOLERANCES: Dict[str, Tuple[float, float]] = {
    "ex1a_rate": (0.02, 0.0),
    "ex1a_voltage": (1e-3, 0.0),
    "ex1a_count": (0.0, 1.0),
    "ex2_rate": (0.2, 0.0),
    "ex11_value": (0.0, 8.0),
    "ex14_crush_rates": (0.0, 1e-9),
    "ex14_test": (0.0, 1e-12),
}
#: Ex. 10: how far (m) the hand must end below where it started.
EX10_DROP_M = 0.03
#: Ex. 14: the seeded study the notebook simulates (participants, seed).
STUDY = (6, 0)
#: Ex. 4: what a dump of the whole server holds (a key of the student's file and one of the master's).
DUMP_KEYS = ("robot_name", "rosdistro")
#: Ex. 4 f): the file the whole server is dumped into, named from the notebook's folder.
DUMP_FILE = "new_robot_params.yaml"
#: grade id -> the parameter its rule reads from what the notebook's rosparam commands leave on the server.
COMMAND_CELLS: Dict[str, str] = {"ex3_integer": "/ex3/integer", "ex3_text": "/ex3/text", "ex3_items": "/ex3/items",
                                 "ex4_loaded": "/robot_mass", "ex4_dumped": ""}
#: grade id -> how the grader finds the values of a cell itself, as the cell's verdict says it: these cells' rules
#: never judge what the kernel handed in (Ex. 3, 4: the notebook's commands; Ex. 10: the grader drives the node).
WORKED_OUT: Dict[str, str] = {**{g: "worked out by the grader from your rosparam commands" for g in COMMAND_CELLS},
                              "ex10_drives": "measured by the grader, driving your teleoperation.py on the simulated arm"}
_NOTE_CHARS = 240
#: Ex. 14: the operator's run (the egg; the longest simulated run, s).
OPERATOR_RUN = ("egg", 120.0)
#: Ex. 14: the level of the test.
ALPHA = 0.05


def _fail(message: str) -> Verdict:
    return Verdict(False, message)


def _missing(values: Values, name: str) -> Optional[Verdict]:
    if name not in values:
        return _fail(f"{name} was not handed in: run the notebook from the top, then this cell")
    return None


def _number(values: Values, name: str) -> Tuple[Optional[float], Optional[Verdict]]:
    """The number handed in as ``name``, or the verdict that it is none (bools and NaN are no numbers)."""
    missing = _missing(values, name)
    if missing is not None:
        return None, missing
    value = values[name]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        return None, _fail(f"{name} is {_shown(value)}: a number is expected")
    return float(value), None


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _close(actual: float, expected: float, grade_id: str) -> bool:
    rtol, atol = TOLERANCES[grade_id]
    return abs(actual - expected) <= atol + rtol * abs(expected)


def _numeric_rule(grade_id: str, name: str, unit: str, hint: str) -> Rule:
    def rule(values: Values, expected: Mapping[str, Any]) -> Verdict:
        value, problem = _number(values, name)
        if problem is not None or value is None:
            return problem or _fail(f"{name}: no number")
        if _close(value, float(expected[name]), grade_id):
            return Verdict(True, RIGHT)
        return _fail(f"{name} is {value:g}{unit}: {hint}")

    return rule


def _ex2_type(values: Values, expected: Mapping[str, Any]) -> Verdict:
    missing = _missing(values, "pub_force_type")
    if missing is not None:
        return missing
    value = values["pub_force_type"]
    if not isinstance(value, str):
        return _fail(f"pub_force_type is {_shown(value)}: text (a str) is expected, as rostopic prints it")
    if value.strip() == expected["pub_force_type"]:
        return Verdict(True, RIGHT)
    return _fail(f"pub_force_type is {_shown(value)}: run `rostopic type /pub_force` while the node runs and copy "
                 "what it prints, package/Type")


def _with_note(values: Values, message: str) -> str:
    """``message``, and the first of the notebook's rosparam commands that fails, if one does."""
    notes = values.get("notes")
    if isinstance(notes, list) and notes and isinstance(notes[0], str):
        note = notes[0] if len(notes[0]) <= _NOTE_CHARS else notes[0][:_NOTE_CHARS - 3] + "..."
        return f"{message} (in your commands, {note})"
    return message


def _ex3_type(name: str, kind: type, hint: str) -> Rule:
    def rule(values: Values, _expected: Mapping[str, Any]) -> Verdict:
        missing = _missing(values, "value")
        if missing is not None:
            return missing
        value = values["value"]
        if type(value) is kind:
            return Verdict(True, RIGHT)
        if value is None:
            return _fail(_with_note(values, f"your notebook's commands leave {name} unset: write them as "
                                            f"`!rosparam set {name} ...` lines in the answer cell"))
        return _fail(_with_note(values, f"{name} is {_shown(value)}: {hint}"))

    return rule


def _ex4_loaded(values: Values, expected: Mapping[str, Any]) -> Verdict:
    missing = _missing(values, "robot_mass")
    if missing is not None:
        return missing
    value = values["robot_mass"]
    if value is None:
        return _fail(_with_note(values, "your notebook's commands leave /robot_mass unset: load your file with "
                                        "`!rosparam load hri_lab/config/robot_params.yaml` in the answer cell"))
    if not isinstance(value, bool) and isinstance(value, (int, float)) and value == expected["robot_mass"]:
        return Verdict(True, RIGHT)
    return _fail(_with_note(values, f"/robot_mass is {_shown(value)}, not Table 1's value: fix the file and load "
                                    "it again"))


def _ex4_dumped(values: Values, expected: Mapping[str, Any]) -> Verdict:
    if values.get("file") is not True:
        return _fail(_with_note(values, f"your notebook's commands write no {DUMP_FILE} next to it: dump the "
                                        f"server with `!rosparam dump {DUMP_FILE}` in the answer cell"))
    keys = values.get("keys")
    wanted = expected["keys"]
    if isinstance(keys, list) and all(key in keys for key in wanted):
        return Verdict(True, RIGHT)
    return _fail(_with_note(values, f"dump the whole server (rosparam dump {DUMP_FILE}), after loading your file"))


def _ex10_drives(values: Values, expected: Mapping[str, Any]) -> Verdict:
    start, problem = _number(values, "z_start_m")
    if problem is not None or start is None:
        return problem or _fail("z_start_m: no number")
    now, problem = _number(values, "z_m")
    if problem is not None or now is None:
        return problem or _fail("z_m: no number")
    drop = float(expected["drop_m"])
    if now < start - drop:
        return Verdict(True, RIGHT)
    return _fail(f"the hand is at z = {now:.3f} m, it started at {start:.3f} m: drive it at least {drop * 100:g} cm "
                 "down; see your node's output (node.output())")


def _ex11_value(values: Values, expected: Mapping[str, Any]) -> Verdict:
    missing = _missing(values, "max_sensor_force")
    if missing is not None:
        return missing
    value = values["max_sensor_force"]
    if type(value) is not int:
        return _fail(f"max_sensor_force is {_shown(value)}: the parameter is a count, an int")
    if _close(float(value), float(expected["max_sensor_force"]), "ex11_value"):
        return Verdict(True, RIGHT)
    return _fail(f"max_sensor_force is {value}: the largest count of record.count, while the piston is fully pressed")


def _ex14_lifts_egg(values: Values, expected: Mapping[str, Any]) -> Verdict:
    """The grader runs the student's operator (``my_steps``, plain data) in the lock-step lab itself."""
    from hri_teleop.core.run_record import summarize  # noqa: PLC0415 - the lock-step lab, only for Ex. 14
    from hri_teleop.sim.grasp_objects import OBJECTS  # noqa: PLC0415 - as above
    from hri_teleop.sim.lab import run_lab  # noqa: PLC0415 - as above
    from hri_teleop.sim.virtual_pad import parse_script  # noqa: PLC0415 - as above
    from hri_teleop.sim.world import WorldConfig  # noqa: PLC0415 - as above

    missing = _missing(values, "steps")
    if missing is not None:
        return missing
    try:
        steps = parse_script(values["steps"], "my_steps")
        record = run_lab(steps, WorldConfig(object=OBJECTS[str(expected["object"])]),
                         max_duration_s=float(expected["max_duration_s"]))
    except HriTeleopError as exc:
        return _fail(f"your operator could not run: {_first_line(exc)}")
    outcome = summarize(record)
    if outcome.lifted and not outcome.crushed:
        return Verdict(True, RIGHT)
    return _fail(f"the egg was {outcome.outcome}: lift it without crushing it (change your operator's steps)")


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    line = text[0] if text else type(exc).__name__
    return line if len(line) <= 200 else line[:197] + "..."


def _ex14_crush_rates(values: Values, expected: Mapping[str, Any]) -> Verdict:
    missing = _missing(values, "crush_rate")
    if missing is not None:
        return missing
    value, wanted = values["crush_rate"], expected["crush_rate"]
    if not isinstance(value, dict) or set(value) != set(wanted):
        return _fail(f"crush_rate is {_shown(value)}: a dict with the keys 'feedback' and 'no_feedback'")
    for condition in sorted(wanted):
        share = value[condition]
        if isinstance(share, bool) or not isinstance(share, (int, float)) or not math.isfinite(float(share)) \
                or not _close(float(share), float(wanted[condition]), "ex14_crush_rates"):
            return _fail(f"crush_rate[{condition!r}] is {_shown(share)}: per condition, its crushed trials over "
                         "its trials (study.metrics)")
    return Verdict(True, RIGHT)


def _ex14_test(values: Values, expected: Mapping[str, Any]) -> Verdict:
    p_value, problem = _number(values, "p_crush")
    if problem is not None or p_value is None:
        return problem or _fail("p_crush: no number")
    if not _close(p_value, float(expected["p_value"]), "ex14_test"):
        return _fail("p_crush: the p_value of study.comparisons['crush_rate'], as it is")
    significant = values.get("significant")
    if not isinstance(significant, bool):
        return _fail(f"significant is {_shown(significant)}: True or False (is p_crush below {ALPHA}?)")
    if significant == (float(expected["p_value"]) < ALPHA):
        return Verdict(True, RIGHT)
    return _fail(f"significant: is p_crush below {ALPHA}?")


#: grade id -> its rule (every autograded cell of the course has one; a test says so).
RULES: Dict[str, Rule] = {
    "ex1a_rate": _numeric_rule("ex1a_rate", "sketch_rate_hz", " Hz",
                               "one message per pass of loop(); read how long the sketch's loop waits"),
    "ex1a_voltage": _numeric_rule("ex1a_voltage", "a0_voltage_at_1n_v", " V",
                                  "the voltage across the 10 kOhm resistor, with the FSR's 6 kOhm above it"),
    "ex1a_count": _numeric_rule("ex1a_count", "a0_count_at_1n", "",
                                "count = floor(V * 1024 / 5 V): 1024 steps of 5/1024 V"),
    "ex2_type": _ex2_type,
    "ex2_rate": _numeric_rule("ex2_rate", "pub_force_rate_hz", " Hz",
                              "run `rostopic hz /pub_force` while the node runs and copy the average rate"),
    "ex3_integer": _ex3_type("/ex3/integer", int, "write a whole number"),
    "ex3_text": _ex3_type("/ex3/text", str, "write text; a value YAML reads as a number needs YAML quotes inside "
                                            "the shell's: rosparam set /ex3/text \"'7'\""),
    "ex3_items": _ex3_type("/ex3/items", list, "write a list in brackets, quoted for the shell"),
    "ex4_loaded": _ex4_loaded,
    "ex4_dumped": _ex4_dumped,
    "ex10_drives": _ex10_drives,
    "ex11_value": _ex11_value,
    "ex14_lifts_egg": _ex14_lifts_egg,
    "ex14_crush_rates": _ex14_crush_rates,
    "ex14_test": _ex14_test,
}


@functools.lru_cache(maxsize=None)
def _study() -> Tuple[Dict[str, float], float]:
    from hri_teleop.sim.study import simulate_study  # noqa: PLC0415 - the lock-step lab, only for Ex. 14

    participants, seed = STUDY
    result = simulate_study(participants, seed=seed)
    rates = {condition: float(row["crush_rate"]) for condition, row in result.rates().items()}
    return rates, float(result.comparisons["crush_rate"].p_value)


def expectations(grade_id: str) -> Dict[str, Any]:
    """What the rule of ``grade_id`` compares with, computed here from the toolkit's models (never handed in)."""
    if grade_id in ("ex1a_rate", "ex1a_voltage", "ex1a_count"):
        from hri_teleop.core import fsr  # noqa: PLC0415 - numpy, only where a rule needs it
        from hri_teleop.core.board_rates import HANDOUT_PERIOD_S  # noqa: PLC0415 - as above

        volts = float(fsr.resistance_to_voltage(6e3))
        return {"sketch_rate_hz": 1.0 / HANDOUT_PERIOD_S, "a0_voltage_at_1n_v": volts,
                "a0_count_at_1n": float(fsr.voltage_to_count(volts))}
    if grade_id == "ex2_type":
        return {"pub_force_type": "std_msgs/Int16"}
    if grade_id == "ex2_rate":
        from hri_teleop.sim.sensor_profile import FSR_SENSOR_RATE_HZ  # noqa: PLC0415 - as above

        return {"pub_force_rate_hz": float(FSR_SENSOR_RATE_HZ)}
    if grade_id == "ex4_loaded":
        from hri_teleop.grading.cases.handout import TABLE_1  # noqa: PLC0415 - as above

        return {"robot_mass": TABLE_1["robot_mass"]}
    if grade_id == "ex4_dumped":
        return {"keys": list(DUMP_KEYS)}
    if grade_id == "ex10_drives":
        return {"drop_m": EX10_DROP_M}
    if grade_id == "ex11_value":
        from hri_teleop.core.attachment import Attachment  # noqa: PLC0415 - as above

        return {"max_sensor_force": Attachment().full_travel_count}
    if grade_id == "ex14_lifts_egg":
        return {"object": OPERATOR_RUN[0], "max_duration_s": OPERATOR_RUN[1]}
    if grade_id in ("ex14_crush_rates", "ex14_test"):
        rates, p_value = _study()
        return {"crush_rate": dict(rates), "p_value": p_value}
    if grade_id in RULES:
        return {}
    raise AnswerRuleError(f"no rule for the graded cell {grade_id!r}: write one in "
                          "hri_teleop/grading/judge/notebook_answers.py (docs/instructors.md)")


def command_values(grade_id: str, tree: Mapping[str, Any], dumps: Sequence[Mapping[str, Any]],
                   notes: Sequence[str] = ()) -> Dict[str, Any]:
    """The values the rule of a :data:`COMMAND_CELLS` cell judges, from what the notebook's rosparam commands
    leave: ``tree`` (the server), ``dumps`` (each with ``file`` and ``keys``) and the ``notes`` of failing ones."""
    from hri_teleop.core.rosparam_model import value_at  # noqa: PLC0415 - only for the cells of Ex. 3 and 4

    kept = [str(n) for n in list(notes)[:3]]
    if grade_id == "ex4_dumped":
        last = None
        for dump in dumps:
            if posixpath.normpath(str(dump.get("file", ""))) == DUMP_FILE:
                last = dump
        return {"file": last is not None, "keys": list(last.get("keys", [])) if last is not None else None,
                "notes": kept}
    found, value = value_at(tree, COMMAND_CELLS[grade_id])
    name = "robot_mass" if grade_id == "ex4_loaded" else "value"
    return {name: value if found else None, "notes": kept}


def has_rule(grade_id: str) -> bool:
    return grade_id in RULES


def apply_rule(grade_id: str, values: Any, expected: Mapping[str, Any]) -> Verdict:
    """The rule of ``grade_id`` on ``values`` (the JSON a cell handed in) and ``expected``; never raises on values."""
    if grade_id not in RULES:
        raise AnswerRuleError(f"no rule for the graded cell {grade_id!r}: write one in "
                              "hri_teleop/grading/judge/notebook_answers.py (docs/instructors.md)")
    if not isinstance(values, dict):
        return _fail(f"not judged: the cell handed in {type(values).__name__}, not named values")
    try:
        return RULES[grade_id](values, expected)
    except (TypeError, ValueError, KeyError, AttributeError, OverflowError) as exc:
        return _fail(f"not judged: the values handed in could not be read ({type(exc).__name__})")


def judge(grade_id: str, values: Any) -> Verdict:
    """The verdict on what the cell ``grade_id`` handed in, against :func:`expectations` computed here."""
    return apply_rule(grade_id, values, expectations(grade_id))
