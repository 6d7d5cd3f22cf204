#!/usr/bin/env python3
# Last term's FSR_sensor.py: solutions/hri_lab/scripts/FSR_sensor.py at commit 69bb000 (before the layers).
"""Simulated FSR sensor board (handout Ex. 1-2): publishes raw ADC counts on /pub_force.

It stands in for the Arduino of the lab (``arduino_code_force_node.ino`` over
rosserial): same topic, same type (std_msgs/Int16, 0..1023). The values are repeated,
smooth presses of the piston shaped through the FSR 402 model
(hri_teleop.sensor_profile.press_profile_count).

Parameters (private):
  ~rate_hz    float  10.0    publish rate in Hz (the Arduino sketch sends about 3 Hz,
                             delay(300); the lab's teleoperation wants more)
  ~max_value  int    1023    count at the top of a press (1023 = full ADC range; set it to
                             your /max_sensor_force to see /force_mapped reach exactly 1)
  ~period_s   float  4.0     duration of one press-and-release cycle in seconds
Publishes:
  pub_force   std_msgs/Int16 (resolves to /pub_force in the root namespace)
"""

from __future__ import annotations

import rospy
from std_msgs.msg import Int16

from hri_teleop.mapping import ADC_MAX_COUNT
from hri_teleop.ros.clock import ClockError, NodeClock
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.sensor_profile import FSR_SENSOR_RATE_HZ, press_profile_count


def main() -> int:
    rospy.init_node("FSR_sensor")
    rate_hz = get_param("~rate_hz", FSR_SENSOR_RATE_HZ, kind=float, fix="set it to a rate in Hz, e.g. _rate_hz:=10")
    max_value = get_param("~max_value", ADC_MAX_COUNT, kind=int,
                          fix=f"set it to an ADC count in 1..{ADC_MAX_COUNT}, e.g. _max_value:=1023")
    period_s = get_param("~period_s", 4.0, kind=float, fix="set it to a duration in s, e.g. _period_s:=4.0")
    name = rospy.get_name()
    if not 0.0 < float(rate_hz) <= 1000.0:
        fail(f"parameter {name}/rate_hz is {rate_hz!r}; set it to a rate in Hz between 0 and 1000, e.g. _rate_hz:=10")
    if not 0 < int(max_value) <= ADC_MAX_COUNT:
        fail(f"parameter {name}/max_value is {max_value!r}; set it to an ADC count in 1..{ADC_MAX_COUNT}, e.g. _max_value:=1023")
    if not float(period_s) > 0.0:
        fail(f"parameter {name}/period_s is {period_s!r}; set it to a positive duration in seconds, e.g. _period_s:=4.0")

    pub = rospy.Publisher("pub_force", Int16, queue_size=10)
    rospy.loginfo("simulated FSR on %s: %.1f Hz, presses up to %d every %.1f s",
                  pub.resolved_name, rate_hz, max_value, period_s)
    clock = NodeClock()  # the wall clock, or /clock when the autograder owns the time
    try:
        start = clock.wait_started()
    except ClockError as exc:
        fail(str(exc))
    rate = rospy.Rate(float(rate_hz))
    while not rospy.is_shutdown():
        count = int(press_profile_count(clock.now() - start, float(period_s), int(max_value)))
        pub.publish(Int16(data=count))
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == "__main__":
    run_node(main)
