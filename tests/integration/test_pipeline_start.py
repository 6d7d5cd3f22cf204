"""Ex. 15's pipeline at home (the student bundle: no lab launch file), on a real roscore: it returns once
the graph has settled, and a node that ends while it starts is named with what to do, everything stopped."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from hri_teleop.course import lab, lab_nodes, nodes
from hri_teleop.course.errors import CourseError
from hri_teleop.course.pipeline_start import PIPELINE_WIRING, registrations
from hri_teleop.grading.cases.templates import make_template
from hri_teleop.ros.master_api import master_call

REPO = Path(__file__).resolve().parents[2]
ANSWER_KEY = REPO / "solutions" / "hri_lab"

pytestmark = pytest.mark.ros


@pytest.fixture
def bundle_kernel(ros_master, monkeypatch, tmp_path):
    """This process as a notebook kernel of the student bundle: its own master, no lab launch file."""
    for key, value in ros_master.env.items():
        monkeypatch.setenv(key, value)
    for key in ("HRI_MODE", "NBGRADER_EXECUTION"):
        monkeypatch.delenv(key, raising=False)
    monkeypatch.setattr(lab_nodes, "lab_launch_file", lambda: tmp_path / "no-lab-launch-file" / "teleoperation.launch")
    yield ros_master
    lab.stop()


def _package(tmp_path: Path, **scripts: str) -> Path:
    """The answer key's hri_lab with some scripts replaced (name without .py -> text)."""
    package = tmp_path / "hri_lab"
    shutil.copytree(ANSWER_KEY, package)
    for name, text in scripts.items():
        (package / "scripts" / f"{name}.py").write_text(text)
    return package


def _nothing_left_running() -> list:
    return [" ".join(p.argv[-3:]) for p in nodes.STARTED if p.anything_left]


def test_a_template_teleoperation_py_names_the_exercise_to_finish_and_stops_every_node_it_started(bundle_kernel,
                                                                                                   tmp_path):
    template = make_template((ANSWER_KEY / "scripts" / "teleoperation.py").read_text(), "python")
    package = _package(tmp_path, teleoperation=template)
    with pytest.raises(CourseError) as raised:
        lab_nodes.start_pipeline(package=package)
    message = str(raised.value)
    assert "/teleoperation ended: teleoperation.py is still the template" in message
    assert "finish Ex. 9 first" in message
    assert "NotImplementedError" in message and 'File "teleoperation.py", line' in message
    assert "\\n" not in message and "'" not in message.splitlines()[0]  # no repr of a cut-off output
    assert "/FSR_sensor" not in message and "/gripper_manager" not in message  # only the node that ended
    assert _nothing_left_running() == []


def test_a_template_mapping_node_py_names_ex_5(bundle_kernel, tmp_path):
    template = make_template((ANSWER_KEY / "scripts" / "mapping_node.py").read_text(), "python")
    package = _package(tmp_path, mapping_node=template)
    with pytest.raises(CourseError, match=r"/mapping_node ended: mapping_node.py is still the template.*finish Ex\. 5 first"):
        lab_nodes.start_pipeline(package=package)
    assert _nothing_left_running() == []


def test_a_crashing_mapping_node_is_named_with_its_own_last_traceback_lines(bundle_kernel, tmp_path):
    text = (ANSWER_KEY / "scripts" / "mapping_node.py").read_text()
    broken = text.replace("rospy.init_node(", "undefined_helper()\n    rospy.init_node(", 1)
    assert broken != text
    package = _package(tmp_path, mapping_node=broken)
    with pytest.raises(CourseError) as raised:
        lab_nodes.start_pipeline(package=package)
    message = str(raised.value)
    assert "/mapping_node ended while starting (exit status 1): mapping_node.py crashed: fix mapping_node.py" in message
    assert "NameError: name 'undefined_helper' is not defined" in message
    assert 'File "mapping_node.py", line' in message and "undefined_helper()" in message
    assert "still the template" not in message and "/teleoperation" not in message
    assert _nothing_left_running() == []


def test_the_pipeline_returns_once_every_node_has_registered_its_topics(bundle_kernel, tmp_path):
    pipeline = lab_nodes.start_pipeline(package=_package(tmp_path))
    assert pipeline.running
    found = registrations(master_call("getSystemState"))  # read at once, as the graph view's cell does
    for topic, publisher, subscriber in PIPELINE_WIRING:
        assert (topic, publisher, "pub") in found and (topic, subscriber, "sub") in found, (topic, sorted(found))


def test_a_student_node_that_never_subscribes_still_starts_the_pipeline_as_it_is(bundle_kernel, tmp_path):
    text = (ANSWER_KEY / "scripts" / "teleoperation.py").read_text()
    deaf = text.replace('self.force_sub = rospy.Subscriber("/force_mapped", Float32, self.on_force)',
                        "self.force_sub = None")
    assert deaf != text
    pipeline = lab_nodes.start_pipeline(package=_package(tmp_path, teleoperation=deaf))
    assert pipeline.running  # the graph view then shows what this node does
    found = registrations(master_call("getSystemState"))
    assert ("/gripper_width", "/gripper_manager", "sub") in found
    assert not any(node == "/teleoperation" and kind == "sub" for _topic, node, kind in found)
