"""How often the lab's sensor board sends a count: the handout's sketch, its accepted periods, the recommended rate.

One home for these numbers: the simulated board (sim/board.py) offers them as rates and
``make doctor`` (core/doctor.py) judges a real board against them. The sketches themselves are in
firmware/ (arduino_code_force_node's FORCE_NODE_* constants, fsr_serial's SAMPLE_PERIOD_US).
"""

from __future__ import annotations

__all__ = ["HANDOUT_PERIOD_S", "HANDOUT_RATE_HZ", "RECOMMENDED_RATE_HZ", "MIN_PERIOD_MS", "MAX_PERIOD_MS"]

#: The handout's sketch publishes once per ``delay(300)``: about 3.3 counts a second.
HANDOUT_PERIOD_S = 0.3
HANDOUT_RATE_HZ = 1.0 / HANDOUT_PERIOD_S
#: What we recommend and fsr_serial sends: a count every 10 ms (~publish_period_ms 10 for rosserial).
RECOMMENDED_RATE_HZ = 100.0
#: The rosserial sketch's accepted ~publish_period_ms; outside it keeps the handout's 300 ms.
MIN_PERIOD_MS, MAX_PERIOD_MS = 5, 10000
