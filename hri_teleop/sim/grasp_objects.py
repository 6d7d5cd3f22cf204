"""Objects to grasp (width, stiffness, mass, friction, breaking force) and when friction holds them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional

from hri_teleop.sim.hand_params import GRAVITY_M_PER_S2, HandSimError, checked_param

__all__ = ["GraspObject", "OBJECTS", "holding_force_n", "is_held"]


@dataclass(frozen=True)
class GraspObject:
    """Something to put between the fingers (SI units; ``breaking_force_n`` None: unbreakable).

    ``stiffness_n_per_m`` is the object's stiffness across the grasp (both faces together),
    ``friction_coefficient`` the static and kinetic coefficient against the fingers.
    """

    name: str
    width_m: float
    stiffness_n_per_m: float
    mass_kg: float
    friction_coefficient: float
    breaking_force_n: Optional[float] = None
    note: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise HandSimError(f"GraspObject.name must be a non-empty string, got {self.name!r}; e.g. 'egg'")
        for name, fix in (
            ("width_m", "e.g. 0.045 for an egg"),
            ("stiffness_n_per_m", "e.g. 1e6 for a rigid block"),
            ("mass_kg", "e.g. 0.06 for an egg"),
            ("friction_coefficient", "e.g. 0.4"),
        ):
            object.__setattr__(self, name, checked_param(getattr(self, name), f"GraspObject.{name}", fix,
                                                  lowest=">0"))
        if self.breaking_force_n is not None:
            object.__setattr__(self, "breaking_force_n", checked_param(
                self.breaking_force_n, "GraspObject.breaking_force_n", "e.g. 30.0, or None for unbreakable",
                lowest=">0"))

    def min_grip_force_n(self, hand_accel_up_m_per_s2: float = 0.0) -> float:
        """The smallest grip force (N) that holds the object while the hand accelerates upwards."""
        return self.mass_kg * max(GRAVITY_M_PER_S2 + hand_accel_up_m_per_s2, 0.0) / (2.0 * self.friction_coefficient)


#: The predefined objects.  Masses are those of the real things; the lift column says what
#: grip force holds each one at rest (m g / 2 mu), against the 1.77 N of the piston spring:
#: light objects lift on the spring alone, the heavy block needs the housing to press.
OBJECTS: Dict[str, GraspObject] = {
    obj.name: obj
    for obj in (
        GraspObject(
            "block", width_m=0.05, stiffness_n_per_m=1e6, mass_kg=0.08, friction_coefficient=0.4,
            note="50 mm wooden cube (0.65 g/cm^3 -> 81 g), effectively rigid; holds from 0.98 N",
        ),
        GraspObject(
            "heavy_block", width_m=0.04, stiffness_n_per_m=1e7, mass_kg=0.17, friction_coefficient=0.3,
            note="40 mm aluminium cube (2.7 g/cm^3 -> 173 g), rigid and slippery; holds from 2.8 N, "
                 "i.e. only with the piston pressed in level with the housing",
        ),
        GraspObject(
            "sponge", width_m=0.05, stiffness_n_per_m=1500.0, mass_kg=0.015, friction_coefficient=0.8,
            note="kitchen sponge 50 mm thick, 10 N squeezes it by 7 mm; holds from 0.09 N",
        ),
        GraspObject(
            "egg", width_m=0.044, stiffness_n_per_m=1.2e5, mass_kg=0.06, friction_coefficient=0.35,
            breaking_force_n=30.0,
            note="a hen's egg across its short axis: 44 mm, 60 g, shell stiffness of the order of 100 N/mm, "
                 "cracks at 30 N (the low end of typical eggs); holds from 0.84 N, so a grip inside the "
                 "piston's travel lifts it and a squeeze past full travel crushes it within 0.25 mm",
        ),
    )
}


def holding_force_n(grip_force_n: float, friction_coefficient: float) -> float:
    """Largest vertical force (N) two friction faces carry: ``2 * mu * F_grip``."""
    return 2.0 * friction_coefficient * max(grip_force_n, 0.0)


def is_held(grip_force_n: float, obj: GraspObject, hand_accel_up_m_per_s2: float = 0.0) -> bool:
    """Whether friction carries the object while the hand accelerates upwards by ``a``.

    Held iff ``2 * mu * F_grip >= m * (g + a)``; a hand falling at ``g`` or faster needs no grip.
    """
    need_n = obj.mass_kg * max(GRAVITY_M_PER_S2 + hand_accel_up_m_per_s2, 0.0)
    return holding_force_n(grip_force_n, obj.friction_coefficient) >= need_n
