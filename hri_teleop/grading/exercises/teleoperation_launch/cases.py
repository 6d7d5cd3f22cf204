"""Ex. 12-13's simulated lab: the world the launch file runs in and the operator's scripted drive."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Tuple

__all__ = ["LaunchSimCase", "launch_sim_case"]


@dataclass(frozen=True)
class LaunchSimCase:
    """The simulated lab and the operator the grader runs a student's teleoperation.launch with.

    The arm starts low, a sponge already between the open fingers (soft: the force rises
    over millimetres of closing, so every run sees it whatever the tap timing), so that a few seconds
    exercise every link: cross closes the hand (gripper_manager -> franka_gripper), taps
    until the rumble is strong (board -> serial_node -> mapping_node -> teleoperation),
    the right stick lifts (twist -> arm), square quits.
    """

    world: Dict[str, object]
    script: Tuple[Dict[str, object], ...]
    lift_from_s: float           # script time the right stick goes up
    lift_to_s: float             # and back to rest
    quit_s: float

    def scenario(self) -> Dict[str, object]:
        """A lab_sim scenario (world and steps), which is also a pad script."""
        return {"description": "hri-grade: teleoperation.launch in simulation",
                "world": dict(self.world), "steps": [dict(step) for step in self.script]}


def launch_sim_case() -> LaunchSimCase:
    lift_from, lift_to, quit_s = 3.6, 4.6, 5.4
    script = (
        {"t": 1.5, "press": "south"},
        {"t": 2.1, "release": "south"},
        {"t": 2.3, "tap": "south", "hold": 0.04, "every": 0.3, "until": "rumble", "above": 0.8, "max_wait": 4},
        {"t": lift_from, "axis": "right_y", "value": 0.5},
        {"t": lift_to, "axis": "right_y", "value": 0.0},
        {"t": quit_s, "tap": "west", "hold": 0.1},
    )
    world: Dict[str, object] = {"object": "sponge", "arm": {"start_position_m": [0.4, 0.0, 0.03]}}
    return LaunchSimCase(world, script, lift_from, lift_to, quit_s)
