/*
 * uno_sim: a simulated Arduino Uno (ATmega328P, 16 MHz, over libsimavr) that runs a compiled
 * sketch, drives its A0 with a voltage profile and exposes its serial port as a pseudo-terminal.
 *
 * Why: the plain-serial sketch (fsr_serial) and everything behind it -- the serial bridge,
 * /pub_force, the mapping node, the calibration CLI -- can then be tested end to end on a
 * machine without a board: the same firmware image that would be flashed runs here, and the
 * host programs open a serial port exactly as they would open /dev/ttyACM0.
 *
 *   uno_sim --firmware build/fsr_serial/fsr_serial.elf --link /tmp/x/ttyACM0 \
 *           [--profile volts.txt] [--repeat-us N] [--speed 1.0] [--quiet]
 *
 * --link PATH     a symbolic link to the pseudo-terminal is made at PATH (atomically);
 *                 open PATH as the serial port (any baud; a pty has none).
 * --profile FILE  the A0 voltage: lines "<t_us> <microvolts>", t ascending, '#' comments.
 *                 Each value holds from its time on (zero-order hold); before the first line
 *                 A0 reads 0 V. Time is the board's own, counted while it is powered.
 *                 hri_teleop/hardware/sim/simavr_board.py writes these files from a force profile and
 *                 the FSR model (hri_teleop/core/fsr.py).
 * --repeat-us N   the profile repeats every N microseconds.
 * --speed S       simulated seconds per wall-clock second (default 1: real time, so the
 *                 sample rate seen by the host is the firmware's own).
 *
 * Signals: SIGUSR1 unplugs the USB cable (the pseudo-terminal closes, the link goes, the
 * board loses power and stops); SIGUSR2 plugs it back in (a new pseudo-terminal behind the
 * same link, the board starts again from reset, as an Uno does on power-up). SIGINT and
 * SIGTERM end the program and remove the link.
 *
 * stdout: one line "uno_sim: plugged <link> -> <pty>" per plug-in, "uno_sim: unplugged" per
 * unplug. Bytes the host sends reach the board's UART receiver (paced by simavr's receive
 * FIFO), so a sketch that talks both ways (rosserial) works too. When the host does not
 * read, the pty fills up and further bytes from the board are dropped, as the Uno's
 * USB-serial chip drops them; fsr_serial's sequence numbers show the gap.
 *
 * ADC: the ATmega328P converts as count = floor(Vin * 1024 / Vref), Vref = AVCC = 5 V here
 * (hri_teleop.core.fsr.voltage_to_count does the same). simavr 1.6 instead takes the input in
 * whole millivolts and computes floor(mV * 1023 / Vref_mV). So this program converts each
 * profile voltage to its count itself, exactly, and hands simavr count * 50 with AVCC set to
 * 51150 (= 50 * 1023): simavr's arithmetic then returns that count unchanged. (AVCC is used
 * by nothing else in the simulated chip.)
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <pty.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <avr_adc.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_irq.h>

#define MCU_NAME "atmega328p"
#define F_CPU_HZ 16000000UL
#define SUPPLY_UV 5000000ULL
/* See "ADC" above: simavr returns floor(x * 1023 / AVCC); x = count * 50, AVCC = 51150. */
#define SIMAVR_AVCC 51150
#define SIMAVR_PER_COUNT 50
/* How many instructions to run between looks at the clock, the signals and the pty. */
#define BATCH 2000
/* How far the simulation may run ahead of the wall clock before it sleeps. */
#define AHEAD_NS 2000000LL

typedef struct {
  uint64_t t_us;
  uint16_t count; /* the ADC count of the point's voltage */
} point_t;

/* The ATmega328P's conversion of a voltage (microvolts) with a 5 V reference. */
static uint16_t adc_count(uint64_t microvolts)
{
  uint64_t count = microvolts * 1024ULL / SUPPLY_UV;
  return (uint16_t)(count > 1023 ? 1023 : count);
}

static volatile sig_atomic_t want_unplug = 0, want_plug = 0, want_quit = 0;

static void on_signal(int sig)
{
  if (sig == SIGUSR1) want_unplug = 1;
  else if (sig == SIGUSR2) want_plug = 1;
  else want_quit = 1;
}

static void die(const char *what)
{
  fprintf(stderr, "uno_sim: %s\n", what);
  exit(2);
}

typedef struct {
  avr_t *avr;
  int master;      /* our end of the pty; -1 while unplugged */
  int slave_keep;  /* a slave fd kept open so that the host may close and reopen the port */
  const char *link;
  uint64_t dropped_bytes;
  int rx_ready;    /* simavr's receive FIFO has room (its XON/XOFF signals) */
  uint8_t in[4096];/* bytes from the host not yet given to the UART */
  size_t in_len, in_pos;
} board_t;

static void uart_xon(struct avr_irq_t *irq, uint32_t value, void *param)
{
  (void)irq;
  (void)value;
  ((board_t *)param)->rx_ready = 1;
}

static void uart_xoff(struct avr_irq_t *irq, uint32_t value, void *param)
{
  (void)irq;
  (void)value;
  ((board_t *)param)->rx_ready = 0;
}

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
  (void)irq;
  board_t *b = (board_t *)param;
  if (b->master < 0) return;
  uint8_t byte = (uint8_t)value;
  ssize_t n = write(b->master, &byte, 1);
  if (n != 1) b->dropped_bytes++;
}

static point_t *read_profile(const char *path, size_t *count)
{
  FILE *f = fopen(path, "r");
  if (!f) {
    char msg[PATH_MAX + 100];
    snprintf(msg, sizeof msg, "cannot read the profile %s: %s; pass --profile with a file of '<t_us> <uV>' lines",
             path, strerror(errno));
    die(msg);
  }
  size_t cap = 64, n = 0;
  point_t *pts = malloc(cap * sizeof *pts);
  char line[256];
  unsigned lineno = 0;
  while (fgets(line, sizeof line, f)) {
    lineno++;
    char *p = line;
    while (*p == ' ' || *p == '\t') p++;
    if (*p == '#' || *p == '\n' || *p == '\0') continue;
    unsigned long long t, uv;
    if (sscanf(p, "%llu %llu", &t, &uv) != 2 || uv > SUPPLY_UV || (n > 0 && t < pts[n - 1].t_us)) {
      char msg[PATH_MAX + 160];
      snprintf(msg, sizeof msg, "%s line %u: expected '<t_us> <uV>' with t ascending and 0 <= uV <= %llu; fix the file",
               path, lineno, SUPPLY_UV);
      die(msg);
    }
    if (n == cap) {
      cap *= 2;
      pts = realloc(pts, cap * sizeof *pts);
    }
    pts[n].t_us = t;
    pts[n].count = adc_count(uv);
    n++;
  }
  fclose(f);
  *count = n;
  return pts;
}

static void unplug(board_t *b)
{
  if (b->master < 0) return;
  close(b->master);
  close(b->slave_keep);
  b->master = b->slave_keep = -1;
  b->in_len = b->in_pos = 0;
  unlink(b->link);
  printf("uno_sim: unplugged\n");
  fflush(stdout);
}

static void plug(board_t *b)
{
  char name[128];
  int master, slave;
  if (openpty(&master, &slave, name, NULL, NULL) != 0) die("openpty failed: is /dev/pts mounted?");
  struct termios tio;
  if (tcgetattr(slave, &tio) == 0) {
    cfmakeraw(&tio);
    tcsetattr(slave, TCSANOW, &tio);
  }
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
  fcntl(master, F_SETFD, FD_CLOEXEC);
  fcntl(slave, F_SETFD, FD_CLOEXEC);
  char tmp[PATH_MAX];
  snprintf(tmp, sizeof tmp, "%s.new", b->link);
  unlink(tmp);
  if (symlink(name, tmp) != 0 || rename(tmp, b->link) != 0) {
    char msg[PATH_MAX + 100];
    snprintf(msg, sizeof msg, "cannot make the link %s: %s; pass --link in a writable folder", b->link,
             strerror(errno));
    die(msg);
  }
  b->master = master;
  b->slave_keep = slave;
  printf("uno_sim: plugged %s -> %s\n", b->link, name);
  fflush(stdout);
}

static int64_t now_ns(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void sleep_ns(int64_t ns)
{
  struct timespec ts = {(time_t)(ns / 1000000000LL), (long)(ns % 1000000000LL)};
  nanosleep(&ts, NULL);
}

/* simavr's messages: errors only, on stderr, marked as ours ("Loaded 2754 .text" is noise). */
static int log_level = LOG_ERROR;
static void logger(avr_t *avr, const int level, const char *format, va_list ap)
{
  (void)avr;
  if (level > log_level) return;
  fputs("uno_sim: simavr: ", stderr);
  vfprintf(stderr, format, ap);
}

static void usage(void)
{
  fprintf(stderr,
          "usage: uno_sim --firmware ELF --link PATH [--profile FILE] [--repeat-us N] [--speed S] [--quiet]\n"
          "  (see the comment at the top of firmware/sim/uno_sim.c)\n");
  exit(2);
}

int main(int argc, char **argv)
{
  const char *firmware = NULL, *link = NULL, *profile_path = NULL;
  uint64_t repeat_us = 0;
  double speed = 1.0;
  int quiet = 0;
  static const struct option options[] = {
    {"firmware", required_argument, 0, 'f'}, {"link", required_argument, 0, 'l'},
    {"profile", required_argument, 0, 'p'},  {"repeat-us", required_argument, 0, 'r'},
    {"speed", required_argument, 0, 's'},    {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, 'h'},           {0, 0, 0, 0},
  };
  int opt;
  while ((opt = getopt_long(argc, argv, "", options, NULL)) != -1) {
    switch (opt) {
      case 'f': firmware = optarg; break;
      case 'l': link = optarg; break;
      case 'p': profile_path = optarg; break;
      case 'r': repeat_us = strtoull(optarg, NULL, 10); break;
      case 's': speed = atof(optarg); break;
      case 'q': quiet = 1; break;
      default: usage();
    }
  }
  if (!firmware || !link || optind != argc) usage();
  if (!(speed > 0.0 && speed <= 100.0)) die("--speed must be in (0, 100]; 1 is real time");

  size_t npoints = 0;
  point_t *points = profile_path ? read_profile(profile_path, &npoints) : NULL;

  log_level = quiet ? LOG_NONE : LOG_ERROR;
  avr_global_logger_set(logger);
  elf_firmware_t fw;
  memset(&fw, 0, sizeof fw);
  if (access(firmware, R_OK) != 0 || elf_read_firmware(firmware, &fw) != 0) {
    char msg[PATH_MAX + 100];
    snprintf(msg, sizeof msg, "cannot load the firmware %s; build it with 'make firmware'", firmware);
    die(msg);
  }
  avr_t *avr = avr_make_mcu_by_name(MCU_NAME);
  if (!avr) die("libsimavr has no " MCU_NAME);
  avr_init(avr);
  avr->log = log_level;
  avr_load_firmware(avr, &fw);
  avr->frequency = F_CPU_HZ;
  avr->avcc = SIMAVR_AVCC;

  board_t board;
  memset(&board, 0, sizeof board);
  board.avr = avr;
  board.master = board.slave_keep = -1;
  board.link = link;
  board.rx_ready = 1;
  /* No "UART0: ..." echo of every line on our stdout. */
  uint32_t flags = 0;
  avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~AVR_UART_FLAG_STDIO;
  avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), uart_out, &board);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), uart_xon, &board);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), uart_xoff, &board);
  avr_irq_t *uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_t *adc0 = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0);

  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGUSR1, &sa, NULL);
  sigaction(SIGUSR2, &sa, NULL);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  signal(SIGPIPE, SIG_IGN);

  plug(&board);
  uint64_t powered_us_before = 0;   /* board time of earlier power-ups */
  avr_cycle_count_t cycle0 = avr->cycle;
  int64_t wall0 = now_ns();
  size_t next_point = 0;            /* index of the next profile point to apply */
  uint64_t profile_round = 0;       /* with --repeat-us: which repetition we are in */
  int lag_reported = 0;
  avr_raise_irq(adc0, 0);

  while (!want_quit) {
    if (want_unplug) {
      want_unplug = 0;
      if (board.master >= 0) {
        powered_us_before += (uint64_t)((avr->cycle - cycle0) / (F_CPU_HZ / 1000000UL));
        unplug(&board);
      }
    }
    if (want_plug) {
      want_plug = 0;
      if (board.master < 0) {
        avr_reset(avr);
        avr->avcc = SIMAVR_AVCC;
        plug(&board);
        cycle0 = avr->cycle;
        wall0 = now_ns();
      }
    }
    if (board.master < 0) {
      sleep_ns(10000000LL);
      continue;
    }
    for (int i = 0; i < BATCH; ++i) {
      if (npoints) {
        uint64_t t_us = powered_us_before + (uint64_t)((avr->cycle - cycle0) / (F_CPU_HZ / 1000000UL));
        if (repeat_us) {
          uint64_t round = t_us / repeat_us;
          if (round != profile_round) {
            profile_round = round;
            next_point = 0;
          }
          t_us %= repeat_us;
        }
        while (next_point < npoints && points[next_point].t_us <= t_us) {
          avr_raise_irq(adc0, (uint32_t)points[next_point].count * SIMAVR_PER_COUNT);
          next_point++;
        }
      }
      if (board.in_pos < board.in_len && board.rx_ready) {
        avr_raise_irq(uart_in, board.in[board.in_pos++]);
      }
      int state = avr_run(avr);
      if (state == cpu_Done || state == cpu_Crashed) {
        unplug(&board);
        die(state == cpu_Crashed ? "the firmware crashed (see simavr's message above)" : "the firmware stopped");
      }
    }
    /* Real time: sleep while the board is ahead of the wall clock. */
    int64_t sim_ns = (int64_t)((double)(avr->cycle - cycle0) * 1e9 / (double)F_CPU_HZ / speed);
    int64_t wall_ns = now_ns() - wall0;
    if (sim_ns > wall_ns + AHEAD_NS) {
      sleep_ns(sim_ns - wall_ns);
    } else if (!lag_reported && wall_ns - sim_ns > 500000000LL) {
      lag_reported = 1;
      fprintf(stderr, "uno_sim: the simulation runs slower than real time (%.1f s behind); the board's rate "
              "seen by the host will be lower than the firmware's\n", (wall_ns - sim_ns) / 1e9);
    }
    /* What the host sent, for the UART's receiver (read more once the last is delivered). */
    if (board.master >= 0 && board.in_pos == board.in_len) {
      ssize_t n = read(board.master, board.in, sizeof board.in);
      board.in_pos = 0;
      board.in_len = n > 0 ? (size_t)n : 0;
    }
  }
  unplug(&board);
  avr_terminate(avr);
  free(points);
  return 0;
}
