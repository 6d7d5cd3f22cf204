"""Stepping the simulated hand in the hand's tests (test_sim_hand_physics, test_sim_hand_goals)."""

from __future__ import annotations

from hypothesis import settings

from hri_teleop.core.attachment import Attachment
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.hand_params import HandParams

DT = 0.001  # the simulation node steps at 1 kHz
TRAVEL = Attachment().piston_travel_m
FULL_FORCE = Attachment().full_travel_force_n
SETTINGS = settings(max_examples=80, deadline=None)


def advance(hand: HandSim, seconds: float, vz: float = 0.0, az=None, on_step=None) -> None:
    """Step ``hand`` at 1 kHz for ``seconds`` (times computed from the start: no drift)."""
    start = hand.now_s
    for k in range(1, round(seconds / DT) + 1):
        hand.step(start + k * DT, vz, az)
        if on_step is not None:
            on_step(hand)


def until_done(hand: HandSim, record, limit_s: float = 5.0, vz: float = 0.0) -> None:
    start = hand.now_s
    k = 0
    while not record.done:
        k += 1
        assert k * DT <= limit_s, f"{record.action} goal still {record.status.name} after {limit_s} s: {record}"
        hand.step(start + k * DT, vz)


def hand_with(name: str, **params) -> HandSim:
    hand = HandSim(HandParams(**params)) if params else HandSim()
    hand.place_object(OBJECTS[name])
    return hand
