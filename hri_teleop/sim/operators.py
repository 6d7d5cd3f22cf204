"""Random simulated operators: pad scripts that do what hurried, clumsy people do.

"No command stream ever breaks the Franka's limits" must hold for any operator. :func:`random_operator`
draws a seeded script with what stresses the limiter most (full stick reversals in one tick, mode
toggles mid-motion, both gripper buttons, a lost pad, quitting while moving), and
:func:`script_to_yaml_data` writes it for the node's ``~pad_script``, so the same operator runs
offline (:func:`hri_teleop.sim.lab.run_lab`) and through the real node.
"""

from __future__ import annotations

import random
from typing import Any, Dict, List

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.virtual_pad import ScriptStep

__all__ = ["OperatorError", "random_operator", "script_to_yaml_data", "study_operator", "study_scenario",
           "squeeze_taps"]

_STICKS = ("left_x", "left_y", "right_x", "right_y")
_BUTTONS = ("south", "east", "north")


class OperatorError(HriTeleopError, ValueError):
    """A study operator asked for with a condition, object or timing the simulated study does not have."""


def random_operator(seed: int, duration_s: float = 10.0, quit_at_end: bool = True,
                    rotate: bool = True) -> List[ScriptStep]:
    """A seeded random pad script of about ``duration_s`` seconds (see the module doc).

    ``rotate`` False never presses triangle: the sticks only translate the hand.
    """
    rng = random.Random(seed)
    buttons = _BUTTONS if rotate else tuple(b for b in _BUTTONS if b != "north")
    steps: List[ScriptStep] = []
    t = 0.0
    pressed = set()
    unplugged = failing = False
    while True:
        t = round(t + rng.choice((0.02, 0.04, 0.1, 0.2, 0.5, 1.0)), 2)
        if t >= duration_s:
            break
        roll = rng.random()
        if roll < 0.55:
            value = rng.choice((-1.0, 1.0, 0.0, round(rng.uniform(-1.0, 1.0), 3)))
            steps.append(ScriptStep(t, "axis", (rng.choice(_STICKS),), value))
        elif roll < 0.80:
            button = rng.choice(buttons)
            if button in pressed:
                pressed.discard(button)
                steps.append(ScriptStep(t, "release", (button,)))
            else:
                pressed.add(button)
                steps.append(ScriptStep(t, "press", (button,)))
        elif roll < 0.88:
            steps.append(ScriptStep(t, "tap", (rng.choice(buttons),), hold_s=rng.choice((0.02, 0.04, 0.1))))
        elif roll < 0.94:
            unplugged = not unplugged
            steps.append(ScriptStep(t, "disconnect" if unplugged else "reconnect"))
        else:
            failing = not failing
            steps.append(ScriptStep(t, "fail" if failing else "recover"))
    if unplugged:
        steps.append(ScriptStep(duration_s, "reconnect"))
    if failing:
        steps.append(ScriptStep(duration_s, "recover"))
    if quit_at_end:
        steps.append(ScriptStep(duration_s, "press", ("west",)))
    return steps


def script_to_yaml_data(steps: List[ScriptStep], description: str = "") -> Dict[str, Any]:
    """The YAML-ready mapping of a script (``yaml.safe_dump`` it); ``parse_script`` reads it back."""
    out: List[Dict[str, Any]] = []
    for s in steps:
        item: Dict[str, Any] = {"t": s.t}
        if s.action == "axis":
            item["axis"] = s.target[0]
            item["value"] = s.value
        elif s.action in ("press", "release", "tap"):
            item[s.action] = list(s.target) if len(s.target) > 1 else s.target[0]
            if s.action == "tap":
                item["hold"] = s.hold_s
                if s.every_s:
                    item["every"] = s.every_s
        else:
            item[s.action] = True
        if s.condition:
            item["until" if s.every_s else "when"] = s.condition
            item["above"] = s.above
            item["max_wait"] = s.max_wait_s
        out.append(item)
    data: Dict[str, Any] = {"steps": out}
    if description:
        data["description"] = description
    return data


#: The study operator's approach in the lab's full scenario (s at 0.1 m/s, from the ready pose).
FULL_APPROACH_S = 4.6
#: The fast close stops this far (m) outside the object: the piston (3 mm) touches 3 mm before the shell.
CLOSE_MARGIN_M = 0.012
#: A tap holds cross this long (s): two ticks at 50 Hz, 1.6 mm at k_gripper 0.04 m/s.
TAP_HOLD_S = 0.04
#: The careful (feedback) participant taps once a second, feeling each tap before the next. From a
#: tap to its rumble takes 0.24-0.28 s through the lab's nodes (the hand's move is 0.24 s of it; 12
#: trials measured, idle and beside two CPU hogs); at 0.5 s a stalled node on a busy PC let one tap
#: too many through and cracked the egg. A real-time trial cannot own the clock, so the margin is
#: the period: 0.7 s.
FEEDBACK_TAP_PERIOD_S = 1.0


def study_operator(condition: str, seed: int, *, object_width_m: float = 0.044, approach_s: float = FULL_APPROACH_S,
                   lift_s: float = 2.0, hold_s: float = 2.0, start_s: float = 1.0, skip_taps: int = 0,
                   k_gripper_m_per_s: float = 0.04) -> List[ScriptStep]:
    """A participant of Ex. 14's experiment grasping and lifting an object (default: the egg).

    Both conditions approach the same way (right stick down for ``approach_s``) and close
    fast to ``object_width_m`` + 12 mm (56 mm for the 44 mm egg).  Then:

    * ``feedback``: taps cross (1.6 mm a tap) once a second until the pad rumbles above
      0.9 -- the default scenario's careful operator;
    * ``no_feedback``: cannot feel the piston, so judges by eye: 6 to 9 taps, drawn with
      the seed and biased towards squeezing too much (7 taps land in the piston's window;
      6 hold too lightly and the egg slips, 8 or more crush it).

    Then lift for ``lift_s`` at 5 cm/s, hold still for ``hold_s`` and quit.  The timing
    jitters with the seed (reaction and pauses), as people do.  The defaults are the
    lab's full scenario; :func:`study_scenario` ``quick=True`` shortens approach, lift and
    hold (the tests' short trials) and ``skip_taps`` closes fast that many taps further
    and taps that many times less: the same widths, reached sooner.
    ``k_gripper_m_per_s``: the teleop gain the fast close is timed for (teleop.yaml's 0.04).
    """
    if condition not in ("feedback", "no_feedback"):
        raise OperatorError(f"condition must be feedback or no_feedback, got {condition!r}")
    if not 0 <= skip_taps <= 5:
        raise OperatorError(f"skip_taps must be 0..5 (the careless operator taps at least 6 times), got {skip_taps!r}")
    tap_m = TAP_HOLD_S * k_gripper_m_per_s
    close_s = round((GRIPPER_MAX_WIDTH_M - (object_width_m + CLOSE_MARGIN_M - skip_taps * tap_m)) / k_gripper_m_per_s, 2)
    if not 0.0 < close_s <= 2.0:
        raise OperatorError(f"object_width_m {object_width_m!r} leaves no room to close fast from "
                            f"{GRIPPER_MAX_WIDTH_M * 1000:g} mm; "
                            "give the object's width in m, e.g. 0.044 (an egg)")
    rng = random.Random(seed)
    t = round(start_s + rng.uniform(0.0, 0.3), 2)
    steps = [ScriptStep(t, "axis", ("right_y",), -1.0)]
    t = round(t + approach_s, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.0))
    t = round(t + 0.9 + rng.uniform(0.0, 0.3), 2)
    steps.append(ScriptStep(t, "press", ("south",)))
    t = round(t + close_s, 2)
    steps.append(ScriptStep(t, "release", ("south",)))
    t = round(t + 0.5, 2)
    if condition == "feedback":
        steps.append(ScriptStep(t, "tap", ("south",), hold_s=TAP_HOLD_S, every_s=FEEDBACK_TAP_PERIOD_S,
                                condition="rumble", above=0.9, max_wait_s=20.0))
        t = round(t + 0.5, 2)
    else:
        for _ in range(rng.choice((6, 7, 8, 8, 9)) - skip_taps):
            steps.append(ScriptStep(t, "tap", ("south",), hold_s=TAP_HOLD_S))
            t = round(t + 0.5, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.5))
    t = round(t + lift_s, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.0))
    t = round(t + hold_s, 2)
    steps.append(ScriptStep(t, "tap", ("west",), hold_s=0.1))
    return steps


def squeeze_taps(steps: List[ScriptStep]) -> int:
    """How many single cross taps a study operator's script makes (0 for the feedback one, which repeats one tap)."""
    return sum(1 for s in steps if s.action == "tap" and s.target == ("south",) and not s.every_s)


def study_scenario(condition: str, seed: int, object_name: str = "egg", *, quick: bool = False) -> Dict[str, Any]:
    """A scenario (YAML-ready: description, world, steps) with :func:`study_operator` and an object of the sim's set.

    ``quick``: the arm starts 0.34 m lower (the same final height after a 1.2 s approach),
    the fast close goes 4 taps further (and 4 taps fewer follow), the lift is 3 cm and the
    hold 0.4 s: a trial of about 7 s instead of 16 s, with the same grasp.
    """
    if object_name not in OBJECTS:
        raise OperatorError(f"object {object_name!r} is not in the simulation's set; "
                            f"use one of {', '.join(sorted(OBJECTS))}")
    world: Dict[str, Any] = {"object": object_name}
    timing: Dict[str, Any] = {}
    if quick:
        # here, not at the top: the world loads pinocchio (the arm's joints), and ros.trial, so the
        # notebooks' widgets, import this module; a 3D view is what should pay for pinocchio
        from hri_teleop.sim.world import LAB_ARM_CONFIG  # noqa: PLC0415 - pinocchio only for a quick trial

        approach_s = 1.2
        x, y, z = LAB_ARM_CONFIG.start_position_m
        lower_z = round(float(z) - 0.1 * (FULL_APPROACH_S - approach_s), 4)  # the same end after 0.1 m/s
        world["arm"] = {"start_position_m": [float(x), float(y), lower_z]}
        timing = {"approach_s": approach_s, "lift_s": 0.6, "hold_s": 0.4, "start_s": 0.5, "skip_taps": 4}
    steps = study_operator(condition, seed, object_width_m=OBJECTS[object_name].width_m, **timing)
    data = script_to_yaml_data(steps, f"Ex. 14 study operator ({condition}, seed {seed}, {object_name}"
                                      f"{', quick' if quick else ''})")
    data["world"] = world
    return data
