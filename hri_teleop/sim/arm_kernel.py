"""The simulated arm's common 1 kHz cycles in C (``arm_cycle.c``), loaded with ctypes when pip built it.

The Python cycle (:class:`~hri_teleop.sim.arm.SimArm`, :class:`~hri_teleop.sim.joint_motion.JointMotion`)
is the reference: the C runs the same arithmetic for cycles without an event and hands every other
cycle back. Where no compiler was there at install, :func:`kernel` is None and the arm runs in
Python alone, with the same results (to rounding), 5 to 10 times slower. ``HRI_SIM_KERNEL=python``
chooses that path on purpose (the benchmark's reference, the equivalence tests).
"""

from __future__ import annotations

import ctypes
import os
from contextlib import contextmanager
from functools import lru_cache
from pathlib import Path
from typing import Iterator, List, Optional

__all__ = ["ArmKernel", "kernel", "kernel_library", "load_library", "python_cycles", "STATE_SIZE", "PARAM_SIZE", "JOINT_STATE_SIZE",
           "JOINT_CONST_SIZE", "TRACE_WIDTH", "JOINT_TYPES"]

#: Sizes of the four arrays the C takes (arm_cycle.c's enums; a library of another layout is not loaded).
STATE_SIZE, PARAM_SIZE, JOINT_STATE_SIZE, JOINT_CONST_SIZE = 47, 16, 28, 36 + 7 * 16 + 12
#: Doubles per cycle in a trace: the hand's position (3) and velocity (6) after the cycle.
TRACE_WIDTH = 9
#: pinocchio's joint models the C knows, with its code for each.
JOINT_TYPES = {"JointModelRX": 0, "JointModelRY": 1, "JointModelRZ": 2, "JointModelRevoluteUnaligned": 3}

_Doubles = ctypes.POINTER(ctypes.c_double)
_forced_python = [False]


def kernel_library() -> Optional[Path]:
    """The shared library pip built beside this module (any Python's build: it uses no Python API)."""
    here = Path(__file__).resolve().parent
    for path in sorted(here.glob("_arm_cycle*.so")):
        return path
    return None


class ArmKernel:
    """The loaded library: :meth:`run` runs cycles ``first..last`` and says where Python takes over."""

    def __init__(self, library: ctypes.CDLL) -> None:
        run = library.hri_arm_run
        run.argtypes = [_Doubles, _Doubles, _Doubles, _Doubles, ctypes.c_double, ctypes.c_int, ctypes.c_int, _Doubles]
        run.restype = ctypes.c_int
        self._run = run

    def run(self, state: "ctypes.Array[ctypes.c_double]", params: "ctypes.Array[ctypes.c_double]",
            joint_state: Optional["ctypes._Pointer[ctypes.c_double]"],
            joint_consts: Optional["ctypes._Pointer[ctypes.c_double]"], t0: float, first: int, last: int,
            trace: Optional["ctypes.Array[ctypes.c_double]"]) -> int:
        """Cycles ``first..last`` at ``t0 + k * dt``; returns the first one Python must run (last + 1: none)."""
        return int(self._run(state, params, joint_state, joint_consts, t0, first, last, trace))


@lru_cache(maxsize=1)
def load_library() -> Optional[ArmKernel]:
    """The built library, loaded once; None when absent, broken or of another layout."""
    path = kernel_library()
    if path is None:
        return None
    try:
        library = ctypes.CDLL(str(path))
        layout = library.hri_arm_layout
        layout.argtypes = [ctypes.c_int]
        layout.restype = ctypes.c_int
    except (OSError, AttributeError):  # a broken or foreign build: the Python cycle does the same work
        return None
    if [layout(i) for i in range(4)] != [STATE_SIZE, PARAM_SIZE, JOINT_STATE_SIZE, JOINT_CONST_SIZE]:
        return None
    return ArmKernel(library)


def kernel() -> Optional[ArmKernel]:
    """The compiled cycle, or None: not built here, or the Python path chosen (HRI_SIM_KERNEL=python)."""
    if _forced_python[0] or os.environ.get("HRI_SIM_KERNEL", "") == "python":
        return None
    return load_library()


@contextmanager
def python_cycles() -> Iterator[None]:
    """Arms made inside this block run every cycle in Python (the reference, for comparisons)."""
    before = _forced_python[0]
    _forced_python[0] = True
    try:
        yield
    finally:
        _forced_python[0] = before


def doubles(values: List[float]) -> "ctypes.Array[ctypes.c_double]":
    """A C array holding ``values``."""
    return (ctypes.c_double * len(values))(*values)
