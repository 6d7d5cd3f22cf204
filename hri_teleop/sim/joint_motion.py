"""The simulated Panda's joints under a Cartesian command: follow the hand's pose, judge every joint.

Each 1 ms cycle the arm's Cartesian side has a commanded twist and the hand's next pose. The
joints take the step that reaches that pose, and the robot's joint-side checks judge the joint
motion its inverse kinematics makes of the commanded twist: position, velocity, acceleration and
jerk against the Panda's limits, with libfranka's error names.
"""

from __future__ import annotations

from functools import lru_cache
from typing import List, Optional, Sequence, Tuple

import numpy as np
import pinocchio as pin

from hri_teleop.core.joints import (
    READY_POSE_RAD,
    ROBOT_JOINT_LIMITS,
    JointLimits,
    JointVector,
    joint_violations,
)
from hri_teleop.sim.arm_config import ROBOT_MODEL, ArmModel
from hri_teleop.sim.arm_kernel import JOINT_CONST_SIZE, JOINT_STATE_SIZE, JOINT_TYPES
from hri_teleop.sim.kinematics import PandaKinematics, Vector

__all__ = ["JointMotion", "JointStep", "start_joints"]

#: One broken joint limit: (libfranka error, joint 1..7, value, limit).
JointStep = Tuple[str, int, float, float]


@lru_cache(maxsize=64)
def start_joints(position_m: Tuple[float, float, float], orientation_xyzw: Tuple[float, float, float, float],
                 limits: JointLimits = ROBOT_JOINT_LIMITS, arm: ArmModel = ROBOT_MODEL) -> JointVector:
    """The joints of a start pose, found from the ready pose (cached: many arms start alike)."""
    return PandaKinematics(limits, arm).inverse(position_m, orientation_xyzw, seed=READY_POSE_RAD)


class JointMotion:
    """The seven joints: where they are, the joint velocity the command asks of them, and the judge."""

    def __init__(self, start_rad: Sequence[float], limits: JointLimits = ROBOT_JOINT_LIMITS,
                 rel_tol: float = 1e-9, arm: ArmModel = ROBOT_MODEL) -> None:
        self.kinematics = PandaKinematics(limits, arm)
        self.limits = limits
        self.rel_tol = rel_tol
        # one array, in arm_cycle.c's layout, so that the compiled cycle works on it in place
        self.state: Vector = np.zeros(JOINT_STATE_SIZE)
        self.q: Vector = self.state[0:7]               # the joint angles (rad)
        self.velocity: Vector = self.state[7:14]       # what the joints did in the last cycle (rad/s)
        self._commanded: Vector = self.state[14:21]    # the IK of the commanded twist, last accepted cycle
        self._acceleration: Vector = self.state[21:28]  # its backward difference
        self.q[:] = np.asarray(start_rad, dtype=float)
        tol = 1.0 + rel_tol
        self._low = np.array(limits.position_min_rad)
        self._high = np.array(limits.position_max_rad)
        self._v_max = np.array(limits.velocity_rad_per_s) * tol
        self._a_max = np.array(limits.acceleration_rad_per_s2) * tol
        self._j_max = np.array(limits.jerk_rad_per_s3) * tol
        self._rhs = np.zeros((7, 2))  # row 7: the elbow stays still
        self.consts: Optional[Vector] = self._kernel_constants()

    def _kernel_constants(self) -> Optional[Vector]:
        """The limits and the chain in arm_cycle.c's layout; None when the C cannot follow this arm
        (not a chain of seven revolute joints ending in the tool frame's joint)."""
        model = self.kinematics.model
        if list(model.parents) != [0, 0, 1, 2, 3, 4, 5, 6] or model.nq != 7:
            return None
        if model.frames[self.kinematics.frame].parentJoint != 7:
            return None
        chain: List[float] = []
        for i in range(1, 8):
            kind = model.joints[i].shortname()
            if kind not in JOINT_TYPES:
                return None
            axis = (np.eye(3)[JOINT_TYPES[kind]] if JOINT_TYPES[kind] < 3
                    else np.asarray(model.joints[i].extract().axis, dtype=float))
            placement = model.jointPlacements[i]
            chain += [float(JOINT_TYPES[kind]), *axis.tolist(), *placement.rotation.reshape(9).tolist(),
                      *placement.translation.tolist()]
        frame = model.frames[self.kinematics.frame].placement
        values = [*self._low, *self._high, *self._v_max, *self._a_max, *self._j_max, float(self.kinematics.elbow),
                  *chain, *frame.rotation.reshape(9).tolist(), *frame.translation.tolist()]
        out: Vector = np.array(values, dtype=float)
        return out if out.size == JOINT_CONST_SIZE else None

    @property
    def positions(self) -> JointVector:
        q = self.q
        return (float(q[0]), float(q[1]), float(q[2]), float(q[3]), float(q[4]), float(q[5]), float(q[6]))

    def at_rest(self) -> bool:
        """No commanded joint motion and no acceleration left: an idle cycle can be skipped."""
        return not self._commanded.any() and not self._acceleration.any()

    def stop(self) -> None:
        """The robot stopped (a reflex, or recovery): the joints are at rest."""
        self._commanded[:] = 0.0
        self._acceleration[:] = 0.0
        self.velocity[:] = 0.0

    def step(self, commanded: Sequence[float], position_m: Sequence[float],
             rotation: Optional[Vector], dt: float) -> List[JointStep]:
        """One cycle: judge the command's joint motion, then move toward the hand's next pose.

        ``commanded`` is the twist the robot judged (m/s, rad/s); ``position_m`` and ``rotation``
        (a 3x3 matrix, None: unchanged) the hand's pose after this cycle. Returns the broken limits
        (and leaves the joints where they are) or [] after moving them.
        """
        kin = self.kinematics
        model, data, frame = kin.model, kin.data, kin.frame
        q = self.q
        # this runs 1000 times per simulated second: pinocchio directly, one solve for both twists
        pin.computeJointJacobians(model, data, q)
        placement = pin.updateFramePlacement(model, data, frame)
        system = kin.system(pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED))
        rhs = self._rhs
        rhs[:6, 0] = commanded
        current_r = placement.rotation
        rhs[:3, 1] = (np.asarray(position_m, dtype=float) - placement.translation) / dt
        rhs[3:6, 1] = pin.log3((rotation if rotation is not None else current_r) @ current_r.T) / dt
        try:
            both: Vector = np.asarray(np.linalg.solve(system, rhs), dtype=np.float64)
        except np.linalg.LinAlgError:  # exactly singular: no finite joint motion does it
            both = np.full((7, 2), np.inf)
        commanded_dq: Vector = both[:, 0]
        applied_dq: Vector = both[:, 1]
        acceleration: Vector = (commanded_dq - self._commanded) / dt
        jerk: Vector = (acceleration - self._acceleration) / dt
        next_q: Vector = q + applied_dq * dt
        ok = ((next_q >= self._low) & (next_q <= self._high) & (np.abs(commanded_dq) <= self._v_max)
              & (np.abs(acceleration) <= self._a_max) & (np.abs(jerk) <= self._j_max))
        if ok.all():
            self._commanded[:] = commanded_dq
            self._acceleration[:] = acceleration
            self.velocity[:] = applied_dq
            self.q[:] = next_q
            return []
        # the slow path, once per reflex: core.joints' judge names each broken limit (same tests as above)
        return [(v.error, v.joint, v.value, v.limit)
                for v in joint_violations(next_q.tolist(), commanded_dq.tolist(), acceleration.tolist(),
                                          jerk.tolist(), limits=self.limits, rel_tol=self.rel_tol)]
