// What arduino_code_force_node.ino does, in a class the host can compile and test.
//
// Why a header: the sketch needs the rosserial Arduino library (ros_lib), which exists only
// where rosserial is installed. This file uses nothing of it but the calls below, so
// firmware/test/ holds small stand-ins for ros.h, std_msgs/Int16.h and Arduino.h, and
// tests/unit/test_firmware_host.py compiles this logic with g++ and checks it.
//
// The handout's listing (Ex. 1), corrected:
//   * its line 27 does not compile (the course's Ex. 1 asks which name is wrong, so the
//     student bundle ships this file): here the reading is declared where it is taken and
//     that value is published;
//   * it published every delay(300) ms, about 3 counts a second, too slow for haptic
//     feedback: the period now comes from the ROS parameter ~publish_period_ms, read once
//     the board has connected to rosserial_python's serial_node (so it resolves to
//     /serial_node/publish_period_ms), and again after every reconnect. Without it, or
//     with a value outside 5..10000 ms, the handout's 300 ms stays; 10 ms (100 Hz) is the
//     recommended value (Int16 over rosserial at 57600 baud: 10 bytes a message, under
//     a fifth of the line);
//   * no delay(): samples fall on a fixed millis() grid and spinOnce() runs on every pass
//     of loop(), so rosserial's time sync and parameter replies are never kept waiting.
#ifndef FORCE_NODE_H
#define FORCE_NODE_H

#include <Arduino.h>
#include <ros.h>
#include <std_msgs/Int16.h>

// The handout's delay(300): the period when the parameter is missing or unusable.
const int FORCE_NODE_DEFAULT_PERIOD_MS = 300;
// What we recommend setting: 100 Hz, as the plain-serial sketch (fsr_serial) sends.
const int FORCE_NODE_RECOMMENDED_PERIOD_MS = 10;
// Accepted range of the parameter. Below 5 ms rosserial at 57600 baud has no room left
// for its own traffic; above 10 s the sensor is effectively off.
const int FORCE_NODE_MIN_PERIOD_MS = 5;
const int FORCE_NODE_MAX_PERIOD_MS = 10000;
// How long getParam waits for serial_node's answer (it sends none for a missing
// parameter, so this is the delay before the fallback applies).
const int FORCE_NODE_PARAM_TIMEOUT_MS = 500;
#define FORCE_NODE_PERIOD_PARAM "~publish_period_ms"

// NodeHandle: the sketch's rosserial node handle type (ros::NodeHandle or a smaller
// ros::NodeHandle_<...>); any class with rosserial's initNode/advertise/spinOnce/
// connected/getParam/loginfo/logwarn will do, which is how the host test runs it.
template <class NodeHandle>
class ForceNode
{
public:
  ForceNode(NodeHandle &nh, ros::Publisher &pub, std_msgs::Int16 &msg, uint8_t fsr_pin)
    : nh_(nh), pub_(pub), msg_(msg), fsr_pin_(fsr_pin),
      period_ms_(FORCE_NODE_DEFAULT_PERIOD_MS), configured_(false), last_publish_ms_(0)
  {
  }

  // setup(): initialize the ROS node and create the publisher (handout lines 17-21).
  void begin()
  {
    nh_.initNode();
    nh_.advertise(pub_);
  }

  // loop(): one pass; publishes when a sample is due, never waits.
  void step()
  {
    nh_.spinOnce();
    if (!nh_.connected()) {
      configured_ = false;  // read the parameter again after the next (re)connect
      return;
    }
    if (!configured_) {
      period_ms_ = read_period_ms();
      configured_ = true;
      last_publish_ms_ = (uint32_t)millis() - (uint32_t)period_ms_;  // first sample right away
    }
    // uint32_t, as unsigned long is on the Uno: the differences stay right when millis()
    // wraps after 49.7 days (and the host test, where unsigned long is wider, checks it).
    uint32_t now_ms = (uint32_t)millis();
    if ((uint32_t)(now_ms - last_publish_ms_) < (uint32_t)period_ms_) {
      return;
    }
    last_publish_ms_ += (uint32_t)period_ms_;
    if ((uint32_t)(now_ms - last_publish_ms_) >= (uint32_t)period_ms_) {
      last_publish_ms_ = now_ms;  // fell a whole period behind: do not publish in bursts
    }

    // Read the sensor value on the analog pin and publish it (handout lines 26-31).
    int fsr_analog_reading = analogRead(fsr_pin_);
    msg_.data = fsr_analog_reading;
    pub_.publish(&msg_);
  }

  // The publish period in use (ms).
  int period_ms() const { return period_ms_; }

private:
  // The messages are short on purpose: rosserial's log calls take RAM strings, not flash.
  int read_period_ms()
  {
    int value = 0;
    if (!nh_.getParam(FORCE_NODE_PERIOD_PARAM, &value, 1, FORCE_NODE_PARAM_TIMEOUT_MS)) {
      nh_.logwarn("no ~publish_period_ms: 300 ms (handout); 10 recommended");
      return FORCE_NODE_DEFAULT_PERIOD_MS;
    }
    if (value < FORCE_NODE_MIN_PERIOD_MS || value > FORCE_NODE_MAX_PERIOD_MS) {
      nh_.logwarn("~publish_period_ms not in 5..10000: 300 ms; 10 recommended");
      return FORCE_NODE_DEFAULT_PERIOD_MS;
    }
    nh_.loginfo("period from ~publish_period_ms");
    return value;
  }

  NodeHandle &nh_;
  ros::Publisher &pub_;
  std_msgs::Int16 &msg_;
  uint8_t fsr_pin_;
  int period_ms_;
  bool configured_;
  uint32_t last_publish_ms_;
};

#endif  // FORCE_NODE_H
