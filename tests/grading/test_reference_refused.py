"""A node that delegates its exercise to the toolkit's reference rule gets no points, with the reason."""

from __future__ import annotations

import pytest

from hri_teleop.grading.exercises.mapping_node.check import grade_mapping_node

pytestmark = pytest.mark.ros

CHEAT = '''#!/usr/bin/env python3
import rospy
from std_msgs.msg import Float32, Int16
from hri_teleop.core.mapping import map_force


def main():
    rospy.init_node("mapping_node")
    pub = rospy.Publisher("/force_mapped", Float32, queue_size=10)
    rospy.Subscriber("/pub_force", Int16, lambda m: pub.publish(Float32(map_force(m.data, rospy.get_param("/max_sensor_force")))))
    rospy.spin()


if __name__ == "__main__":
    main()
'''


def test_a_mapping_node_that_imports_map_force_scores_zero_and_is_told_to_write_the_rule(tmp_path):
    package = tmp_path / "hri_lab"
    (package / "scripts").mkdir(parents=True)
    (package / "scripts" / "mapping_node.py").write_text(CHEAT)
    result = grade_mapping_node(package, seed=1)
    assert result.score == 0 and result.max_score > 0
    first = result.parts[0]
    assert first.message.startswith("mapping_node.py uses the lab's reference implementation (line 4: from "
                                    "hri_teleop.core.mapping import map_force")
    assert all(p.message == "not judged: the file uses the lab's reference implementation" for p in result.parts[1:])
