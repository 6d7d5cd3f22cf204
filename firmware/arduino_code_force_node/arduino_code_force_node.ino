// arduino_code_force_node: the handout's rosserial sketch (Ex. 1, 11), corrected.
//
// The Uno reads the FSR divider on A0 and publishes the raw 10-bit count (0..1023) as
// std_msgs/Int16 on /pub_force through rosserial. On the host:
//   rosrun rosserial_python serial_node.py _port:=/dev/ttyACM0 _baud:=57600 _publish_period_ms:=10
// or `roslaunch hri_lab teleoperation.launch board:=rosserial`.
//
// Publish period: the ROS parameter ~publish_period_ms of serial_node (ms), read once the
// board has connected and again after every reconnect. Without it: 300 ms, the handout's
// delay(300). Recommended: 10 ms (100 Hz). force_node.h has the logic and the reasons;
// it is compiled and tested on the host (tests/unit/test_firmware_host.py).
//
// Building needs the rosserial Arduino library (ros_lib). Make it on a machine with ROS:
//   rosrun rosserial_arduino make_libraries.py ~/Arduino/libraries
// (or install "Rosserial Arduino Library" from the Arduino IDE's library manager).
#include <ros.h>
#include <std_msgs/Int16.h>

#include "force_node.h"

// Create a Node handle. rosserial's default ros::NodeHandle reserves room for 25 publishers,
// 25 subscribers and two 280-byte buffers on an Uno: 85 % of its 2 KB of RAM for one
// publisher, and the Arduino IDE warns "Low memory available". This one is rosserial's own
// size for the smaller ATmega168 (6 publishers, 6 subscribers, 150-byte buffers).
typedef ros::NodeHandle_<ArduinoHardware, 6, 6, 150, 150> NodeHandle;
NodeHandle nh;

// Declare message and Publisher
std_msgs::Int16 force_msg;
ros::Publisher force_pub("pub_force", &force_msg);

const uint8_t fsr_pin = A0;  // the FSR and 10K resistor are connected to pin A0

ForceNode<NodeHandle> force_node(nh, force_pub, force_msg, fsr_pin);

void setup()
{
  // Initializing ROS Node and creating the Publisher object
  force_node.begin();
}

void loop()
{
  // Processing of ROS (spinOnce), reading A0 and publishing when a sample is due;
  // the period comes from ~publish_period_ms (300 ms without it)
  force_node.step();
}
