#!/usr/bin/env python3
"""Handout Ex. 5: map the raw FSR count on /pub_force to a float 0..1 on /force_mapped.

The Arduino (or FSR_sensor.py) publishes the 10-bit ADC count as std_msgs/Int16 on
/pub_force. With the piston pressed level with the housing the count reaches about 700
(Ex. 11); that count is set on the parameter server as /max_sensor_force. This node maps
0../max_sensor_force to 0.0..1.0 and publishes it as std_msgs/Float32 on /force_mapped,
one message for every count. A count above the maximum (a firmer press) gives 1.0.

Run it:  rosparam set /max_sensor_force 700 && rosrun hri_lab mapping_node.py
"""

import rospy
from std_msgs.msg import Float32, Int16


class MappingNode:
    """Object-oriented node as in Task 2: set up in __init__, work in the callback."""

    def __init__(self):
        # Read /max_sensor_force from the parameter server, create the publisher of
        # /force_mapped and the subscriber of /pub_force (callback: self.callback).
        self.max_sensor_force = 700
        self.publisher = rospy.Publisher("/force_mapped", Float32, queue_size=10)
        self.subscriber = rospy.Subscriber("/pub_force", Int16, self.callback)

    def map_force(self, count):
        """The count as a float 0..1 over 0..max_sensor_force; above the maximum 1.0."""
        mapped = float(count) / float(self.max_sensor_force)
        return min(1.0, max(0.0, mapped))

    def callback(self, msg):
        """Called for every message on /pub_force: publish its mapped value."""
        self.publisher.publish(Float32(self.map_force(msg.data)))


if __name__ == "__main__":
    rospy.init_node("mapping_node")
    MappingNode()
    rospy.spin()
