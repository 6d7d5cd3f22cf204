// Host test of force_node.h (the rosserial sketch's logic) against the doubles in this folder.
//
//   g++ -std=gnu++11 -Wall -Wextra -Werror -I firmware/test -I firmware/arduino_code_force_node
//       firmware/test/test_force_node.cpp -o test_force_node
//   ./test_force_node --list          # the scenarios
//   ./test_force_node <scenario>      # exit 0 and "ok <scenario>", or exit 1 and why
//
// tests/unit/test_firmware_host.py compiles it and runs every scenario as its own test.
#include <stdio.h>
#include <string.h>

#include <string>
#include <vector>

#include <Arduino.h>
#include <ros.h>
#include <std_msgs/Int16.h>

#include "force_node.h"

static int failures = 0;

#define CHECK(cond, ...)                                       \
  do {                                                         \
    if (!(cond)) {                                             \
      failures++;                                              \
      fprintf(stderr, "%s:%d: %s: ", __FILE__, __LINE__, #cond); \
      fprintf(stderr, __VA_ARGS__);                            \
      fprintf(stderr, "\n");                                   \
    }                                                          \
  } while (0)

// The sketch's globals, as arduino_code_force_node.ino declares them.
struct Board {
  ros::NodeHandle nh;
  std_msgs::Int16 force_msg;
  ros::Publisher force_pub;
  ForceNode<ros::NodeHandle> node;
  Board() : force_pub("pub_force", &force_msg), node(nh, force_pub, force_msg, A0) {}
};

static void reset_world(uint32_t start_ms)
{
  fake::now_ms = start_ms;
  for (int i = 0; i < 6; ++i) fake::adc[i] = 0;
  fake::last_analog_pin = -1;
  fake::host_connected = false;
  fake::param_set = false;
  fake::param_value = 0;
  fake::param_reply_ms = 20;
  fake::init_calls = 0;
  fake::spin_calls = 0;
  fake::advertised.clear();
  fake::param_requests.clear();
  fake::published.clear();
  fake::logs.clear();
}

// Runs loop() for duration_ms of board time, one pass every step_ms.
static void run_for(Board &b, uint32_t duration_ms, uint32_t step_ms = 1)
{
  uint32_t start = fake::now_ms;
  while ((uint32_t)(fake::now_ms - start) < duration_ms) {
    b.node.step();
    fake::now_ms += step_ms;
  }
}

static bool any_log(const char *level, const char *needle)
{
  for (size_t i = 0; i < fake::logs.size(); ++i) {
    if (fake::logs[i].level == level && fake::logs[i].text.find(needle) != std::string::npos) return true;
  }
  return false;
}

static void check_intervals(uint32_t expected_ms, size_t from)
{
  for (size_t i = from + 1; i < fake::published.size(); ++i) {
    uint32_t dt = fake::published[i].t_ms - fake::published[i - 1].t_ms;
    CHECK(dt == expected_ms, "interval %zu is %lu ms, expected %lu", i, (unsigned long)dt,
          (unsigned long)expected_ms);
  }
}

static void initializes_the_node_and_advertises_pub_force_once()
{
  reset_world(0);
  Board b;
  b.node.begin();
  run_for(b, 100);
  CHECK(fake::init_calls == 1, "initNode called %d times", fake::init_calls);
  CHECK(fake::advertised.size() == 1 && fake::advertised[0] == "pub_force", "advertised %zu topics",
        fake::advertised.size());
}

static void spins_on_every_pass_and_publishes_nothing_before_the_host_connects()
{
  reset_world(0);
  Board b;
  b.node.begin();
  run_for(b, 1000);
  CHECK(fake::spin_calls == 1000, "spinOnce called %d times in 1000 passes", fake::spin_calls);
  CHECK(fake::published.empty(), "%zu messages published while not connected", fake::published.size());
  CHECK(fake::param_requests.empty(), "getParam called while not connected");
}

static void reads_the_period_parameter_once_after_connecting_and_publishes_at_it()
{
  reset_world(0);
  Board b;
  b.node.begin();
  run_for(b, 100);
  fake::host_connected = true;
  fake::param_set = true;
  fake::param_value = FORCE_NODE_RECOMMENDED_PERIOD_MS;
  run_for(b, 1000);
  CHECK(fake::param_requests.size() == 1, "getParam called %zu times", fake::param_requests.size());
  CHECK(!fake::param_requests.empty() && fake::param_requests[0] == "~publish_period_ms", "asked for %s",
        fake::param_requests.empty() ? "nothing" : fake::param_requests[0].c_str());
  CHECK(b.node.period_ms() == 10, "period %d ms", b.node.period_ms());
  // 1000 ms minus the 20 ms the parameter reply took, one message every 10 ms.
  CHECK(fake::published.size() >= 97 && fake::published.size() <= 99, "%zu messages in ~980 ms at 10 ms",
        fake::published.size());
  check_intervals(10, 0);
  for (size_t i = 0; i < fake::published.size(); ++i) {
    CHECK(fake::published[i].topic == "pub_force", "published on %s", fake::published[i].topic.c_str());
  }
}

static void falls_back_to_the_handouts_300_ms_without_the_parameter()
{
  reset_world(0);
  Board b;
  b.node.begin();
  fake::host_connected = true;
  run_for(b, 2000);
  CHECK(b.node.period_ms() == 300, "period %d ms", b.node.period_ms());
  CHECK(fake::published.size() == 5, "%zu messages in 1.5 s after the 0.5 s timeout", fake::published.size());
  check_intervals(300, 0);
  CHECK(any_log("warn", "300 ms (handout)"), "no warning naming the 300 ms fallback");
  CHECK(any_log("warn", "10 recommended"), "the warning does not recommend 10 ms");
}

static void refuses_a_period_outside_5_to_10000_ms_and_uses_300_ms()
{
  const int bad[] = {0, -5, 4, 10001, 32000};
  for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
    reset_world(0);
    Board b;
    b.node.begin();
    fake::host_connected = true;
    fake::param_set = true;
    fake::param_value = bad[k];
    run_for(b, 700);
    CHECK(b.node.period_ms() == 300, "with %d: period %d ms", bad[k], b.node.period_ms());
    CHECK(any_log("warn", "not in 5..10000"), "with %d: no warning", bad[k]);
  }
  const int good[] = {5, 10, 300, 10000};
  for (size_t k = 0; k < sizeof(good) / sizeof(good[0]); ++k) {
    reset_world(0);
    Board b;
    b.node.begin();
    fake::host_connected = true;
    fake::param_set = true;
    fake::param_value = good[k];
    run_for(b, 50);
    CHECK(b.node.period_ms() == good[k], "with %d: period %d ms", good[k], b.node.period_ms());
  }
}

static void publishes_the_reading_of_a0_taken_when_the_sample_is_due()
{
  reset_world(0);
  Board b;
  b.node.begin();
  fake::host_connected = true;
  fake::param_set = true;
  fake::param_value = 50;
  uint32_t start = fake::now_ms;
  while ((uint32_t)(fake::now_ms - start) < 1000) {
    fake::adc[0] = (int)((fake::now_ms * 7) % 1024);  // changes every millisecond
    fake::adc[1] = 999;                               // another pin: must not be read
    size_t before = fake::published.size();
    b.node.step();
    if (fake::published.size() > before) {
      long got = fake::published.back().value;
      CHECK(got == fake::adc[0], "published %ld, A0 read %d", got, fake::adc[0]);
    }
    fake::now_ms += 1;
  }
  CHECK(fake::last_analog_pin == 0, "read analog pin %d, not A0", fake::last_analog_pin);
  CHECK(fake::published.size() >= 19, "%zu messages", fake::published.size());
}

static void reads_the_parameter_again_after_a_reconnect()
{
  reset_world(0);
  Board b;
  b.node.begin();
  fake::host_connected = true;
  fake::param_set = true;
  fake::param_value = 10;
  run_for(b, 200);
  CHECK(b.node.period_ms() == 10, "period %d ms", b.node.period_ms());
  fake::host_connected = false;  // serial_node restarted
  run_for(b, 200);
  size_t before = fake::published.size();
  run_for(b, 200);
  CHECK(fake::published.size() == before, "published while disconnected");
  fake::param_value = 50;
  fake::host_connected = true;
  run_for(b, 500);
  CHECK(fake::param_requests.size() == 2, "getParam called %zu times", fake::param_requests.size());
  CHECK(b.node.period_ms() == 50, "after reconnect: period %d ms", b.node.period_ms());
}

static void keeps_its_period_across_the_millis_wraparound()
{
  reset_world(0xFFFFFFFFUL - 505UL);  // millis() wraps after about 49.7 days
  Board b;
  b.node.begin();
  fake::host_connected = true;
  fake::param_set = true;
  fake::param_value = 10;
  run_for(b, 1000);
  CHECK(fake::now_ms < 1000, "the clock did not wrap (now %lu)", (unsigned long)fake::now_ms);
  CHECK(fake::published.size() >= 97, "%zu messages across the wrap", fake::published.size());
  check_intervals(10, 0);
}

static void does_not_burst_after_a_long_stall()
{
  reset_world(0);
  Board b;
  b.node.begin();
  fake::host_connected = true;
  fake::param_set = true;
  fake::param_value = 10;
  run_for(b, 100);
  size_t before = fake::published.size();
  fake::now_ms += 95;  // loop() held up for 95 ms (e.g. a slow spinOnce)
  run_for(b, 5);
  CHECK(fake::published.size() - before == 1, "%zu messages right after the stall, expected 1",
        fake::published.size() - before);
}

struct Scenario {
  const char *name;
  void (*run)();
};

static const Scenario scenarios[] = {
  {"initializes_the_node_and_advertises_pub_force_once", initializes_the_node_and_advertises_pub_force_once},
  {"spins_on_every_pass_and_publishes_nothing_before_the_host_connects",
   spins_on_every_pass_and_publishes_nothing_before_the_host_connects},
  {"reads_the_period_parameter_once_after_connecting_and_publishes_at_it",
   reads_the_period_parameter_once_after_connecting_and_publishes_at_it},
  {"falls_back_to_the_handouts_300_ms_without_the_parameter", falls_back_to_the_handouts_300_ms_without_the_parameter},
  {"refuses_a_period_outside_5_to_10000_ms_and_uses_300_ms", refuses_a_period_outside_5_to_10000_ms_and_uses_300_ms},
  {"publishes_the_reading_of_a0_taken_when_the_sample_is_due", publishes_the_reading_of_a0_taken_when_the_sample_is_due},
  {"reads_the_parameter_again_after_a_reconnect", reads_the_parameter_again_after_a_reconnect},
  {"keeps_its_period_across_the_millis_wraparound", keeps_its_period_across_the_millis_wraparound},
  {"does_not_burst_after_a_long_stall", does_not_burst_after_a_long_stall},
};

int main(int argc, char **argv)
{
  const size_t n = sizeof(scenarios) / sizeof(scenarios[0]);
  if (argc == 2 && strcmp(argv[1], "--list") == 0) {
    for (size_t i = 0; i < n; ++i) printf("%s\n", scenarios[i].name);
    return 0;
  }
  int ran = 0;
  for (size_t i = 0; i < n; ++i) {
    if (argc == 1 || strcmp(argv[1], scenarios[i].name) == 0) {
      int before = failures;
      scenarios[i].run();
      printf("%s %s\n", failures == before ? "ok" : "FAIL", scenarios[i].name);
      ran++;
    }
  }
  if (ran == 0) {
    fprintf(stderr, "no scenario named %s; --list shows them\n", argc > 1 ? argv[1] : "");
    return 2;
  }
  return failures == 0 ? 0 : 1;
}
