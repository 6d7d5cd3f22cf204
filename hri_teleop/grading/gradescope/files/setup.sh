#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder's image (base image: Ubuntu 22.04).
# It installs what `make setup` installs, through the same script (tools/setup.sh): ROS 1 from the
# distribution's packages (ros-core, rospy, ...; universe on Ubuntu), bubblewrap for the sandbox, and
# the toolkit in /autograder/source/.venv; the student edition, without test or firmware tools.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
purelib() { "$1" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])'; }
# HRI_GRADESCOPE_REUSE_VENV=<a venv holding the toolkit's dependencies> (the test of the zip): the new
# .venv sees that venv's packages instead of downloading them. Gradescope never sets it.
if [ -n "${HRI_GRADESCOPE_REUSE_VENV:-}" ] && [ ! -x .venv/bin/python ]; then
  echo "setup.sh: reusing the packages of $HRI_GRADESCOPE_REUSE_VENV"
  /usr/bin/python3 -m venv --system-site-packages .venv
  # addsitedir, not a bare path: that venv's own .pth files (pin's cmeel prefix) must count too.
  printf 'import site; site.addsitedir(%s)\n' "'$(purelib "$HRI_GRADESCOPE_REUSE_VENV/bin/python")'" \
    > "$(purelib .venv/bin/python)/hri-gradescope-reuse.pth"
  export PIP_NO_DEPS=1 PIP_NO_BUILD_ISOLATION=0 PIP_NO_INDEX=1
fi
HRI_SETUP_EDITION=student bash tools/setup.sh
# Student processes run as an unprivileged uid of their own: they must read the toolkit and the lab files.
chmod -R a+rX .
