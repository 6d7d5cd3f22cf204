// Prints the line fsr_line.h makes for each "<seq> <count>" pair read from stdin, one per
// line, so that tests/unit/test_firmware_host.py can parse them with the Python parser
// (hri_teleop/core/serial_protocol.py): the two sides of the protocol checked against each other.
#include <stdio.h>

#include "fsr_line.h"

int main()
{
  unsigned long seq, count;
  char line[FSR_LINE_MAX + 8];
  while (scanf("%lu %lu", &seq, &count) == 2) {
    for (int i = 0; i < FSR_LINE_MAX + 8; ++i) line[i] = '#';
    uint8_t n = fsr_format_line(line, (uint16_t)seq, (uint16_t)count);
    if (n >= FSR_LINE_MAX || line[n] != '\0' || line[FSR_LINE_MAX] != '#') {
      fprintf(stderr, "line for %lu %lu overran FSR_LINE_MAX\n", seq, count);
      return 1;
    }
    fwrite(line, 1, n, stdout);
  }
  return 0;
}
