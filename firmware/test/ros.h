// Test double of rosserial's ros_lib (ros.h) for host tests: the subset of
// ros::NodeHandle and ros::Publisher that force_node.h uses, with the same signatures as
// rosserial_client's node_handle.h and publisher.h (noetic-devel), recording every call.
// The "host side" (connected or not, the parameter's value, how long the reply takes) is
// a set of variables the test sets.
#ifndef FAKE_ROS_H
#define FAKE_ROS_H

#include <stdint.h>

#include <string>
#include <utility>
#include <vector>

#include "Arduino.h"

namespace ros {

class Msg
{
public:
  virtual ~Msg() {}
  // Not in rosserial: lets the double record what was published.
  virtual long fake_value() const { return 0; }
};

class Publisher;

}  // namespace ros

namespace fake {
struct Published {
  std::string topic;
  uint32_t t_ms;
  long value;
};
struct Log {
  std::string level;
  std::string text;
};
// The host: is serial_node connected, does it have the parameter, and what it answers.
static bool host_connected = false;
static bool param_set = false;
static int param_value = 0;
static uint32_t param_reply_ms = 20;  // the reply (or the timeout) takes this long
// What the board did.
static int init_calls = 0;
static int spin_calls = 0;
static std::vector<std::string> advertised;
static std::vector<std::string> param_requests;
static std::vector<Published> published;
static std::vector<Log> logs;
}  // namespace fake

namespace ros {

class Publisher
{
public:
  Publisher(const char *topic_name, Msg *msg, int endpoint = 0)
    : topic_(topic_name), msg_(msg), endpoint_(endpoint) {}

  int publish(const Msg *msg)
  {
    fake::Published p = {topic_, fake::now_ms, msg->fake_value()};
    fake::published.push_back(p);
    return 1;
  }

  const char *topic_;
  Msg *msg_;
  int endpoint_;
};

class NodeHandle
{
public:
  void initNode() { fake::init_calls++; }

  bool advertise(Publisher &p)
  {
    fake::advertised.push_back(p.topic_);
    return true;
  }

  int spinOnce()
  {
    fake::spin_calls++;
    return 0;
  }

  bool connected() { return fake::host_connected; }

  bool getParam(const char *name, int *param, int length = 1, int timeout = 1000)
  {
    fake::param_requests.push_back(name);
    if (!fake::host_connected || !fake::param_set || length != 1) {
      fake::now_ms += (uint32_t)timeout;  // rosserial waits for the reply until the timeout
      return false;
    }
    fake::now_ms += fake::param_reply_ms;
    *param = fake::param_value;
    return true;
  }

  void loginfo(const char *msg) { log("info", msg); }
  void logwarn(const char *msg) { log("warn", msg); }
  void logerror(const char *msg) { log("error", msg); }

private:
  void log(const char *level, const char *msg)
  {
    fake::Log entry = {level, msg};
    fake::logs.push_back(entry);
  }
};

}  // namespace ros

#endif  // FAKE_ROS_H
