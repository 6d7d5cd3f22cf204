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


# ------------------------------------------------------------------ each rule at its edge (the sketch's side of the wire)

def _checked(payload: bytes) -> bytes:
    """``payload`` with its good CRC-8 and newline: a line that only the rule under test can refuse."""
    return payload + b" %02X\n" % crc8(payload)


def test_the_sketch_sends_seq_0_to_65535_and_counts_0_to_1023_and_nothing_else():
    assert format_line(0, 0) == b"F 0 0 92\n"
    assert format_line(65535, 1023) == b"F 65535 1023 9B\n"
    for seq, count in ((-1, 0), (65536, 0), (0, -1), (0, 1024)):   # each out of range alone
        with pytest.raises(SerialProtocolError) as caught:
            format_line(seq, count)
        assert caught.value.reason == "range"
        assert caught.value.line == b""
        assert str(caught.value) == (f"corrupt line from the sensor board (range: seq {seq} not in 0..65535 or "
                                     f"count {count} not in 0..1023): b''")


@pytest.mark.parametrize("seq, ok", [(b"65535", True), (b"65536", False)])
def test_a_seq_up_to_65535_is_read_and_one_above_is_out_of_range(seq, ok):
    line = _checked(b"F " + seq + b" 5")
    if ok:
        assert parse_line(line) == Sample(seq=65535, count=5)
        return
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(line)
    assert caught.value.reason == "range"
    assert str(caught.value) == ("corrupt line from the sensor board (range: seq 65536 is above 65535): "
                                 "b'F 65536 5 62\\n'")


def test_a_count_above_1023_names_the_count_in_its_message():
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(b"F 1 1024 FE\n")
    assert str(caught.value) == ("corrupt line from the sensor board (range: count 1024 is above 1023): "
                                 "b'F 1 1024 FE\\n'")


@pytest.mark.parametrize("line, message", [
    # a sign, a letter or a sixth digit behind a good checksum: not a plain decimal, whatever its value
    (b"F -1 5 7B\n", "format: seq b'-1' is not a plain decimal number"),
    (b"F 1x 5 48\n", "format: seq b'1x' is not a plain decimal number"),
    (b"F 1 -5 D4\n", "format: count b'-5' is not a plain decimal number"),
    (b"F 123456 5 E4\n", "format: seq b'123456' is not a plain decimal number"),
    # words split by two spaces: the sketch writes one
    (b"F  1 5 85\n", "format: expected 'F <seq> <count> <crc>'"),
    (b"F\t1 5 " + b"%02X" % crc8(b"F\t1 5") + b"\n", "format: expected 'F <seq> <count> <crc>'"),
    (b"F 1 2 XX\n", "format: checksum b'XX' is not two upper-case hex digits"),
])
def test_a_line_with_a_good_checksum_but_a_malformed_word_is_refused_as_format(line, message):
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(line)
    assert caught.value.reason == "format"
    assert caught.value.line == line
    assert str(caught.value) == f"corrupt line from the sensor board ({message}): {line!r}"


def test_the_five_digit_seq_12345_is_read():
    assert parse_line(_checked(b"F 12345 5")) == Sample(seq=12345, count=5)


@pytest.mark.parametrize("length, ok", [(63, True), (64, True), (65, False)])
def test_an_information_line_of_64_bytes_is_read_and_one_of_65_is_too_long(length, ok):
    line = b"#" + b"a" * (length - 1) + b"\n"
    if ok:
        info = parse_line(line)
        assert isinstance(info, BoardInfo) and info.text == "#" + "a" * (length - 1)
        return
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(line)
    assert caught.value.reason == "too_long"
    assert caught.value.line == line
    # the message shows the line's first 40 bytes only
    assert str(caught.value) == ("corrupt line from the sensor board (too_long: 65 bytes, at most 64): b'#"
                                 + "a" * 39 + "'")


def test_an_information_line_keeps_its_text_and_a_value_with_an_equals_sign_whole():
    info = parse_line(b"# fsr_serial v1 note=a=b baud=115200\r\n")
    assert info == BoardInfo(text="# fsr_serial v1 note=a=b baud=115200", restarted=True,
                             fields={"note": "a=b", "baud": "115200"})


def test_a_control_character_in_an_information_line_is_an_encoding_error():
    with pytest.raises(SerialProtocolError) as caught:
        parse_line(b"# \x07\n")
    assert caught.value.reason == "encoding"


@pytest.mark.parametrize("seq, lost", [(32767, 32766), (32768, 32767), (32769, None), (32770, None)])
def test_a_forward_jump_of_up_to_32767_lost_lines_counts_them_a_larger_one_is_a_restart(seq, lost):
    tracker = SequenceTracker()
    assert tracker.feed(0) == 0
    assert tracker.feed(seq) == lost


def _line_of(body_bytes: int) -> bytes:
    """An information line of ``body_bytes`` bytes before its newline."""
    return b"#" + b"b" * (body_bytes - 1) + b"\n"


@pytest.mark.parametrize("body_bytes", [63, 64])
def test_the_framer_passes_a_line_of_up_to_64_bytes_whole(body_bytes):
    framer = LineFramer()
    line = _line_of(body_bytes)
    assert framer.feed(line + format_line(1, 2)) == [line, format_line(1, 2)]


def test_the_framer_cuts_a_line_of_65_bytes_to_65_without_its_newline_and_reads_the_next():
    framer = LineFramer()
    line = _line_of(65)
    assert framer.feed(line + format_line(1, 2)) == [line[:65], format_line(1, 2)]


def test_the_framer_waits_for_the_newline_of_64_bytes_and_cuts_65_at_once():
    framer = LineFramer()
    assert framer.feed(b"c" * 64) == []
    assert framer.feed(b"\n") == [b"c" * 64 + b"\n"]
    assert framer.feed(b"d" * 65) == [b"d" * 65]
    assert framer.feed(b"dd\n" + format_line(3, 4)) == [format_line(3, 4)]


def test_a_read_that_starts_with_the_newline_ends_the_line_before_it():
    framer = LineFramer()
    first, second = format_line(5, 6), format_line(7, 8)
    assert framer.feed(first[:-1]) == []
    assert framer.feed(b"\n" + second) == [first, second]


def test_a_read_that_starts_with_the_newline_of_a_cut_line_ends_the_dropping():
    framer = LineFramer()
    assert framer.feed(b"e" * 70) == [b"e" * 65]
    assert framer.feed(b"\n" + format_line(9, 10)) == [format_line(9, 10)]


def test_the_stream_counts_every_corrupt_line_info_line_and_restart():
    stream = BoardStream()
    banner = b"# fsr_serial v1 period_us=10000 baud=115200\n"
    events = stream.feed(banner + format_line(100, 1) + b"F 101 1 00\n" + b"F 102 1 00\n"
                         + b"# hello\n" + banner + format_line(0, 2)
                         + format_line(50, 3) + format_line(10, 4)       # backwards: restarted, nothing lost
                         + format_line(5, 5))                            # backwards again
    assert [type(e).__name__ for e in events] == ["BoardInfo", "Sample", "SerialProtocolError", "SerialProtocolError",
                                                  "BoardInfo", "BoardInfo", "Sample", "Sample", "Sample", "Sample"]
    assert events[0] == BoardInfo(text=banner[:-1].decode(), restarted=True,
                                  fields={"period_us": "10000", "baud": "115200"})
    samples = [e for e in events if isinstance(e, Sample)]
    assert samples == [Sample(seq=100, count=1), Sample(seq=0, count=2), Sample(seq=50, count=3, lost_before=49),
                       Sample(seq=10, count=4), Sample(seq=5, count=5)]
    c = stream.counters
    assert (c.samples, c.corrupt, c.lost, c.restarts, c.info_lines, c.partial) == (5, 2, 49, 4, 3, 0)
    assert c.summary() == "5 samples, 49 lost, 2 corrupt, 4 board restarts"


def test_after_each_reopen_a_cut_first_line_is_partial_not_corrupt():
    stream = BoardStream()
    assert stream.feed(b"23 4F\n" + format_line(1, 1)) == [Sample(seq=1, count=1)]
    stream.reopened()
    assert stream.feed(b"7 1A\n" + format_line(9, 1)) == [Sample(seq=9, count=1)]
    assert (stream.counters.partial, stream.counters.corrupt, stream.counters.lost) == (2, 0, 0)


@pytest.mark.parametrize("number, message", [
    (errno.ENOENT, "no serial port /dev/ttyUSB1: plug the board in or pass --port ... "
                   "(`ls /dev/ttyACM* /dev/ttyUSB*` lists the boards)"),
    (errno.ENODEV, "no serial port /dev/ttyUSB1: plug the board in or pass --port ... "
                   "(`ls /dev/ttyACM* /dev/ttyUSB*` lists the boards)"),
    (errno.ENXIO, "no serial port /dev/ttyUSB1: plug the board in or pass --port ... "
                  "(`ls /dev/ttyACM* /dev/ttyUSB*` lists the boards)"),
    (errno.EACCES, "no permission to open /dev/ttyUSB1: add yourself to the dialout group "
                   "(`sudo usermod -aG dialout $USER`, then log in again)"),
    (errno.EPERM, "no permission to open /dev/ttyUSB1: add yourself to the dialout group "
                  "(`sudo usermod -aG dialout $USER`, then log in again)"),
    (errno.EBUSY, "serial port /dev/ttyUSB1 is busy: close the program that holds it "
                  "(Arduino IDE serial monitor, another bridge or serial_node)"),
    (errno.EIO, "cannot open serial port /dev/ttyUSB1 ([Errno 5] Input/output error): check the cable and the "
                "board, or pass --port ..."),
    (None, "cannot open serial port /dev/ttyUSB1 ([Errno 5] Input/output error): check the cable and the "
           "board, or pass --port ..."),
])
def test_each_open_error_reads_exactly_as_the_user_sees_it(number, message):
    assert open_error_message("/dev/ttyUSB1", number, "[Errno 5] Input/output error", "--port ...") == message
