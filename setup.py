"""The one build step pyproject.toml cannot say: the simulated arm's compiled cycle (hri_teleop/sim/arm_cycle.c).

Optional: without a C compiler the install goes on and the arm runs its cycles in Python
(hri_teleop.sim.arm_kernel), with the same results, slower. Plain C loaded by ctypes: it needs
no Python headers, and one build serves every Python of the machine.
"""

from setuptools import Extension, setup

setup(ext_modules=[Extension(
    "hri_teleop.sim._arm_cycle", ["hri_teleop/sim/arm_cycle.c"], optional=True, libraries=["m"],
    # the same doubles as Python's arithmetic: no fused multiply-add (aarch64 would fuse by default)
    extra_compile_args=["-O2", "-std=c99", "-ffp-contract=off"],
)])
