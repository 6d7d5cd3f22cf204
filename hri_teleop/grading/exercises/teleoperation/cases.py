"""Ex. 8-9's inputs: pad-event traces for the class, a scripted drive for the node; public and hidden (seeded).

The expected outputs always come from the reference controller (``TeleopController``), never from a
second copy of the rules.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Dict, FrozenSet, List, Optional, Sequence, Set, Tuple

from hri_teleop.core.gamepad import AXES, PadState
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.core.teleop import Mode, TeleopController, TeleopParams
from hri_teleop.grading.cases.inputs import CasesError
from hri_teleop.grading.run.gains import TeleopGains

__all__ = ["reference_params", "PUBLIC_GAINS", "PadTick", "ExpectedTick", "TeleopPartsCase",
           "public_teleop_parts_case", "hidden_teleop_parts_case", "reference_parts",
           "Plateau", "TeleopNodeCase", "public_teleop_node_case", "hidden_teleop_node_case"]


def reference_params(gains: TeleopGains) -> TeleopParams:
    """The reference controller's parameters for ``gains``: the handout's rules (no rumble threshold)."""
    return TeleopParams(rate_hz=gains.rate, k_trans=gains.k_trans, k_rot=gains.k_rot,
                        k_gripper=gains.k_gripper, deadzone=gains.deadzone, rumble_threshold=0.0,
                        initial_width_m=GRIPPER_MAX_WIDTH_M, width_min_m=0.0, width_max_m=GRIPPER_MAX_WIDTH_M)


PUBLIC_GAINS = TeleopGains()


def _random_gains(rng: random.Random) -> TeleopGains:
    # Rates >= 50 Hz: the limiter refuses slower loops with the default limits (a step
    # per message the robot would feel). Gains stay below the default velocity limits
    # (0.25 m/s, 0.5 rad/s) so that a held stick reaches its exact value on the node.
    return TeleopGains(rate=rng.choice([50.0, 60.0, 75.0, 100.0]),
                       k_trans=round(rng.uniform(0.05, 0.2), 3), k_rot=round(rng.uniform(0.1, 0.45), 3),
                       k_gripper=round(rng.uniform(0.02, 0.08), 3), deadzone=round(rng.uniform(0.05, 0.25), 3))


@dataclass(frozen=True)
class PadTick:
    """The pad at one tick (positional axes, held buttons) and the latest /force_mapped value."""

    axes: Tuple[Tuple[str, float], ...]
    buttons: FrozenSet[str]
    force: float

    def state(self) -> PadState:
        return PadState(dict(self.axes), {b: True for b in self.buttons}, True)


@dataclass(frozen=True)
class ExpectedTick:
    """The reference after one tick: the student's variables must equal these."""

    gripper_width: float
    rotation_mode: bool
    cartesian_velocity: Tuple[float, ...]          # in the reference's mode
    velocity_if_translation: Tuple[float, ...]     # for judging the velocity in the student's own mode
    velocity_if_rotation: Tuple[float, ...]
    rumble: float


@dataclass(frozen=True)
class TeleopPartsCase:
    label: str
    gains: TeleopGains
    ticks: Tuple[PadTick, ...]
    hidden: bool = False


class _Builder:
    """Pad ticks from segments: hold this pad state (and force) for n ticks."""

    def __init__(self) -> None:
        self.axes: Dict[str, float] = {a: 0.0 for a in AXES}
        self.buttons: Set[str] = set()
        self.force = 0.0
        self.ticks: List[PadTick] = []

    def hold(self, n: int, axes: Optional[Dict[str, float]] = None, press: Sequence[str] = (),
             release: Sequence[str] = (), force: Optional[float] = None) -> "_Builder":
        self.axes.update(axes or {})
        self.buttons |= set(press)
        self.buttons -= set(release)
        if force is not None:
            self.force = force
        for _ in range(n):
            self.ticks.append(PadTick(tuple(sorted(self.axes.items())), frozenset(self.buttons), self.force))
        return self

    def tap(self, button: str, n_down: int = 3, n_up: int = 3) -> "_Builder":
        return self.hold(n_down, press=[button]).hold(n_up, release=[button])


def public_teleop_parts_case() -> TeleopPartsCase:
    """Sticks (inside, at and beyond the dead zone), toggles, gripper to both ends, forces."""
    b = _Builder()
    b.hold(5)
    b.hold(10, {"left_y": 1.0}, force=0.25)                         # full forward
    b.hold(5, {"left_y": 0.05})                                     # inside the dead zone: 0
    b.hold(5, {"left_y": 0.5, "left_x": -0.3}, force=0.5)           # diagonal
    b.hold(5, {"left_y": 0.0, "left_x": 1.0, "right_y": -0.7})      # right + down
    b.hold(5, {"left_x": 0.0, "right_y": 0.0, "right_x": 0.9})      # right_x drives nothing
    b.hold(3, {"right_x": 0.0})
    b.tap("north", 4, 4)                                            # -> rotation
    b.hold(8, {"left_y": -0.8, "right_y": 0.4}, force=1.0)
    b.hold(5, {"left_y": 0.0, "left_x": -1.0}, force=1.4)           # force above 1: rumble 1
    b.hold(3, {"left_x": 0.0}, force=-0.2)                          # below 0: rumble 0
    b.tap("north", 2, 3)                                            # -> translation
    b.hold(6, {"left_y": 0.3}, force=0.7)
    b.hold(40, {"left_y": 0.0}, press=["south"])                    # close: 40 steps
    b.hold(3, release=["south"])
    b.hold(10, press=["east"])                                      # open a bit
    b.hold(6, press=["south"])                                      # both held: no change
    b.hold(3, release=["east", "south"])
    b.hold(110, press=["south"], force=0.0)                         # close to the end: clipped at 0
    b.hold(3, release=["south"])
    b.hold(120, press=["east"])                                     # open to the end: clipped at 0.08
    b.hold(3, release=["east"])
    b.tap("north", 1, 1).tap("north", 1, 1).tap("north", 5, 2)      # three quick toggles -> rotation
    b.hold(5, {"right_y": 1.0})
    b.hold(3, {"right_y": 0.0})
    return TeleopPartsCase("public", PUBLIC_GAINS, tuple(b.ticks))


def hidden_teleop_parts_case(seed: int) -> TeleopPartsCase:
    """Random gains, rate and dead zone; random segments of sticks, toggles, gripper buttons and forces."""
    rng = random.Random(seed ^ 0x5EED7E1E)
    gains = _random_gains(rng)
    b = _Builder()
    b.hold(3)
    for _ in range(14):
        choice = rng.random()
        if choice < 0.35:
            axis = rng.choice(["left_x", "left_y", "right_y", "right_x"])
            value = round(rng.choice([-1.0, 1.0]) * rng.uniform(0.0, 1.0), 3)
            b.hold(rng.randint(3, 8), {axis: value}, force=round(rng.uniform(-0.2, 1.3), 3))
        elif choice < 0.5:
            b.tap("north", rng.randint(1, 4), rng.randint(1, 4))
        elif choice < 0.8:
            button = rng.choice(["south", "east"])
            b.hold(rng.randint(5, 70), press=[button]).hold(2, release=[button])
        else:
            b.hold(rng.randint(2, 6), {a: 0.0 for a in ("left_x", "left_y", "right_x", "right_y")},
                   force=round(rng.uniform(0.0, 1.0), 3))
    b.hold(3, {a: 0.0 for a in ("left_x", "left_y", "right_x", "right_y")}, release=["south", "east"])
    return TeleopPartsCase(f"hidden (seed {seed})", gains, tuple(b.ticks), hidden=True)


def _rotation_controller(params: TeleopParams) -> TeleopController:
    """A reference controller switched to rotation mode (by pressing the toggle once)."""
    controller = TeleopController(params)
    dt_s = 1.0 / params.rate_hz
    controller.step(PadState({}, {params.toggle_button: True}), None, 0.0, dt_s)
    controller.step(PadState({}, {}), None, 0.0, dt_s)
    if controller.mode is not Mode.ROTATION:  # pragma: no cover - TeleopController's own contract
        raise CasesError("the reference controller did not switch to rotation; check hri_teleop.core.teleop")
    return controller


def reference_parts(case: TeleopPartsCase) -> List[ExpectedTick]:
    """What the student's variables must be after each tick, from TeleopController."""
    params = reference_params(case.gains)
    controller = TeleopController(params)
    translation = TeleopController(params)
    rotation = _rotation_controller(params)
    dt_s = 1.0 / params.rate_hz
    expected: List[ExpectedTick] = []
    for tick in case.ticks:
        pad = tick.state()
        controller.step(pad, tick.force, 0.0, dt_s)
        expected.append(ExpectedTick(
            gripper_width=controller.gripper_width_m,
            rotation_mode=controller.mode is Mode.ROTATION,
            cartesian_velocity=tuple(controller.target_twist(pad)),
            velocity_if_translation=tuple(translation.target_twist(pad)),
            velocity_if_rotation=tuple(rotation.target_twist(pad)),
            rumble=controller.rumble_for(tick.force, 0.0),
        ))
    return expected


@dataclass(frozen=True)
class Plateau:
    """A twist the node must publish for a while (a held stick, after the ramp)."""

    what: str                       # e.g. "left stick up 0.8 in translation mode"
    component: int                  # index into (vx, vy, vz, wx, wy, wz)
    value: float
    start_s: float                  # script time the stick is set
    end_s: float                    # script time it is let go


@dataclass(frozen=True)
class TeleopNodeCase:
    """A pad script for the node, the force it gets, and what must come out."""

    label: str
    gains: TeleopGains
    script: Tuple[Dict[str, object], ...]     # ScriptedPad steps
    force: float                              # published on /force_mapped throughout
    plateaus: Tuple[Plateau, ...]
    close_s: float                            # how long cross is held
    final_width: float                        # gripper width after the script
    quit_s: float                             # when square is pressed
    hidden: bool = False
    rumble: float = field(init=False, default=0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "rumble", min(1.0, max(0.0, self.force)))

    @property
    def duration_s(self) -> float:
        return self.quit_s


def _node_case(label: str, gains: TeleopGains, forward: float, sideways: float, close_s: float,
               force: float, hidden: bool) -> TeleopNodeCase:
    params = reference_params(gains)
    translation = TeleopController(params)
    rotation = _rotation_controller(params)
    vx = translation.target_twist(PadState({"left_y": forward}))[0]
    wy = rotation.target_twist(PadState({"left_x": sideways}))[4]
    t_close = 3.4
    t_toggle = t_close + close_s + 0.3
    t_side = t_toggle + 0.4
    t_quit = t_side + 2.4
    script = (
        {"t": 1.0, "axis": "left_y", "value": forward},
        {"t": 3.0, "axis": "left_y", "value": 0.0},
        {"t": t_close, "press": "south"},
        {"t": t_close + close_s, "release": "south"},
        {"t": t_toggle, "press": "north"},
        {"t": t_toggle + 0.2, "release": "north"},
        {"t": t_side, "axis": "left_x", "value": sideways},
        {"t": t_quit - 0.3, "axis": "left_x", "value": 0.0},
        {"t": t_quit, "press": "west"},
    )
    plateaus = (
        Plateau(f"left stick at {forward:+.3f} up in translation mode: v_x", 0, vx, 1.0, 3.0),
        Plateau(f"left stick at {sideways:+.3f} right in rotation mode: w_y", 4, wy, t_side, t_quit - 0.3),
    )
    final_width = max(0.0, min(GRIPPER_MAX_WIDTH_M, GRIPPER_MAX_WIDTH_M - gains.k_gripper * close_s))
    return TeleopNodeCase(label, gains, script, force, plateaus, close_s, final_width, t_quit, hidden)


def public_teleop_node_case() -> TeleopNodeCase:
    return _node_case("public", PUBLIC_GAINS, 0.8, -0.6, 1.0, 0.6, hidden=False)


def hidden_teleop_node_case(seed: int) -> TeleopNodeCase:
    rng = random.Random(seed ^ 0x0DE5C0DE)
    gains = _random_gains(rng)
    forward = round(rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 1.0), 3)
    sideways = round(rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 1.0), 3)
    close_s = round(rng.uniform(0.6, 1.2), 2)
    force = round(rng.uniform(0.2, 0.9), 3)
    return _node_case(f"hidden (seed {seed})", gains, forward, sideways, close_s, force, hidden=True)
