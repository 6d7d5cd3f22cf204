"""Ex. 5's inputs: the public trace and the hidden cases (seeded), their expected values from ``map_force``."""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import List, Tuple

from hri_teleop.core.mapping import ADC_MAX_COUNT, map_force
from hri_teleop.grading.cases.inputs import PUBLIC_MAX_SENSOR_FORCE, PUBLIC_SEED

__all__ = ["MappingCase", "public_mapping_case", "hidden_mapping_cases"]


@dataclass(frozen=True)
class MappingCase:
    """Counts to publish on /pub_force with /max_sensor_force set, and what must come back."""

    label: str
    max_sensor_force: int
    counts: Tuple[int, ...]
    hidden: bool = False

    @property
    def expected(self) -> Tuple[float, ...]:
        return tuple(float(map_force(c, self.max_sensor_force)) for c in self.counts)


def _noise(rng: random.Random, level: int, n: int, spread: int) -> List[int]:
    return [min(ADC_MAX_COUNT, max(0, level + rng.randint(-spread, spread))) for _ in range(n)]


def _mapping_counts(rng: random.Random, maximum: int) -> List[int]:
    """0, the maximum, values above it, noise, steps and a ramp, around ``maximum``."""
    above = sorted({min(ADC_MAX_COUNT, maximum + d) for d in (1, 2, 50, 150)} | {ADC_MAX_COUNT})
    counts: List[int] = [0, 0, maximum, 0, maximum - 1, 1, maximum // 2]
    counts += [c for c in above]                                   # above the maximum: 1.0
    counts += _noise(rng, 0, 6, 3)                                 # piston free: noise near 0
    counts += _noise(rng, maximum // 3, 10, 8)                     # a light press with noise
    counts += [0] * 3 + [maximum] * 3 + [0] * 3                    # steps
    counts += list(range(0, ADC_MAX_COUNT + 1, 37))                # a ramp over the whole ADC range
    counts += _noise(rng, maximum, 10, 12)                         # pressed in: noise around the maximum
    counts += [rng.randint(0, ADC_MAX_COUNT) for _ in range(12)]   # anywhere
    counts += [0]
    return counts


def public_mapping_case() -> MappingCase:
    """The published trace: /max_sensor_force = 700."""
    rng = random.Random(PUBLIC_SEED)
    return MappingCase("public", PUBLIC_MAX_SENSOR_FORCE, tuple(_mapping_counts(rng, PUBLIC_MAX_SENSOR_FORCE)))


def hidden_mapping_cases(seed: int, count: int = 2) -> List[MappingCase]:
    """``count`` cases with /max_sensor_force drawn away from 700 (one below, one above where possible)."""
    rng = random.Random(seed)
    lows = [m for m in range(150, 1001) if abs(m - PUBLIC_MAX_SENSOR_FORCE) > 40]
    below = [m for m in lows if m < PUBLIC_MAX_SENSOR_FORCE]
    above = [m for m in lows if m > PUBLIC_MAX_SENSOR_FORCE]
    cases = []
    for index in range(count):
        pool = below if index % 2 == 0 else above
        maximum = rng.choice(pool)
        counts = _mapping_counts(rng, maximum)
        rng.shuffle(counts)  # a different order than the public trace, not only other values
        counts = [0] + counts
        cases.append(MappingCase(f"hidden-{index + 1}", maximum, tuple(counts), hidden=True))
    return cases
