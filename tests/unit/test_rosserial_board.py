"""The lab twin's board stand-in speaks as the handout's rosserial sketch does: driven through its bytes, on a fake clock."""

from __future__ import annotations

from typing import List, Optional

import pytest

from hri_teleop.core.rosserial_frames import (
    ID_LOG,
    ID_PARAMETER_REQUEST,
    ID_PUBLISHER,
    ID_TIME,
    TOPIC_REQUEST,
    Frame,
    FrameReader,
    ParamAnswer,
    decode_int16,
    decode_log,
    decode_param_request,
    decode_topic_info,
    encode_param_answer,
    encode_time,
    frame,
)
from hri_teleop.hardware.sim.rosserial_board import (
    FULL_PRESS_COUNT,
    PARAM_TIMEOUT_S,
    PRESS_RAMP_S,
    PUB_FORCE_ID,
    REST_COUNT,
    BoardStandInError,
    Piston,
    SketchBoard,
)

TIME_ANSWER = frame(ID_TIME, encode_time(100, 0))


def frames(data: bytes) -> List[Frame]:
    return FrameReader().feed(data)


def connect(board: SketchBoard, now: float = 0.0) -> List[Frame]:
    """A host asks for the topics and answers the time request; what the board said."""
    said = frames(board.receive(TOPIC_REQUEST, now))
    said += frames(board.receive(TIME_ANSWER, now))
    return said


def run(board: SketchBoard, start: float, end: float, step: float = 0.001,
        answer: Optional[ParamAnswer] = None) -> List[Frame]:
    """The board's loop from ``start`` to ``end``; a parameter request gets ``answer`` (None: unanswered)."""
    said: List[Frame] = []
    t = start
    while t < end:
        for f in frames(board.tick(t)):
            said.append(f)
            if f.topic_id == ID_PARAMETER_REQUEST and answer is not None:
                said += frames(board.receive(frame(ID_PARAMETER_REQUEST, encode_param_answer(answer)), t))
        t += step
    return said


def counts(said: List[Frame]) -> List[int]:
    return [decode_int16(f.payload) for f in said if f.topic_id == PUB_FORCE_ID]


def test_the_board_is_silent_until_asked_then_announces_pub_force_and_asks_for_the_time() -> None:
    board = SketchBoard(Piston(), noise_counts=0.0)
    assert run(board, 0.0, 1.0) == []
    said = connect(board, 1.0)
    info = decode_topic_info(said[0].payload)
    assert (said[0].topic_id, info.topic_name, info.message_type, info.topic_id) == (
        ID_PUBLISHER, "pub_force", "std_msgs/Int16", PUB_FORCE_ID)
    assert said[1] == Frame(ID_TIME, b"")
    assert board.connected


def test_the_period_comes_from_the_parameter_and_the_first_count_comes_at_once() -> None:
    board = SketchBoard(Piston(), noise_counts=0.0)
    connect(board)
    said = run(board, 0.0, 1.0, answer=ParamAnswer(ints=(20,)))
    assert decode_param_request(said[0].payload) == "~publish_period_ms"
    assert decode_log(said[1].payload) == ("info", "period from ~publish_period_ms")
    assert board.stats.period_ms == 20 and board.stats.period_from_param
    assert counts(said) == [REST_COUNT] * 50  # 1 s at 20 ms, from t = 0


@pytest.mark.parametrize("answer, why", [(None, "no ~publish_period_ms"), (ParamAnswer(ints=(3,)), "not in 5..10000")])
def test_without_a_usable_parameter_the_board_keeps_the_handouts_300_ms(answer, why) -> None:
    board = SketchBoard(Piston(), noise_counts=0.0)
    connect(board)
    said = run(board, 0.0, 3.55, answer=answer)  # not at a sample's time: the fake clock's sums round
    warnings = [decode_log(f.payload) for f in said if f.topic_id == ID_LOG]
    assert warnings[0][0] == "warn" and why in warnings[0][1]
    assert board.stats.period_ms == 300
    first = PARAM_TIMEOUT_S if answer is None else 0.0
    assert len(counts(said)) == int((3.55 - first) / 0.3) + 1


def test_a_board_that_fell_behind_sends_no_burst() -> None:
    board = SketchBoard(Piston(), noise_counts=0.0)
    connect(board)
    run(board, 0.0, 0.1, answer=ParamAnswer(ints=(10,)))
    assert len(counts(run(board, 0.5, 0.501))) == 1  # 40 periods late: one count, then on from now


def test_a_press_ramps_to_its_count_holds_and_returns_to_rest() -> None:
    piston = Piston()
    piston.press(FULL_PRESS_COUNT, 2.0, now_s=10.0)
    assert piston.count_at(10.0) == REST_COUNT
    assert REST_COUNT < piston.count_at(10.0 + PRESS_RAMP_S / 2) < FULL_PRESS_COUNT
    assert piston.count_at(10.0 + PRESS_RAMP_S + 1.0) == FULL_PRESS_COUNT
    assert piston.count_at(10.0 + 2 * PRESS_RAMP_S + 2.0 + 0.01) == REST_COUNT
    assert not piston.pressing


def test_the_board_sends_the_pressed_count() -> None:
    piston = Piston()
    board = SketchBoard(piston, noise_counts=1.0)
    connect(board)
    piston.press(700, 1.0, now_s=0.0)
    sent = counts(run(board, 0.0, 1.0, answer=ParamAnswer(ints=(10,))))
    assert max(sent) >= 695 and sent[0] <= REST_COUNT + 5


@pytest.mark.parametrize("count, hold", [(1024, 1.0), (-1, 1.0), (700.5, 1.0), (700, -1.0), (700, float("nan"))])
def test_an_impossible_press_is_one_line_with_an_example(count, hold) -> None:
    with pytest.raises(BoardStandInError) as info:
        Piston().press(count, hold, 0.0)
    assert "\n" not in str(info.value) and "e.g." in str(info.value)
