// Test double of the Arduino core for host tests (tests/unit/test_firmware_host.py): just
// what firmware/arduino_code_force_node/force_node.h calls. The clock and the analog
// inputs are plain variables the test sets; nothing here runs on a board.
#ifndef FAKE_ARDUINO_H
#define FAKE_ARDUINO_H

#include <stdint.h>

#define A0 14

namespace fake {
// millis() returns this; tests advance it. 32 bits, as on the Uno, so it wraps as there.
static uint32_t now_ms = 0;
// analogRead(pin) returns adc[pin - A0] for A0..A5 (and adc[pin] for 0..5, as the core).
static int adc[6] = {0, 0, 0, 0, 0, 0};
static int last_analog_pin = -1;
}  // namespace fake

static inline unsigned long millis() { return fake::now_ms; }

static inline int analogRead(uint8_t pin)
{
  if (pin >= A0) {
    pin = (uint8_t)(pin - A0);
  }
  fake::last_analog_pin = pin;
  return pin < 6 ? fake::adc[pin] : 0;
}

#endif  // FAKE_ARDUINO_H
