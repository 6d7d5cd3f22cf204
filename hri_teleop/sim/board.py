"""The simulated sensor board: the Arduino that samples the FSR divider and sends the count.

At home the simulated hand's FSR count must reach ``/pub_force`` with what a real board adds: a
sampling period and a little seeded ADC noise. :class:`SensorBoard` says when a sample is due and
takes it; pure, the caller passes times and counts. Its rates and noise model: docs/simulation.md.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass
from typing import Optional

from hri_teleop.core.board_rates import HANDOUT_RATE_HZ, RECOMMENDED_RATE_HZ
from hri_teleop.core.checks import ADC_MAX_COUNT, is_finite_number
from hri_teleop.core.errors import HriTeleopError

__all__ = ["BoardError", "BoardConfig", "SensorBoard", "HANDOUT_FIRMWARE_RATE_HZ", "DEFAULT_RATE_HZ"]

#: The handout's sketch (once per ``delay(300)``) and the recommended rate, the simulation's default.
HANDOUT_FIRMWARE_RATE_HZ = HANDOUT_RATE_HZ
DEFAULT_RATE_HZ = RECOMMENDED_RATE_HZ


class BoardError(HriTeleopError, ValueError):
    """A sensor board setting is unusable (the message names the fix)."""


@dataclass(frozen=True)
class BoardConfig:
    """Sampling rate (Hz), ADC noise (counts, standard deviation) and the noise's seed."""

    rate_hz: float = DEFAULT_RATE_HZ
    noise_counts: float = 1.0
    seed: Optional[int] = 0

    def __post_init__(self) -> None:
        if not (is_finite_number(self.rate_hz) and 0.0 < float(self.rate_hz) <= 1000.0):
            raise BoardError(f"sensor board rate_hz must be in (0, 1000] Hz, got {self.rate_hz!r}; "
                             f"use 100 (recommended) or {HANDOUT_FIRMWARE_RATE_HZ:.3f} (the handout's 300 ms)")
        if not (is_finite_number(self.noise_counts) and 0.0 <= float(self.noise_counts) <= 50.0):
            raise BoardError(f"sensor board noise_counts must be in [0, 50] counts, got {self.noise_counts!r}; "
                             "e.g. 1.0 (a few counts, as an Uno's ADC), 0 for none")
        if self.seed is not None and (isinstance(self.seed, bool) or not isinstance(self.seed, int)):
            raise BoardError(f"sensor board seed must be an integer or None, got {self.seed!r}")
        object.__setattr__(self, "rate_hz", float(self.rate_hz))
        object.__setattr__(self, "noise_counts", float(self.noise_counts))

    @property
    def period_s(self) -> float:
        return 1.0 / self.rate_hz


class SensorBoard:
    """Samples a count at a fixed rate and adds ADC noise (the model: docs/simulation.md)."""

    #: A sample is due this long before its instant, s: times summed from 1 ms steps round below it.
    DUE_SLACK_S = 1e-6

    def __init__(self, config: Optional[BoardConfig] = None, start_s: float = 0.0) -> None:
        self.config = config if config is not None else BoardConfig()
        if not isinstance(self.config, BoardConfig):
            raise BoardError("SensorBoard takes a BoardConfig; build it with BoardConfig(rate_hz=..., noise_counts=...)")
        if not is_finite_number(start_s):
            raise BoardError(f"start_s must be a finite time in seconds, got {start_s!r}")
        self._start_s = float(start_s)
        self._k = 0
        self._rng = random.Random(self.config.seed)
        self.samples_sent = 0

    @property
    def next_sample_s(self) -> float:
        """When the next sample is due (s)."""
        return self._start_s + self._k * self.config.period_s

    def due(self, now_s: float) -> bool:
        """Whether a sample is due at ``now_s`` (``DUE_SLACK_S`` absorbs rounding)."""
        return now_s + self.DUE_SLACK_S >= self.next_sample_s

    def sample(self, count: int, now_s: float) -> int:
        """The count the board sends for a true count ``count`` at ``now_s``; schedules the next one.

        A board that fell behind (``now_s`` several periods past the due time) skips the
        missed samples, as firmware with a ``delay`` does: it never sends a burst.
        """
        noise = self._rng.gauss(0.0, self.config.noise_counts) if self.config.noise_counts > 0 else 0.0
        value = int(min(max(round(count + noise), 0), ADC_MAX_COUNT))
        period = self.config.period_s
        self._k = max(self._k + 1, int(math.floor((now_s - self._start_s) / period + 1e-6)) + 1)
        self.samples_sent += 1
        return value
