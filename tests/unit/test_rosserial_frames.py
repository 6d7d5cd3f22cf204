"""rosserial's frames as make doctor reads them: literal bytes of the wire format, checksums, cut and noisy input."""

from __future__ import annotations

import struct

import pytest

from hri_teleop.core.rosserial_frames import (
    ID_TIME,
    TOPIC_REQUEST,
    Frame,
    FrameReader,
    decode_topic_info,
    frame,
)


def _topic_info(topic_id: int, name: str, kind: str, md5: str, size: int) -> bytes:
    def text(s: str) -> bytes:
        return struct.pack("<I", len(s)) + s.encode()
    return struct.pack("<H", topic_id) + text(name) + text(kind) + text(md5) + struct.pack("<i", size)


def test_the_topic_request_is_serial_nodes_bytes() -> None:
    assert TOPIC_REQUEST == bytes.fromhex("fffe0000ff0000ff")


def test_a_frame_has_sync_length_its_checksum_topic_payload_and_checksum() -> None:
    # Int16 125 on topic 125: length 2 (checksum 0xfd), body 7d 00 7d 00 (checksum 255 - 250 = 5)
    assert frame(125, struct.pack("<h", 125)) == bytes.fromhex("fffe0200fd7d007d0005")


def test_the_reader_returns_frames_fed_byte_by_byte_and_skips_noise() -> None:
    reader = FrameReader()
    data = b"\x00\xff\x13" + frame(125, b"\x10\x00") + frame(ID_TIME, b"")
    frames = [f for byte in data for f in reader.feed(bytes([byte]))]
    assert frames == [Frame(125, b"\x10\x00"), Frame(ID_TIME, b"")]
    assert reader.bad == 0


def test_a_wrong_body_checksum_is_dropped_and_counted_and_the_next_frame_read() -> None:
    bad = bytearray(frame(125, b"\x10\x00"))
    bad[-1] ^= 0xFF
    reader = FrameReader()
    assert reader.feed(bytes(bad) + frame(125, b"\x11\x00")) == [Frame(125, b"\x11\x00")]
    assert reader.bad == 1


def test_a_wrong_length_checksum_is_skipped() -> None:
    bad = bytearray(frame(125, b"\x10\x00"))
    bad[4] ^= 0x01
    reader = FrameReader()
    assert reader.feed(bytes(bad)) == []
    assert reader.bad == 1


def test_a_topic_info_decodes_to_its_fields() -> None:
    payload = _topic_info(125, "pub_force", "std_msgs/Int16", "8524586e34fbd7cb1c08c5f5f1ca0e57", 280)
    info = decode_topic_info(payload)
    assert (info.topic_id, info.topic_name, info.message_type, info.buffer_size) == (125, "pub_force",
                                                                                     "std_msgs/Int16", 280)


def test_a_cut_topic_info_is_a_value_error_naming_its_size() -> None:
    payload = _topic_info(125, "pub_force", "std_msgs/Int16", "x", 280)
    with pytest.raises(ValueError, match="cut short"):
        decode_topic_info(payload[:-3])


# ------------------------------------------------------------------ the messages the lab twin's host and board exchange

def test_the_messages_a_host_and_a_board_exchange_read_back_as_written() -> None:
    from hri_teleop.core.rosserial_frames import (
        INT16_MD5,
        ParamAnswer,
        TopicInfo,
        decode_int16,
        decode_log,
        decode_param_answer,
        decode_param_request,
        decode_time,
        encode_int16,
        encode_log,
        encode_param_answer,
        encode_param_request,
        encode_time,
        encode_topic_info,
    )

    info = TopicInfo(125, "pub_force", "std_msgs/Int16", INT16_MD5, 150)
    assert decode_topic_info(encode_topic_info(info)) == info
    assert encode_topic_info(info) == _topic_info(125, "pub_force", "std_msgs/Int16", INT16_MD5, 150)
    assert decode_time(encode_time(1700000000, 999)) == (1700000000, 999)
    assert decode_param_request(encode_param_request("~publish_period_ms")) == "~publish_period_ms"
    answer = ParamAnswer(ints=(10,), floats=(0.5,), strings=("a", "bc"))
    assert decode_param_answer(encode_param_answer(answer)) == answer
    assert encode_param_answer(ParamAnswer()) == bytes(12)  # no value: NO_PARAMETER's bytes
    assert decode_int16(encode_int16(-700)) == -700
    assert decode_log(encode_log(2, "no ~publish_period_ms")) == ("warn", "no ~publish_period_ms")


def test_cut_messages_are_value_errors_not_crashes() -> None:
    from hri_teleop.core.rosserial_frames import decode_int16, decode_log, decode_param_answer, decode_time

    for decode, payload in ((decode_time, b"\x01"), (decode_param_answer, b"\x02\x00\x00\x00\x01"),
                            (decode_int16, b"\x01\x02\x03"), (decode_log, b""), (decode_log, b"\x01\x09\x00")):
        with pytest.raises(ValueError):
            decode(payload)


# ------------------------------------------------------------------ the wire format at its edges: literal bytes

def test_a_checksum_is_255_minus_the_sum_modulo_256() -> None:
    # body 7d 00 ff ff sums to 635 = 2 * 256 + 123: checksum 255 - 123 = 0x84
    assert frame(125, b"\xff\xff") == bytes.fromhex("fffe0200fd7d00ffff84")
    assert FrameReader().feed(bytes.fromhex("fffe0200fd7d00ffff84")) == [Frame(125, b"\xff\xff")]


def test_a_topic_id_is_an_unsigned_16_bit_number_up_to_65535() -> None:
    assert frame(32768, b"") == bytes.fromhex("fffe0000ff00807f")
    assert frame(65535, b"") == bytes.fromhex("fffe0000ffffff01")
    reader = FrameReader()
    assert reader.feed(bytes.fromhex("fffe0000ff00807ffffe0000ffffff01")) == [Frame(32768, b""), Frame(65535, b"")]


def test_a_payload_of_32768_bytes_has_an_unsigned_length_and_reads_back() -> None:
    data = frame(125, bytes(32768))
    assert data[:7] == bytes.fromhex("fffe00807f7d00") and len(data) == 32768 + 8
    assert FrameReader().feed(data) == [Frame(125, bytes(32768))]


def test_each_wrong_checksum_is_counted() -> None:
    good = frame(125, b"\x10\x00")
    bad_length = good[:4] + bytes([good[4] ^ 0x01]) + good[5:]
    bad_body = good[:-1] + bytes([good[-1] ^ 0xFF])
    reader = FrameReader()
    assert reader.feed(bad_length + bad_length + bad_body + bad_body + good) == [Frame(125, b"\x10\x00")]
    assert reader.bad == 4


def test_a_wrong_length_checksum_is_counted_as_soon_as_its_fifth_byte_arrives() -> None:
    reader = FrameReader()
    assert reader.feed(bytes.fromhex("fffe0200")) == [] and reader.bad == 0
    assert reader.feed(bytes.fromhex("fc")) == [] and reader.bad == 1


def test_a_log_level_is_named_as_rospy_names_it_and_an_unknown_one_by_its_number() -> None:
    from hri_teleop.core.rosserial_frames import decode_log

    for level, name in ((0, "debug"), (1, "info"), (2, "warn"), (3, "error"), (4, "fatal"), (5, "5"), (9, "9")):
        assert decode_log(bytes([level]) + b"\x03\x00\x00\x00abc") == (name, "abc")


def test_a_text_that_is_not_utf_8_is_read_with_replacement_characters() -> None:
    from hri_teleop.core.rosserial_frames import decode_log

    assert decode_log(b"\x01\x03\x00\x00\x00a\xffb") == ("info", "a\ufffdb")


@pytest.mark.parametrize("payload, name", [
    (b"\x03\x00\x00\x00abc", "abc"),        # exactly its 3 bytes
    (b"\x03\x00\x00\x00abcd", "abc"),       # a byte after it is not part of it
])
def test_a_string_is_read_up_to_its_length(payload: bytes, name: str) -> None:
    from hri_teleop.core.rosserial_frames import decode_param_request

    assert decode_param_request(payload) == name


@pytest.mark.parametrize("decoder, payload, message", [
    ("decode_param_request", b"\x03\x00\x00\x00ab",
     "a parameter request cut short (6 bytes: a string of 3 bytes at offset 4, 2 left)"),
    ("decode_param_request", b"\xff\xff\xff\xff",
     "a parameter request cut short (4 bytes: a string of 4294967295 bytes at offset 4, 0 left)"),
    ("decode_log", b"\x01\x09\x00\x00\x00ab",
     "a log message cut short (7 bytes: a string of 9 bytes at offset 5, 2 left)"),
    ("decode_topic_info", b"\x7d\x00\x09\x00\x00\x00pub_force\x0e\x00\x00\x00std_m",
     "a TopicInfo cut short (24 bytes: a string of 14 bytes at offset 19, 5 left)"),
])
def test_a_string_cut_short_is_a_frame_error_not_a_shorter_string(decoder: str, payload: bytes, message: str) -> None:
    from hri_teleop.core import rosserial_frames

    with pytest.raises(rosserial_frames.FrameError) as caught:
        getattr(rosserial_frames, decoder)(payload)
    assert str(caught.value) == (f"{message}; the board and its host speak different rosserial versions: build the "
                                 "sketch's ros_lib with this ROS (rosrun rosserial_arduino make_libraries.py)")


def test_a_parameter_answer_is_three_counted_lists_of_int32_float32_and_strings() -> None:
    from hri_teleop.core.rosserial_frames import ParamAnswer, decode_param_answer, encode_param_answer

    answer = ParamAnswer(ints=(-1, 2, 3), floats=(0.5, -2.0), strings=("a",))
    wire = bytes.fromhex("03000000" "ffffffff" "02000000" "03000000"
                         "02000000" "0000003f" "000000c0"
                         "01000000" "01000000" "61")
    assert encode_param_answer(answer) == wire
    assert decode_param_answer(wire) == answer


@pytest.mark.parametrize("payload, struct_says", [
    (b"\xff\xff\xff\xff" + bytes(8), "unpack_from requires a buffer of at least 17179869184 bytes for unpacking "
                                     "17179869180 bytes at offset 4 (actual buffer size is 12)"),
    (bytes(4) + b"\xff\xff\xff\xff" + bytes(4), "unpack_from requires a buffer of at least 17179869188 bytes for "
                                                "unpacking 17179869180 bytes at offset 8 (actual buffer size is 12)"),
    (bytes(8) + b"\xff\xff\xff\xff", "unpack_from requires a buffer of at least 16 bytes for unpacking 4 bytes at "
                                     "offset 12 (actual buffer size is 12)"),
])
def test_a_parameter_answer_counting_4294967295_values_is_cut_short(payload: bytes, struct_says: str) -> None:
    from hri_teleop.core.rosserial_frames import FrameError, decode_param_answer

    with pytest.raises(FrameError) as caught:
        decode_param_answer(payload)
    assert str(caught.value) == (f"a parameter answer cut short (12 bytes: {struct_says}); the board and its host "
                                 "speak different rosserial versions: build the sketch's ros_lib with this ROS "
                                 "(rosrun rosserial_arduino make_libraries.py)")


def test_a_time_is_two_unsigned_32_bit_numbers() -> None:
    from hri_teleop.core.rosserial_frames import decode_time, encode_time

    assert encode_time(4294967295, 2147483648) == bytes.fromhex("ffffffff00000080")
    assert decode_time(bytes.fromhex("ffffffff00000080")) == (4294967295, 2147483648)


def test_a_topic_info_has_an_unsigned_topic_id_and_a_signed_buffer_size() -> None:
    from hri_teleop.core.rosserial_frames import TopicInfo, encode_topic_info

    info = TopicInfo(65535, "a", "b", "c", -1)
    wire = bytes.fromhex("ffff" "0100000061" "0100000062" "0100000063" "ffffffff")
    assert encode_topic_info(info) == wire
    assert decode_topic_info(wire) == info
