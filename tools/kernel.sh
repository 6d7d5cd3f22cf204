#!/usr/bin/env bash
# The "hri-teleop" Jupyter kernel that `make lab` registers: the lab's shell (tools/env.sh: ROS,
# .venv first on PATH, hri_lab on ROS_PACKAGE_PATH), then .venv's Python with Jupyter's arguments
# (kernel.json passes: -m ipykernel_launcher -f <connection file>). exec: Jupyter's interrupt and
# shutdown signals reach the kernel itself, and its exit runs hri_teleop.course.notebook_ros's cleanup.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# The toolkit's hri_lab first even when Jupyter starts the kernel in an assignment folder (env.sh).
HRI_ENV_TOOLKIT_FIRST=1
. "$here/tools/env.sh"
export PYGAME_HIDE_SUPPORT_PROMPT=1
exec "$here/.venv/bin/python" "$@"
