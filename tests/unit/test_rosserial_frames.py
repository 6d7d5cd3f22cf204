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
