"""The simulated sensor board: its rate, its noise, its seed."""

from __future__ import annotations

import statistics

import pytest

from hri_teleop.sim.board import HANDOUT_FIRMWARE_RATE_HZ, BoardConfig, BoardError, SensorBoard


def _run(board: SensorBoard, count: int, seconds: float):
    samples = []
    for k in range(1, int(round(seconds * 1000)) + 1):  # polled at 1 kHz, as the world does
        t = k * 0.001
        if board.due(t):
            samples.append((t, board.sample(count, t)))
    return samples


def test_sends_at_its_rate_100_hz_by_default():
    samples = _run(SensorBoard(BoardConfig(noise_counts=0.0)), 500, 2.0)
    assert len(samples) == 201  # the first poll (1 ms), then every 10 ms up to 2.0 s
    gaps = [b[0] - a[0] for a, b in zip(samples[1:], samples[2:])]
    assert max(gaps) == pytest.approx(0.01) and min(gaps) == pytest.approx(0.01)


def test_the_handout_firmware_period_of_300_ms_is_available():
    samples = _run(SensorBoard(BoardConfig(rate_hz=HANDOUT_FIRMWARE_RATE_HZ, noise_counts=0.0)), 500, 3.0)
    assert len(samples) == 11  # t = 0.001 (first poll), 0.3, ..., 3.0 s
    assert samples[1][0] - samples[0][0] == pytest.approx(0.3, abs=0.0011)


def test_without_noise_the_count_is_passed_through():
    assert {v for _, v in _run(SensorBoard(BoardConfig(noise_counts=0.0)), 612, 0.5)} == {612}


def test_noise_is_a_few_counts_around_the_true_count():
    values = [v for _, v in _run(SensorBoard(BoardConfig(noise_counts=1.0, seed=3)), 500, 30.0)]
    assert statistics.mean(values) == pytest.approx(500, abs=0.1)
    assert 0.8 < statistics.pstdev(values) < 1.2
    assert max(abs(v - 500) for v in values) <= 6


def test_noise_never_leaves_the_adc_range():
    low = [v for _, v in _run(SensorBoard(BoardConfig(noise_counts=2.0)), 0, 5.0)]
    high = [v for _, v in _run(SensorBoard(BoardConfig(noise_counts=2.0)), 1023, 5.0)]
    assert min(low) == 0 and max(low) <= 8 and 0 < sum(1 for v in low if v > 0) < len(low)
    assert max(high) == 1023 and min(high) >= 1015


def test_the_same_seed_gives_the_same_samples_and_another_seed_others():
    a = _run(SensorBoard(BoardConfig(seed=7)), 300, 1.0)
    b = _run(SensorBoard(BoardConfig(seed=7)), 300, 1.0)
    c = _run(SensorBoard(BoardConfig(seed=8)), 300, 1.0)
    assert a == b and a != c


def test_a_late_board_skips_missed_samples_instead_of_bursting():
    board = SensorBoard(BoardConfig(noise_counts=0.0))
    assert board.due(0.0)
    board.sample(1, 0.0)
    board.sample(1, 0.055)  # 5.5 periods late
    assert board.next_sample_s == pytest.approx(0.06)
    assert not board.due(0.059) and board.due(0.06)


def test_a_sample_is_due_from_one_microsecond_before_its_instant():
    board = SensorBoard(BoardConfig(rate_hz=100.0, noise_counts=0.0))
    board.sample(1, 0.0)  # the next one at 0.01 s
    assert board.due(0.01 - 1e-6)
    assert not board.due(0.01 - 1.5e-6)


@pytest.mark.parametrize("kwargs, expected", [
    (dict(rate_hz=0), "rate_hz must be in (0, 1000]"),
    (dict(rate_hz=float("nan")), "rate_hz"),
    (dict(noise_counts=-1), "noise_counts must be in [0, 50]"),
    (dict(seed=1.5), "seed must be an integer"),
])
def test_bad_settings_are_one_line_errors_with_a_fix(kwargs, expected):
    with pytest.raises(BoardError) as info:
        BoardConfig(**kwargs)
    assert expected in str(info.value) and "\n" not in str(info.value)
