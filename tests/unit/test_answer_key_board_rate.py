"""The answer key's teleoperation.launch gives the board the rate Ex. 2 promises (100 counts per second).

Without ``~publish_period_ms`` the sketch falls back to the handout's delay(300): 3 counts per
second, and the rumble lags a squeeze by a third of a second.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _serial_node_params(launch: Path) -> dict:
    tree = ET.parse(launch)
    nodes = [n for n in tree.iter("node") if n.get("type") == "serial_node.py"]
    assert len(nodes) == 1, f"{launch}: one rosserial serial_node expected"
    return {p.get("name"): (p.get("type"), p.get("value")) for p in nodes[0].iter("param")}


def test_the_answer_key_serial_node_publishes_every_10_ms():
    params = _serial_node_params(ROOT / "solutions" / "hri_lab" / "launch" / "teleoperation.launch")
    assert params.get("publish_period_ms") == ("int", "10")


def test_the_lab_launch_default_period_is_10_ms_too():
    tree = ET.parse(ROOT / "hri_lab" / "launch" / "teleoperation.launch")
    args = {a.get("name"): a.get("default") for a in tree.iter("arg")}
    assert args.get("publish_period_ms") == "10"


def test_the_students_template_describes_the_parameter_but_not_the_answer_line():
    from hri_teleop.grading.cases.templates import make_template

    source = ROOT / "solutions" / "hri_lab" / "launch" / "teleoperation.launch"
    template = make_template(source.read_text(encoding="utf-8"), "xml", str(source))
    header = template.split("<launch>")[0]
    for words in ("publish_period_ms", "an int", "300 ms", "3.3 counts a second", "10 gives 100"):
        assert words in header, words
    assert "<param" not in template and "serial_node.py" not in template
