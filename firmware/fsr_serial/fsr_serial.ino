// fsr_serial: the FSR count over plain USB serial at 100 Hz, without rosserial.
//
// Same measurement as the handout's arduino_code_force_node.ino (Ex. 1, 11): the FSR and a
// 10 kOhm pull-down form a divider read on A0. Instead of rosserial (about 3 samples a
// second in the handout), it sends one text line per sample at 115200 baud:
//
//   "# fsr_serial v1 period_us=10000 baud=115200\n"   once at start-up (the banner)
//   "F <seq> <count> <crc>\n"                         then every 10 ms, e.g. "F 1234 517 3C\n"
//
// seq (0..65535, +1 per line, wraps) lets the host count lost lines, crc (CRC-8, two hex
// digits) lets it spot corrupt ones; fsr_line.h and hri_teleop/core/serial_protocol.py document
// the protocol. On the host: `roslaunch hri_lab teleoperation.launch board:=serial`
// (hri_lab/scripts/serial_bridge.py publishes /pub_force), or without ROS
// `python -m hri_teleop.calibrate --port /dev/ttyACM0` (Ex. 11). The Serial Monitor of
// the Arduino IDE (115200 baud) shows the lines as they are.
//
// Timing: samples are due every SAMPLE_PERIOD_US on a fixed grid of micros() (no drift,
// no delay()). A line that does not fit into the send buffer is dropped, never waited for,
// so a host that stops reading cannot slow the sampling; the gap in seq reports the loss.
#include "fsr_line.h"

const uint8_t FSR_PIN = A0;                   // the FSR and the 10 kOhm pull-down meet here
const unsigned long BAUD = 115200;            // 100 lines/s * at most 16 bytes = 14 % of it
const unsigned long SAMPLE_PERIOD_US = 10000; // 100 Hz; the Uno's analogRead takes ~0.11 ms

uint16_t seq = 0;            // sequence number of the next line
unsigned long next_due_us;   // when the next sample is due (micros())

void setup()
{
  Serial.begin(BAUD);
  Serial.print(F("# fsr_serial v1 period_us="));
  Serial.print(SAMPLE_PERIOD_US);
  Serial.print(F(" baud="));
  Serial.print(BAUD);
  Serial.print('\n');
  next_due_us = micros();
}

void loop()
{
  unsigned long now_us = micros();
  if ((long)(now_us - next_due_us) < 0) {
    return;  // not due yet
  }
  next_due_us += SAMPLE_PERIOD_US;
  if ((long)(now_us - next_due_us) >= 0) {
    next_due_us = now_us + SAMPLE_PERIOD_US;  // fell a whole period behind: do not burst
  }

  int fsr_analog_reading = analogRead(FSR_PIN);

  char line[FSR_LINE_MAX];
  uint8_t length = fsr_format_line(line, seq, (uint16_t)fsr_analog_reading);
  seq++;
  if (Serial.availableForWrite() >= length) {
    Serial.write((const uint8_t *)line, length);
  }
}
