"""The Panda's kinematics for the simulation: pinocchio on the Panda description of example-robot-data.

Forward kinematics gives the hand's pose from the seven joints; a twist becomes joint velocities
the way a Cartesian velocity interface with a fixed elbow does it: the six equations of the hand's
Jacobian plus one that keeps joint 3 (Franka's "elbow") where it is. Near a singular pose the
solution grows without bound, which the arm's joint judge then refuses, as the robot does.
"""

from __future__ import annotations

import importlib.metadata
import math
from functools import lru_cache
from pathlib import Path
from typing import Any, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.joints import (
    READY_POSE_RAD,
    ROBOT_JOINT_LIMITS,
    JointLimits,
    JointVector,
)
from hri_teleop.sim.arm_config import ROBOT_MODEL, ArmModel

__all__ = ["KinematicsError", "panda_urdf", "panda_package_dir", "PandaKinematics", "TCP_FRAME", "ELBOW_JOINT"]

# The model, its tool frame and its elbow come from the robot profile (core/robots/franka_panda.yaml).
#: The frame the lab's commands move: between the fingertips (franka_description's ``panda_hand_tcp``).
TCP_FRAME: str = ROBOT_MODEL.tool_frame
#: Franka's "elbow": the joint whose angle a Cartesian velocity command leaves as it is (index 2 = joint 3).
ELBOW_JOINT: int = ROBOT_MODEL.elbow_index
Vector = npt.NDArray[np.float64]


class KinematicsError(HriTeleopError, RuntimeError):
    """The Panda model cannot be loaded, or a pose cannot be reached (the message names the fix)."""


def panda_urdf(urdf: str = ROBOT_MODEL.urdf) -> Path:
    """The URDF at ``urdf`` (default: the Panda's) as example-robot-data installs it."""
    try:
        files = importlib.metadata.files("example-robot-data") or []
    except importlib.metadata.PackageNotFoundError:
        raise KinematicsError("the Panda's description is missing: example-robot-data is not installed; run "
                              "`make setup` (or pip install example-robot-data)") from None
    for entry in files:
        if str(entry).endswith(urdf):
            return Path(str(entry.locate()))
    raise KinematicsError(f"the robot profile's kinematics.urdf {urdf!r} is not in example-robot-data; name a "
                          "URDF it installs (the Panda's: robots/panda_description/urdf/panda.urdf)")


def panda_package_dir() -> Path:
    """The folder a ``package://example-robot-data/...`` mesh path is relative to (for viewers)."""
    return panda_urdf().parents[4]


@lru_cache(maxsize=4)
def _arm_model(arm: ArmModel) -> Any:
    """The seven-joint arm (fingers locked open): loaded once per process and description."""
    try:
        full = pin.buildModelFromUrdf(str(panda_urdf(arm.urdf)))
    except (RuntimeError, ValueError) as exc:
        raise KinematicsError(f"pinocchio cannot read the Panda's URDF ({exc}); reinstall example-robot-data "
                              "with `make setup`") from None
    fingers = [full.getJointId(name) for name in arm.finger_joints]
    return pin.buildReducedModel(full, fingers, pin.neutral(full))


def _quaternion_xyzw(rotation: Vector) -> Tuple[float, float, float, float]:
    q = pin.Quaternion(rotation)
    x, y, z, w = float(q.x), float(q.y), float(q.z), float(q.w)
    if w < 0.0:  # one of the two equal quaternions: the one with w >= 0
        x, y, z, w = -x, -y, -z, -w
    return (x, y, z, w)


class PandaKinematics:
    """Forward kinematics and the twist-to-joint-velocity map of the arm, one instance per arm."""

    def __init__(self, limits: JointLimits = ROBOT_JOINT_LIMITS, arm: ArmModel = ROBOT_MODEL) -> None:
        self.model = _arm_model(arm)
        if tuple(self.model.names)[1:] != arm.joint_names:
            raise KinematicsError(f"the model's joints are {tuple(self.model.names)[1:]}, not the robot profile's "
                                  f"{arm.joint_names}; name the URDF's joints in joints.names")
        self.data = self.model.createData()
        if not self.model.existFrame(arm.tool_frame):
            raise KinematicsError(f"the URDF {arm.urdf} has no frame {arm.tool_frame!r} (the robot profile's "
                                  "kinematics.tool_frame); name one of its frames, e.g. panda_hand_tcp")
        self.frame = self.model.getFrameId(arm.tool_frame)
        self.elbow = arm.elbow_index
        self.limits = limits
        self._system = np.zeros((7, 7))
        self._system[6, self.elbow] = 1.0
        self._rhs = np.zeros(7)
        self._q: Optional[Vector] = None

    def _update(self, q: Vector) -> None:
        """Joint placements and Jacobians for ``q`` (once per configuration)."""
        if self._q is not None and np.array_equal(self._q, q):
            return
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacement(self.model, self.data, self.frame)
        self._q = q.copy()

    def pose(self, q: npt.ArrayLike) -> Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]:
        """The hand's (TCP's) position (m) and orientation (unit quaternion x, y, z, w) in the base frame."""
        self._update(np.asarray(q, dtype=float))
        placement = self.data.oMf[self.frame]
        p = placement.translation
        return (float(p[0]), float(p[1]), float(p[2])), _quaternion_xyzw(placement.rotation)

    def position(self, q: npt.ArrayLike) -> Vector:
        """The TCP's position (m) as an array (no copy of the orientation)."""
        self._update(np.asarray(q, dtype=float))
        out: Vector = np.array(self.data.oMf[self.frame].translation)
        return out

    def rotation(self, q: npt.ArrayLike) -> Vector:
        """The TCP's rotation matrix in the base frame."""
        self._update(np.asarray(q, dtype=float))
        out: Vector = np.array(self.data.oMf[self.frame].rotation)
        return out

    def system(self, jacobian: Vector) -> Vector:
        """The 7 x 7 system of a twist: the hand's Jacobian (base-frame axes) over the elbow's row."""
        self._system[:6, :] = jacobian
        return self._system

    def joint_velocities(self, q: npt.ArrayLike, twists: Vector) -> Vector:
        """Joint velocities (rad/s) for each column of ``twists`` (6 x n: vx vy vz wx wy wz, base frame).

        The elbow (joint 3) stays still. An exactly singular pose gives infinite velocities.
        """
        self._update(np.asarray(q, dtype=float))
        system = self.system(pin.getFrameJacobian(self.model, self.data, self.frame, pin.LOCAL_WORLD_ALIGNED))
        rhs = np.zeros((7, twists.shape[1]))
        rhs[:6, :] = twists
        try:
            out: Vector = np.asarray(np.linalg.solve(system, rhs), dtype=np.float64)
        except np.linalg.LinAlgError:
            out = np.full((7, twists.shape[1]), math.inf)
            out[:, ~rhs[:6].any(axis=0)] = 0.0
        return out

    def inverse(self, position_m: Sequence[float], orientation_xyzw: Sequence[float],
                seed: Sequence[float] = READY_POSE_RAD, iterations: int = 400) -> JointVector:
        """Joint positions that put the TCP at a pose, found from ``seed`` with the elbow held.

        Damped steps inside the joint limits; KinematicsError when the pose cannot be reached
        that way (out of reach, or only past a joint limit), naming the joint in the way.
        """
        x, y, z, w = (float(c) for c in orientation_xyzw)
        target_r = pin.Quaternion(w, x, y, z).normalized().toRotationMatrix()
        target_p = np.asarray(position_m, dtype=float)
        low = np.array(self.limits.position_min_rad)
        high = np.array(self.limits.position_max_rad)
        q = np.clip(np.asarray(seed, dtype=float), low, high)
        error = math.inf
        for _ in range(iterations):
            self._update(q)
            placement = self.data.oMf[self.frame]
            e = np.concatenate([target_p - placement.translation, pin.log3(target_r @ placement.rotation.T)])
            error = float(np.linalg.norm(e))
            if error < 1e-10:
                break
            jacobian = pin.getFrameJacobian(self.model, self.data, self.frame, pin.LOCAL_WORLD_ALIGNED)
            system = np.vstack([jacobian, np.eye(7)[self.elbow]])
            step = system.T @ np.linalg.solve(system @ system.T + 1e-4 * np.eye(7), np.append(np.clip(e, -0.05, 0.05), 0.0))
            q = np.clip(q + step, low, high)
        if error > 1e-6:
            margins = np.minimum(q - low, high - q)
            stuck = int(np.argmin(margins))
            raise KinematicsError(
                f"the pose {tuple(round(float(c), 4) for c in target_p)} m is out of the Panda's reach with this "
                f"orientation (the nearest the arm gets is {error:.3f} away, joint {stuck + 1} at "
                f"{q[stuck]:+.2f} rad next to its limit); pick a pose nearer the ready pose (0.307, 0, 0.487) m")
        return (float(q[0]), float(q[1]), float(q[2]), float(q[3]), float(q[4]), float(q[5]), float(q[6]))
