"""Student files may not use the lab's reference rules; the templates' given imports (the student API) stay allowed."""

from __future__ import annotations

import gc
import sys
import threading
from pathlib import Path

import pytest

from hri_teleop.grading.judge.reference_guard import REFERENCE_MODULES, REFERENCE_NAMES, reference_uses, refusal

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("source, hit", [
    ("from hri_teleop.core.mapping import map_force\n", "line 1: from hri_teleop.core.mapping import map_force"),
    ("import hri_teleop.core.teleop as t\n", "line 1: import hri_teleop.core.teleop"),
    ("from hri_teleop.core import mapping\n", "line 1: from hri_teleop.core import mapping"),
    ("import hri_teleop.core\nv = hri_teleop.core.teleop.TeleopController\n", "line 2: hri_teleop.core.teleop"),
    ("from hri_teleop.grading.cases.inputs import x\n", "line 1: from hri_teleop.grading.cases.inputs import x"),
    ("import hri_teleop\nv = hri_teleop.core.mapping.map_force(1, 2)\n", "line 2: hri_teleop.core.mapping"),
    ("import importlib\nm = importlib.import_module('hri_teleop.core.teleop')\n", "line 2: 'hri_teleop.core.teleop'"),
    ("from somewhere import TeleopController\n", "line 1: from somewhere import TeleopController"),
    ("from hri_teleop.student import PadState, map_force\n", "line 1: from hri_teleop.student import PadState, map_force"),
    ("import hri_teleop.student as api\nrule = api.TeleopController\n", "line 2: hri_teleop.student.TeleopController"),
    ("from hri_teleop import student\nrule = student.map_force\n", "line 2: hri_teleop.student.map_force"),
    ("import hri_teleop.core as c\nrule = c.teleop.TeleopController\n", "line 2: hri_teleop.core.teleop"),
    ("from hri_teleop import core\nrule = core.mapping.map_force\n", "line 2: hri_teleop.core.mapping"),
    ("from hri_teleop.mapping import ADC_MAX_COUNT\n", "line 1: from hri_teleop.mapping import ADC_MAX_COUNT"),
    ("import hri_teleop.teleop\n", "line 1: import hri_teleop.teleop"),
])
def test_each_way_to_reach_a_reference_rule_is_found_with_its_line(source, hit):
    assert hit in reference_uses(source)


@pytest.mark.parametrize("source", [
    "from hri_teleop.core.gamepad import PadState, normalize_analog_input, open_gamepad\n",
    "from hri_teleop.core.limits import TwistLimiter\n",
    "from hri_teleop.student import JOYAXISMOTION, PadState, TwistLimiter, normalize_analog_input, open_gamepad\n",
    "import hri_teleop.student as api\nlimiter = api.TwistLimiter()\nstate = api.PadState.neutral()\n",
    "from hri_teleop import student\npad = student.open_gamepad('virtual')\n",
    "from hri_teleop.gamepad import PadState, normalize_analog_input, open_gamepad\n",  # last term's given imports
    "from hri_teleop.gamepad.events import JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP, pad_events\n",
    "from hri_teleop.limits import TwistLimiter\n",
    "import rospy\nfrom std_msgs.msg import Float32\n",
    "mapping = {'a': 1}\nteleop = mapping['a']\n",
    "def broken(:\n",  # a syntax error is the check's to report
    "class Node:\n    def map_force(self, c):\n        return c\n    def cb(self, m):\n        return self.map_force(m)\n",
])
def test_the_given_imports_and_plain_names_are_allowed(source):
    assert reference_uses(source) == []


@pytest.mark.parametrize("path", ["solutions/hri_lab/scripts/mapping_node.py", "solutions/hri_lab/scripts/teleoperation.py"])
def test_the_answer_key_writes_its_rules_itself(path):
    assert reference_uses((ROOT / path).read_text()) == []


def test_every_name_of_the_student_api_is_allowed_and_none_is_a_reference_rule():
    import hri_teleop.student as student

    for name in student.__all__:
        assert reference_uses(f"from hri_teleop.student import {name}\n") == [], name
        assert name not in REFERENCE_NAMES
        home = getattr(getattr(student, name), "__module__", "") or ""
        assert not any(home == m or home.startswith(m + ".") for m in REFERENCE_MODULES), (name, home)


def test_the_refusal_is_one_line_with_the_file_the_uses_and_the_fix():
    message = refusal("mapping_node.py", ["line 3: from hri_teleop.core.mapping import map_force", "line 9: .map_force",
                                          "line 10: .map_force", "line 11: .map_force"])
    assert message == ("mapping_node.py uses the lab's reference implementation (line 3: from hri_teleop.core.mapping "
                       "import map_force; line 9: .map_force; line 10: .map_force): the exercise is to write that "
                       "rule yourself; remove the import and write it in your file")


class _Finalizer:
    """Cyclic garbage whose finalizer, the first time it runs inside ``ast.parse``, lets another thread
    read a student file and waits for it: what a Popen or socket finalizer did in the grader when the
    checks ran side by side. Outside a parse it leaves new garbage behind, so the collector keeps one at hand."""

    def __init__(self, record: dict) -> None:
        self.record = record
        self.cycle = self

    def __del__(self) -> None:
        record = self.record
        if not record["armed"]:
            return
        record["runs"] += 1
        frame = sys._getframe(1)
        inside_parse = False
        while frame is not None:
            if frame.f_code.co_name == "parse" and frame.f_code.co_filename.endswith("ast.py"):
                inside_parse = True
            frame = frame.f_back
        if inside_parse and not record["inside_parse"]:
            record["inside_parse"] += 1
            other = threading.Thread(target=lambda: record["other"].append(reference_uses(record["source"])))
            other.start()
            other.join(timeout=60)  # hang guard only: the other parse takes milliseconds
            return
        _Finalizer(record)


def test_two_checks_reading_student_files_at_once_both_get_their_answer_even_when_a_finalizer_runs_mid_parse():
    """L28 (3 checks side by side): Python 3.11's ast keeps one recursion counter for all threads, so a
    parse that another thread's parse interrupted (through a finalizer run by the collector) raised
    'SystemError: AST constructor recursion depth mismatch' and the whole submission's grading failed."""
    source = (ROOT / "solutions/hri_lab/scripts/teleoperation.py").read_text() + "\nimport hri_teleop.core.teleop\n"
    record = {"armed": True, "runs": 0, "inside_parse": 0, "other": [], "source": source}
    thresholds = gc.get_threshold()
    gc.set_threshold(1)
    try:
        _Finalizer(record)
        uses = reference_uses(source)
    finally:
        record["armed"] = False
        gc.set_threshold(*thresholds)
        gc.collect()
    expected = [f"line {source.count(chr(10))}: import hri_teleop.core.teleop"]
    assert uses == expected
    assert record["runs"] > 0, "the collector never ran: the test would show nothing"
    assert record["inside_parse"] == 0, "a finalizer ran inside the grader's parse"
    assert record["other"] in ([], [expected])
