// The line protocol of fsr_serial.ino, version 1: "F <seq> <count> <crc>\n".
//
// Kept out of the sketch so that the host compiles it too (firmware/test/print_lines.cpp):
// the test suite checks every line this code makes against the Python parser,
// hri_teleop/core/serial_protocol.py, which documents the protocol in full.
//
//   seq    decimal 0..65535, +1 per sample, wraps; 0 again after every start of the board
//   count  decimal 0..1023, analogRead(A0)
//   crc    two upper-case hex digits: CRC-8 (polynomial 0x07, init 0, no reflection, no
//          final XOR) of every byte before the space in front of it ("F <seq> <count>")
//
// No sprintf: avr-libc's printf family costs about 1.5 KB of the Uno's 32 KB flash.
#ifndef FSR_LINE_H
#define FSR_LINE_H

#include <stdint.h>

// Longest line, "F 65535 1023 FF\n", plus the terminating NUL.
#define FSR_LINE_MAX 17

static inline uint8_t fsr_crc8_update(uint8_t crc, uint8_t byte) {
  crc ^= byte;
  for (uint8_t bit = 0; bit < 8; ++bit) {
    crc = (crc & 0x80) ? (uint8_t)((crc << 1) ^ 0x07) : (uint8_t)(crc << 1);
  }
  return crc;
}

// Appends the decimal digits of value to out; returns how many it wrote.
static inline uint8_t fsr_put_decimal(char *out, uint16_t value) {
  char digits[5];
  uint8_t n = 0;
  do {
    digits[n++] = (char)('0' + value % 10);
    value /= 10;
  } while (value != 0);
  for (uint8_t i = 0; i < n; ++i) {
    out[i] = digits[n - 1 - i];
  }
  return n;
}

// Writes the line for one sample into out (at least FSR_LINE_MAX bytes), NUL-terminated;
// returns its length without the NUL. Counts above 1023 are sent as 1023.
static inline uint8_t fsr_format_line(char *out, uint16_t seq, uint16_t count) {
  static const char hex[] = "0123456789ABCDEF";
  if (count > 1023) {
    count = 1023;
  }
  uint8_t n = 0;
  out[n++] = 'F';
  out[n++] = ' ';
  n += fsr_put_decimal(out + n, seq);
  out[n++] = ' ';
  n += fsr_put_decimal(out + n, count);
  uint8_t crc = 0;
  for (uint8_t i = 0; i < n; ++i) {
    crc = fsr_crc8_update(crc, (uint8_t)out[i]);
  }
  out[n++] = ' ';
  out[n++] = hex[crc >> 4];
  out[n++] = hex[crc & 0x0F];
  out[n++] = '\n';
  out[n] = '\0';
  return n;
}

#endif  // FSR_LINE_H
