"""Random simulated operators: pad scripts that do what hurried, clumsy people do.

Why: "no command stream ever breaks the Franka's limits" must hold for *any* operator,
not only for the polite default scenario.  :func:`random_operator` draws a seeded pad
script with the inputs that stress the twist limiter most -- full stick reversals in one
tick, mode toggles mid-motion, both gripper buttons, a pad that is unplugged or fails to
read, quitting while moving -- and :func:`script_to_yaml_data` writes it in the YAML the
teleoperation node replays (``~pad_script``), so the same operator runs offline
(:func:`hri_teleop.sim.lab.run_lab`) and through the real node.
"""

from __future__ import annotations

import random
from typing import Any, Dict, List

from hri_teleop.gamepad import ScriptStep

__all__ = ["random_operator", "script_to_yaml_data", "study_operator"]

_STICKS = ("left_x", "left_y", "right_x", "right_y")
_BUTTONS = ("south", "east", "north")


def random_operator(seed: int, duration_s: float = 10.0, quit_at_end: bool = True) -> List[ScriptStep]:
    """A seeded random pad script of about ``duration_s`` seconds (see the module doc)."""
    rng = random.Random(seed)
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
            button = rng.choice(_BUTTONS)
            if button in pressed:
                pressed.discard(button)
                steps.append(ScriptStep(t, "release", (button,)))
            else:
                pressed.add(button)
                steps.append(ScriptStep(t, "press", (button,)))
        elif roll < 0.88:
            steps.append(ScriptStep(t, "tap", (rng.choice(_BUTTONS),), hold_s=rng.choice((0.02, 0.04, 0.1))))
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


def study_operator(condition: str, seed: int) -> List[ScriptStep]:
    """A participant of Ex. 14's experiment grasping and lifting the egg (default world).

    Both conditions approach the same way and close fast to 56 mm.  Then:

    * ``feedback``: taps cross (1.6 mm a tap) until the pad rumbles above 0.9 -- the
      default scenario's careful operator;
    * ``no_feedback``: cannot feel the piston, so judges by eye: 6 to 9 taps, drawn with
      the seed and biased towards squeezing too much (7 taps land in the piston's window;
      6 hold too lightly and the egg slips, 8 or more crush it).

    The timing jitters with the seed (reaction and pauses), as people do.
    """
    if condition not in ("feedback", "no_feedback"):
        raise ValueError(f"condition must be feedback or no_feedback, got {condition!r}")
    rng = random.Random(seed)
    t = round(1.0 + rng.uniform(0.0, 0.3), 2)
    steps = [ScriptStep(t, "axis", ("right_y",), -1.0)]
    t = round(t + 4.6, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.0))
    t = round(t + 0.9 + rng.uniform(0.0, 0.3), 2)
    steps.append(ScriptStep(t, "press", ("south",)))
    t = round(t + 0.6, 2)
    steps.append(ScriptStep(t, "release", ("south",)))
    t = round(t + 0.5, 2)
    if condition == "feedback":
        steps.append(ScriptStep(t, "tap", ("south",), hold_s=0.04, every_s=0.5, condition="rumble", above=0.9,
                                max_wait_s=20.0))
        t = round(t + 0.5, 2)
    else:
        for _ in range(rng.choice((6, 7, 8, 8, 9))):
            steps.append(ScriptStep(t, "tap", ("south",), hold_s=0.04))
            t = round(t + 0.5, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.5))
    t = round(t + 2.0, 2)
    steps.append(ScriptStep(t, "axis", ("right_y",), 0.0))
    t = round(t + 2.0, 2)
    steps.append(ScriptStep(t, "tap", ("west",), hold_s=0.1))
    return steps
