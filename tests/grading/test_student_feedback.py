"""The grader's block in a student's feedback pages: which parts each page shows, its score, no grader paths.

The whole path (make grade, make feedback, release_feedback, fetch_feedback) runs in
tests/grading/test_instructors_guide.py; these are the rules at their edges, on nbgrader's page markup.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from hri_teleop.core.paths import REPO
from hri_teleop.grading.batch.student_feedback import (
    BLOCK_ID,
    files_block,
    mark_page,
    notebook_results,
    shown_parts,
    without_grader_paths,
)
from hri_teleop.grading.points import CHECK_CELLS, part_tables
from hri_teleop.grading.results import CheckResult, Part


def _result(check: str, failed: int = 0) -> CheckResult:
    """Every part of ``check`` passed but the first ``failed``."""
    return CheckResult(check, f"/srv/course/submitted/ann/lab/hri_lab/{check}",
                       [Part(n, points, i >= failed, "" if i >= failed else f"{n} is wrong")
                        for i, (n, points) in enumerate(part_tables()[check].values())])


def test_each_part_of_every_check_is_shown_in_exactly_one_notebook():
    for check in {cell.check for cell in CHECK_CELLS}:
        names = {name for name, _p in part_tables()[check].values()}
        shown = [shown_parts(cell) or frozenset(names) for cell in CHECK_CELLS if cell.check == check]
        assert set().union(*shown) == names, check
        assert sum(len(s) for s in shown) == len(names), f"{check}: a part shown in two notebooks"


def test_a_notebook_gets_the_parts_its_check_cells_show_and_a_missing_page_leaves_them_to_the_first():
    results = [_result("teleoperation"), _result("catkin-package"), _result("teleoperation-launch")]
    pages = ["ex08_gamepad_commands", "ex09_teleoperation_node", "ex12_13_teleoperation_launch"]
    by_notebook, homeless = notebook_results("lab", results, pages)
    assert [r.check for r in by_notebook["ex09_teleoperation_node"]] == ["catkin-package", "teleoperation"]
    total = sum(r.max_score for shown in by_notebook.values() for r in shown)
    assert total == sum(r.max_score for r in results) and homeless == []
    # ex09 not handed in: its parts (catkin-package's Ex. 9 half, teleoperation's node parts) go to no page
    by_notebook, homeless = notebook_results("lab", results, [p for p in pages if p != "ex09_teleoperation_node"])
    assert {r.check for r in homeless} == {"catkin-package", "teleoperation"}
    assert all(p.name.startswith("Ex. 9") for p in next(r for r in homeless if r.check == "catkin-package").parts)


def test_grader_paths_are_cut_to_the_students_file_or_a_name_and_ros_names_stay():
    submission = Path("/srv/course/submitted/ann/lab")
    box = Path(tempfile.gettempdir()) / "hri-grade-mapping-node-x1"
    text = (f"mapping-node ({submission}/hri_lab/scripts/mapping_node.py): 0/20\n"
            f"  {box}/hri_lab/scripts/mapping_node.py line 3; log {box}/ros/log/node-1.log.\n"
            f"  plot: {REPO}/out/grades/ann/lab/plots/trace.png and {Path.home()}/x/y.txt\n"
            "  /force_mapped (std_msgs/Float32) on /dev/ttyACM0; /usr/lib/python3/dist-packages/rospy/x.py;"
            " /opt/ros/noetic; data:image/png;base64,iVBO/tmp/Rw0K/home/x==")
    cut = without_grader_paths(text, [submission])
    assert cut.splitlines()[0] == "mapping-node (hri_lab/scripts/mapping_node.py): 0/20"
    assert "  hri_lab/scripts/mapping_node.py line 3; log node-1.log." in cut
    assert "plot: out/grades/ann/lab/plots/trace.png and y.txt" in cut
    for kept in ("/force_mapped", "/dev/ttyACM0", "/usr/lib/python3/dist-packages/rospy/x.py", "/opt/ros/noetic",
                 "base64,iVBO/tmp/Rw0K/home/x=="):
        assert kept in cut
    assert "/srv/" not in cut and str(box) not in cut and str(Path.home()) + "/" not in cut


PAGE = ('<html><body>\n<div class="panel-heading">\n<h4>ex06_07_sensor_launch (Score: 0.0 / 0.0)</h4>\n</div>\n'
        '<div class="panel-body">\n<pre>ran in /tmp/hri-kernel-box/hri_lab/launch/sensor.launch</pre></body></html>')


def test_a_page_counts_the_parts_it_shows_once_however_often_it_is_marked(tmp_path):
    page = tmp_path / "ex06_07_sensor_launch.html"
    page.write_text(PAGE)
    mine = [_result("sensor-launch", failed=1)]  # the first part (1 point) failed: 9 of 10
    for _run in range(2):  # make grade, then make feedback / REPORT=1 on the same page
        block = files_block("preparation", mine, mine, [], {"sensor-launch": ["ex06_07_sensor_launch"]})
        mark_page(page, block, mine, [], [])
    text = page.read_text()
    assert "(Score: 9.0 / 10.0: this notebook's cells 0.0 / 0.0, your hri_lab files' parts it checks 9 / 10)" in text
    assert text.count(f'id="{BLOCK_ID}"') == 1 and "parses with roslaunch is wrong" in text
    assert "/tmp/" not in text and "ran in hri_lab/launch/sensor.launch" in text


def test_files_not_graded_are_said_on_the_page_with_the_notebooks_own_score(tmp_path):
    page = tmp_path / "ex06_07_sensor_launch.html"
    page.write_text(PAGE)
    mark_page(page, files_block("preparation", None, [], [], {}, "took longer than 600 s"), [], [], [])
    text = page.read_text()
    assert "(Score: 0.0 / 0.0)</h4>" in text
    assert "Your hri_lab files (preparation) were not graded</strong>: took longer than 600 s" in text


def test_only_the_pages_of_handed_in_notebooks_are_marked_and_a_students_own_page_stays_as_it_was(tmp_path):
    import json

    from hri_teleop.grading.batch.student_feedback import add_files_feedback

    course, out = tmp_path / "course", tmp_path / "grades"
    submission, feedback = course / "submitted" / "ann" / "preparation", course / "feedback" / "ann" / "preparation"
    for folder in (submission, feedback, out / "ann" / "preparation"):
        folder.mkdir(parents=True)
    (submission / "ex06_07_sensor_launch.ipynb").write_text("{}")
    (feedback / "ex06_07_sensor_launch.html").write_text(PAGE)
    (feedback / "notes.html").write_text(f"<html><body>{tmp_path}</body></html>")  # nbgrader copies her notes.html
    (out / "ann" / "preparation" / "checks.json").write_text(json.dumps([_result("sensor-launch").to_dict()]))
    jobs = [{"assignment": "preparation", "kind": kind, "status": "graded", "message": ""}
            for kind in ("notebooks", "files")]
    marked = add_files_feedback(out, [{"student": "ann", "jobs": jobs}], lambda s, a: course / "submitted" / s / a,
                                lambda s, a: course / "feedback" / s / a, [out])
    assert marked == 1 and (feedback / "notes.html").read_text() == f"<html><body>{tmp_path}</body></html>"
    page = (feedback / "ex06_07_sensor_launch.html").read_text()
    assert "(Score: 10.0 / 10.0:" in page and "sensor-launch (hri_lab/sensor-launch): 10/10" in page
