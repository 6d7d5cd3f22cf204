#!/usr/bin/env python3
"""Simulated FSR sensor board (handout Ex. 1-2): publishes raw ADC counts on /pub_force.

It stands in for the lab's Arduino (``arduino_code_force_node.ino`` over rosserial): same topic,
same type (std_msgs/Int16, 0..1023), repeated smooth presses shaped through the FSR 402 model
(hri_teleop.sim.sensor_profile). Parameters: ``~rate_hz`` (10.0; the sketch sends about
3 Hz), ``~max_value`` (1023, the count at the top of a press: your /max_sensor_force makes
/force_mapped reach exactly 1), ``~period_s`` (4.0 s per press and release).
"""

from __future__ import annotations

import rospy
from std_msgs.msg import Int16

from hri_teleop.student import (
    ADC_MAX_COUNT,
    FSR_SENSOR_RATE_HZ,
    ClockError,
    NodeClock,
    fail,
    get_param,
    press_profile_count,
    refuse_beside_hardware,
    run_node,
)


def main() -> int:
    rospy.init_node("FSR_sensor")
    refuse_beside_hardware("the simulated board FSR_sensor.py")
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
