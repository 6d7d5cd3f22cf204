"""Ex. 8-9's parts and points: the class's (Ex. 8) and the node's (``node_*``, Ex. 9), as students read them."""

from __future__ import annotations

from typing import Dict, Tuple

from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M

__all__ = ["PARTS", "NODE_PARTS"]

#: Part key -> (name as students read it, points; tests refer to the keys).
PARTS: Dict[str, Tuple[str, float]] = {
    # 0 points: the template already builds (the constructor is given); it gates the parts below.
    "import": ("imports and builds Teleoperation(rate, k_trans, k_rot, k_gripper, deadzone)", 0),
    "gripper": ("gripper width: k_gripper / rate per tick while cross/circle is held, within "
                f"0..{GRIPPER_MAX_WIDTH_M:g} m", 3),
    "twist": ("sticks -> cartesian_velocity with the dead zone and k_trans / k_rot", 4),
    "toggle": ("triangle toggles translation <-> rotation once per press", 2),
    "rumble": ("rumble from the mapped force, limited to 0..1", 2),
    "node_start": ("node: starts and subscribes /force_mapped (std_msgs/Float32)", 2),
    "node_twist_topic": ("node: publishes geometry_msgs/Twist on /cartesian_velocity_controller/cmd_vel", 2),
    "node_width_topic": ("node: publishes std_msgs/Float32 on /gripper_width", 2),
    "node_twist": ("node: the published twist follows the sticks", 2),
    "node_width": ("node: the published gripper width follows cross", 1),
    "node_rumble": ("node: the rumble follows /force_mapped", 1),
    "node_quit": ("node: square brings the twist to zero and ends the node", 1),
}
#: The parts the node's run judges (Ex. 9); the others judge the class (Ex. 8).
NODE_PARTS = tuple(key for key in PARTS if key.startswith("node_"))
