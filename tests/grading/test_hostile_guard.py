"""Student code that reaches for the lab's reference gains nothing: graded by make grade's files-only mode.

The source scan (judge.reference_guard) misses a module name computed at run time and an ``exec`` of a
file; a launch file can read the lab's node the grader put beside the student's files into a parameter. Each
is a submission graded in one ``hri-grade batch`` beside the answer key, which keeps its full marks; the
others score 0, their feedback names the refusal, and no line of the lab's nodes reaches any output file.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Dict, List, NamedTuple

import pytest
from grading_helpers import REPO, answer_text, hri_grade, write_package

pytestmark = pytest.mark.ros

CHECKS = "mapping-node,sensor-launch"
GOOD = answer_text("scripts/mapping_node.py")
LAUNCH = answer_text("launch/sensor.launch")

#: The rule by a name the source scan cannot see, used as the student's own map_force.
IMPORTLIB = GOOD.replace("import rospy\n", "import importlib\nimport rospy\n\n"
                         "_rule = importlib.import_module('hri_teleop.core.' + 'mapp' + 'ing')\n", 1).replace(
    "        mapped = float(count) / float(self.max_sensor_force)\n        return min(1.0, max(0.0, mapped))\n",
    "        return float(_rule.map_force(count, self.max_sensor_force))\n")
#: The lab's own node run from its file (the machine's checkout), its class then used.
EXEC_LAB = ("import rospy\n"
            f"exec(open({str(REPO / 'hri_lab' / 'scripts' / 'mapping_node.py')!r}).read().split('if __name__')[0])\n"
            "rospy.init_node('mapping_node')\nMappingNode()\nrospy.spin()\n")
#: The lab's mapping_node.py, which the grader runs in place of the student's, read into a parameter.
TEXTFILE = LAUNCH.replace("<launch>", '<launch>\n  <param name="leak" textfile="$(find hri_lab)/scripts/mapping_node.py"/>', 1)


class Batch(NamedTuple):
    out: Path
    grades: Dict[str, Dict[str, str]]
    output: str


def _distinctive_lines() -> List[str]:
    """Lines of the lab's nodes long enough to prove a leak."""
    found = []
    for name in ("teleoperation.py", "mapping_node.py"):
        found += [line.strip() for line in (REPO / "hri_lab" / "scripts" / name).read_text().splitlines()
                  if len(line.strip()) > 40 and "import" not in line and not line.strip().startswith("#")]
    return found


@pytest.fixture(scope="module")
def batch(tmp_path_factory) -> Batch:
    root = tmp_path_factory.mktemp("hostile-guard") / "submitted"
    write_package(root / "good" / "hri_lab", {"scripts/mapping_node.py": GOOD, "launch/sensor.launch": LAUNCH})
    write_package(root / "importlib_rule" / "hri_lab", {"scripts/mapping_node.py": IMPORTLIB})
    write_package(root / "exec_lab_node" / "hri_lab", {"scripts/mapping_node.py": EXEC_LAB})
    write_package(root / "launch_reads_lab_node" / "hri_lab", {"launch/sensor.launch": TEXTFILE})
    out = root.parent / "grades"
    proc = hri_grade("batch", str(root), "--out", str(out), "--jobs", "2", "--checks", CHECKS, "--timeout", "300",
                     timeout=900)
    grades = {}
    if (out / "grades.csv").is_file():
        with open(out / "grades.csv") as fh:
            grades = {row["student"]: row for row in csv.DictReader(fh)}
    return Batch(out, grades, proc.stdout[-3000:] + proc.stderr[-3000:])


def test_the_answer_key_keeps_its_full_marks_beside_them(batch: Batch) -> None:
    row = batch.grades.get("good")
    assert row is not None and float(row["score"]) == float(row["max_score"]) == 30.0, batch.output


@pytest.mark.parametrize("name,words", [
    ("importlib_rule", "the grader refuses hri_teleop.core.mapping"),
    ("exec_lab_node", "mapping_node.py"),  # the lab's node is not there: an empty, unreadable file in its place
    ("launch_reads_lab_node", "the grader refuses to open"),
])
def test_reaching_for_the_reference_gains_nothing_and_is_named(batch: Batch, name: str, words: str) -> None:
    row = batch.grades.get(name)
    assert row is not None and row["status"] == "graded", f"{name}: {row}\n{batch.output}"
    feedback = (batch.out / name / "feedback.txt").read_text()
    assert float(row["score"]) == 0, f"{name} gained points:\n{feedback}"
    assert words in feedback, f"{name}: {words!r} not in\n{feedback}"
    leaked = [line for path in (batch.out / name).rglob("*") if path.is_file()
              for line in _distinctive_lines() if line in path.read_text(errors="replace")]
    assert leaked == [], leaked[:3]
