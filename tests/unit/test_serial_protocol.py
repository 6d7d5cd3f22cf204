"""The plain-serial board's line protocol (hri_teleop.core.serial_protocol): parse, check, count."""

from __future__ import annotations

import errno

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.serial_protocol import (
    MAX_LINE_BYTES,
    BoardInfo,
    BoardStream,
    LineFramer,
    Sample,
    SequenceTracker,
    SerialProtocolError,
    crc8,
    format_line,
    open_error_message,
    parse_line,
)

seqs = st.integers(min_value=0, max_value=65535)
counts = st.integers(min_value=0, max_value=1023)


def test_crc8_is_crc8_smbus():
    # The catalogue's check value of CRC-8/SMBUS (poly 0x07, init 0): the sketch must agree.
    assert crc8(b"123456789") == 0xF4
    assert crc8(b"") == 0


def test_a_sample_line_looks_as_documented():
    assert format_line(1234, 517) == b"F 1234 517 3C\n"
    assert parse_line(b"F 1234 517 3C\n") == Sample(seq=1234, count=517)


@given(seqs, counts)
def test_every_sample_round_trips(seq, count):
    assert parse_line(format_line(seq, count)) == Sample(seq=seq, count=count)


@given(seqs, counts)
def test_a_carriage_return_before_the_newline_is_tolerated(seq, count):
    line = format_line(seq, count)
    assert parse_line(line[:-1] + b"\r\n") == Sample(seq=seq, count=count)


@given(seqs, counts, st.data())
def test_every_single_bit_error_is_caught(seq, count, data):
    line = bytearray(format_line(seq, count)[:-1])
    index = data.draw(st.integers(min_value=0, max_value=len(line) - 1))
    bit = data.draw(st.integers(min_value=0, max_value=7))
    line[index] ^= 1 << bit
    with pytest.raises(SerialProtocolError):
        parse_line(bytes(line) + b"\n")


def test_two_swapped_neighbouring_digits_are_caught():
    # CRC-8 is linear, so whether a swap is caught depends only on the two digits and where
    # they sit: every count 0..1023 behind a 5-digit seq covers every pair and place.
    missed = []
    for seq in (12345, 65535, 7):
        for count in range(1024):
            line = format_line(seq, count)[:-1]
            end = line.rindex(b" ")
            for i in range(2, end - 1):
                a, b = line[i:i + 1], line[i + 1:i + 2]
                if a == b or not (a.isdigit() and b.isdigit()):
                    continue
                bad = line[:i] + b + a + line[i + 2:] + b"\n"
                try:
                    parse_line(bad)
                except SerialProtocolError:
                    continue
                missed.append(bad)
    assert not missed, missed[:5]


@pytest.mark.parametrize("line, reason", [
    (b"F 1 2\n", "format"),
    (b"G 1 2 00\n", "format"),
    (b"F 01 2 " + b"%02X" % crc8(b"F 01 2") + b"\n", "format"),      # leading zero
    (b"F 1 2 " + b"%02x" % crc8(b"F 1 2") + b"\n", "format"),        # lower-case hex
    (b"F 1 2 3C\n", "checksum"),
    (b"F 1 1024 " + b"%02X" % crc8(b"F 1 1024") + b"\n", "range"),   # above the 10-bit ADC
    (b"F 65536 5 " + b"%02X" % crc8(b"F 65536 5") + b"\n", "range"),
    (b"F " + b"1" * 70 + b"\n", "too_long"),
    (b"# \xff\xfe\n", "encoding"),
    (b"\xff\xfe\x00\x07\n", "format"),                                # a rosserial frame
])
def test_a_bad_line_is_refused_with_its_reason(line, reason):
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(line)
    assert caught.value.reason == reason
    assert "\n" not in str(caught.value)


def test_the_banner_says_the_board_restarted_and_carries_its_settings():
    info = parse_line(b"# fsr_serial v1 period_us=10000 baud=115200\n")
    assert isinstance(info, BoardInfo)
    assert info.restarted
    assert info.fields == {"period_us": "10000", "baud": "115200"}
    other = parse_line(b"# hello\n")
    assert isinstance(other, BoardInfo) and not other.restarted


def test_sequence_gaps_count_lost_lines_across_the_wrap():
    tracker = SequenceTracker()
    assert tracker.feed(65533) == 0
    assert tracker.feed(65534) == 0
    assert tracker.feed(1) == 2       # 65535 and 0 lost
    assert tracker.feed(2) == 0
    assert tracker.feed(10) == 7


def test_a_sequence_going_backwards_is_a_restart_not_65000_lost_lines():
    tracker = SequenceTracker()
    tracker.feed(5000)
    assert tracker.feed(0) is None
    assert tracker.feed(1) == 0


def test_the_framer_joins_lines_split_across_reads():
    framer = LineFramer()
    line = format_line(7, 300)
    assert framer.feed(line[:4]) == []
    assert framer.feed(line[4:] + line[:2]) == [line]
    assert framer.feed(line[2:]) == [line]


def test_an_overlong_line_is_reported_once_and_the_next_line_is_read():
    framer = LineFramer()
    good = format_line(1, 2)
    out = framer.feed(b"x" * 200)
    out += framer.feed(b"y" * 200 + b"\n" + good)
    assert len(out) == 2
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(out[0])
    assert caught.value.reason == "too_long"
    assert len(out[0]) == MAX_LINE_BYTES + 1
    assert out[1] == good


def test_the_stream_publishes_good_samples_and_counts_corrupt_and_lost_lines():
    stream = BoardStream()
    data = (b"17 3C\n"                    # tail of a line sent before the port opened
            + format_line(10, 100)
            + b"F 11 101 00\n"            # corrupt
            + format_line(12, 102)
            + format_line(15, 105))       # 13, 14 lost
    events = stream.feed(data)
    samples = [e for e in events if isinstance(e, Sample)]
    assert [s.count for s in samples] == [100, 102, 105]
    assert [s.lost_before for s in samples] == [0, 1, 2]   # the corrupt line is a lost line too
    errors = [e for e in events if isinstance(e, SerialProtocolError)]
    assert [e.reason for e in errors] == ["checksum"]
    c = stream.counters
    assert (c.samples, c.corrupt, c.lost, c.partial) == (3, 1, 3, 1)


def test_a_banner_or_a_reopen_starts_the_sequence_afresh():
    stream = BoardStream()
    stream.feed(format_line(500, 1) + format_line(501, 1))
    stream.feed(b"# fsr_serial v1 period_us=10000 baud=115200\n" + format_line(0, 2))
    assert stream.counters.lost == 0 and stream.counters.restarts == 1
    stream.reopened()
    stream.feed(format_line(300, 3))
    assert stream.counters.lost == 0
    assert stream.counters.samples == 4


@pytest.mark.parametrize("number, words", [
    (errno.ENOENT, "no serial port /dev/ttyACM0: plug the board in or pass port:=..."),
    (errno.EACCES, "dialout"),
    (errno.EBUSY, "busy"),
    (None, "cannot open serial port /dev/ttyACM0"),
])
def test_an_open_error_is_one_line_naming_the_cause_and_the_fix(number, words):
    message = open_error_message("/dev/ttyACM0", number, "[Errno x] details", "port:=...")
    assert words in message
    assert "\n" not in message
