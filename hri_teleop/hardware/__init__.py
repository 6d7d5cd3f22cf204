"""The hardware boundary: the lab's real devices (``real``) and their home stand-ins (``sim``).

Both sides speak the interfaces of :mod:`hri_teleop.core` (a pad gives a ``PadState``, a board
a count), so a node does not know which one it drives; :mod:`hri_teleop.hardware.gamepad` picks.
"""
