#!/usr/bin/env bash
# Installs what `make demo` and `make test` need, and nothing that is already there.
#
# Why a script and not only Makefile rules: the decision "use the lab's /opt/ros/noetic
# or Debian's ROS 1 packages" and "root, sudo or tell the user" is easier to read here.
# Idempotent: a second run only checks (dpkg-query, a stamp file) and takes about half a second (`make bench notebooks` measures it).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
venv="$here/.venv"
stamp="$venv/.hri-teleop-installed"

say() { printf 'setup: %s\n' "$*"; }

# Debian packages the project uses. ros-core brings roscore, roslaunch, rosbag, rosparam,
# rostopic; the rest are the message and client libraries the nodes import.
apt_packages=(
  ros-core python3-rospy python3-roslaunch python3-rosbag python3-rosgraph
  python3-std-msgs python3-geometry-msgs python3-sensor-msgs
  python3-diagnostic-msgs python3-std-srvs
  python3-actionlib python3-actionlib-msgs python3-genpy
  # the message definitions rosmsg show reads (the handout's `rostopic type /force_mapped | rosmsg show`)
  ros-std-msgs ros-geometry-msgs ros-sensor-msgs ros-actionlib-msgs
  rospack-tools rosbash catkin python3-venv catkin-lint bubblewrap
  # System libraries the pip wheels load and do not carry: pinocchio (the simulated Panda, the 3D
  # view) needs libgomp and libquadmath, pygame's mixer glib. Present on most desktops, not on a
  # minimal system (a container's base: the simulated arm failed to import there).
  libgomp1 libquadmath0 libglib2.0-0
  # `make firmware` and its tests: the Uno's toolchain and Arduino core, simavr with its
  # library (the simulated Uno), a host compiler (the harness, the sketches' host tests).
  gcc-avr avr-libc binutils-avr arduino-core-avr simavr libsimavr-dev gcc g++ make
)
# HRI_SETUP_EDITION=student (the student bundle's `make setup`): the toolkit without its test
# tools, the firmware toolchain or the Python 3.8 test environment.
edition="${HRI_SETUP_EDITION:-project}"
if [ "$edition" = student ]; then
  apt_packages=(
    ros-core python3-rospy python3-roslaunch python3-rosbag python3-rosgraph
    python3-std-msgs python3-geometry-msgs python3-sensor-msgs
    python3-diagnostic-msgs python3-std-srvs
    python3-actionlib python3-actionlib-msgs python3-genpy
    ros-std-msgs ros-geometry-msgs ros-sensor-msgs ros-actionlib-msgs
    rospack-tools rosbash catkin python3-venv bubblewrap
    libgomp1 libquadmath0 libglib2.0-0
    # pip builds the simulated arm's compiled cycle with it (without, the arm runs in Python, slower)
    gcc libc6-dev
  )
fi
# `make lab`'s browser test (tests/integration/test_jupyterlab_browser.py): headless Chromium
# and its WebDriver. Debian's packages; Ubuntu ships Chromium only as a snap (the test skips there).
if [ "$edition" != student ] && grep -qs '^ID=debian' /etc/os-release; then apt_packages+=(chromium chromium-driver); fi
# Tests check the "no root" path with a package list of their own.
if [ -n "${HRI_SETUP_APT_PACKAGES:-}" ]; then read -r -a apt_packages <<<"$HRI_SETUP_APT_PACKAGES"; fi
uid="$(id -u)"
debian_ros=0
[ -z "${HRI_SETUP_PRETEND_UID:-}" ] || uid="$HRI_SETUP_PRETEND_UID"

if [ -n "${CONDA_PREFIX:-}" ] && [ -x "$CONDA_PREFIX/bin/python" ] && "$CONDA_PREFIX/bin/python" -c 'import rospy' 2>/dev/null; then
  # A conda environment made from environment.yml (RoboStack's ROS Noetic), active: its Python
  # has rospy; install nothing from apt (macOS, or a Linux without apt).
  say "using ROS from the conda environment $CONDA_PREFIX"
  system_python="$CONDA_PREFIX/bin/python"
elif [ -f /opt/ros/noetic/setup.sh ]; then
  # The lab PCs: ROS Noetic is installed; use it and install nothing from apt.
  say "using ROS Noetic from /opt/ros/noetic"
  set +u; . /opt/ros/noetic/setup.sh; set -u
  system_python=/usr/bin/python3
else
  # One dpkg-query for all packages (one per package was ~28 processes, a third of a no-op
  # setup). A package counts as installed exactly as before: when what `dpkg-query -W
  # -f='${Status}' NAME` alone would print is "install ok installed". dpkg-query prints in
  # its own order, so each name (and name:arch) gathers its statuses from all lines.
  missing=()
  statuses="$(dpkg-query -W -f='${Package} ${Status}\n${Package}:${Architecture} ${Status}\n' "${apt_packages[@]}" 2>/dev/null || true)"
  for p in "${apt_packages[@]}"; do
    status=""
    while read -r name state; do
      [ "$name" != "$p" ] || status+="$state"
    done <<<"$statuses"
    [ "$status" = "install ok installed" ] || missing+=("$p")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    if ! command -v apt-get >/dev/null 2>&1; then
      say "missing ${missing[*]} and no apt-get: on a system without apt, make the conda environment of environment.yml (mamba env create -f environment.yml), activate it (mamba activate hri-teleop), then run 'make setup' again; or use the container (README)" >&2
      exit 1
    fi
    if [ "$uid" -eq 0 ]; then
      sudo_cmd=()
    elif [ -z "${HRI_SETUP_PRETEND_UID:-}" ] && command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
      sudo_cmd=(sudo -n)
    else
      say "need root to install ${#missing[@]} Debian package(s). Run this, then 'make setup' again:" >&2
      printf '  sudo apt-get update && sudo apt-get install -y %s\n' "${missing[*]}" >&2
      exit 1
    fi
    say "installing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    "${sudo_cmd[@]}" apt-get update -qq
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
  system_python=/usr/bin/python3
  debian_ros=1
fi

if ! "$system_python" -c 'import ensurepip, venv' 2>/dev/null; then
  say "$system_python cannot create a virtual environment: run 'sudo apt-get install -y python3-venv', then 'make setup' again" >&2
  exit 1
fi
# The venv must come from the interpreter whose dist-packages hold rospy, and see them.
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import sys' 2>/dev/null; then
  say "creating $venv (with system site packages, so rospy is importable)"
  rm -rf "$venv"
  "$system_python" -m venv --system-site-packages "$venv"
fi

# Debian keeps message definitions (ros-std-msgs, ...) in /usr/share/<package>/msg, but their
# package.xml comes only with the C++ -dev packages: without one, rospack cannot find the package
# and `rosmsg show std_msgs/Float32` fails ("unknown package [std_msgs]"). A manifest for each
# such folder, in .venv/share/hri-ros-msgs, which tools/env.sh puts on ROS_PACKAGE_PATH.
if [ "$debian_ros" = 1 ]; then
  for msg in /usr/share/*/msg; do
    package="$(basename "$(dirname "$msg")")"
    manifest="$venv/share/hri-ros-msgs/$package"
    if [ -d "$msg" ] && [ ! -f "/usr/share/$package/package.xml" ] && [ ! -f "$manifest/package.xml" ]; then
      mkdir -p "$manifest"
      ln -sfn "$msg" "$manifest/msg"
      printf '<?xml version="1.0"?>\n<package format="2">\n  <name>%s</name>\n  <version>0.0.0</version>\n  <description>Debian'"'"'s message definitions in %s (a manifest made by make setup)</description>\n  <maintainer email="hri-teleop@example.org">hri-teleop setup</maintainer>\n  <license>BSD</license>\n  <buildtool_depend>catkin</buildtool_depend>\n</package>\n' "$package" "$msg" > "$manifest/package.xml"
    fi
  done
fi

# The term's exact versions (constraints.txt, written by `make pins`): every install takes them.
pins=()
[ ! -f constraints.txt ] || pins=(-c constraints.txt)
want="$(cat pyproject.toml constraints.txt 2>/dev/null | sha256sum | cut -c1-16)"
# The lab PCs run Python 3.8. Where this machine has a python3.8 (pyenv) and is not itself
# on 3.8, a small ROS-free .venv38 lets `make test` run the core's unit tests on 3.8 too. It is
# built beside .venv, at the same time (about 45 s each from pip's cache): it gets the project's
# dependencies and a .pth file that puts this checkout on its path (what an editable install does
# for imports), so the two installs never build the project in the same folder at once. The stamp is checked first: looking for
# python3.8 costs ~0.15 s (pyenv's shim is a shell script) and only matters when .venv38 is to be built.
build_venv38() {
  say "creating .venv38 (Python 3.8, as on the lab PCs) for the core's unit tests"
  # pip >= 24.1 (24.3.1, the last for 3.8): the pip 23.0 of python3.8's ensurepip backtracks
  # for many minutes over the Jupyter stack (jsonschema extras); 24.3 resolves it in seconds.
  rm -rf .venv38
  local requirements
  if "$py38" -m venv .venv38 \
    && .venv38/bin/python -m pip install -q --disable-pip-version-check "pip>=24.1" \
    && requirements="$(.venv38/bin/python tools/requirements.py dependencies test)" \
    && printf '%s\n' "$requirements" > .venv38/requirements.txt \
    && .venv38/bin/python -m pip install -q --disable-pip-version-check ${pins[@]+"${pins[@]}"} -r .venv38/requirements.txt \
    && printf '%s\n' "$here" > "$(.venv38/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/hri_teleop_checkout.pth"; then
    echo "$want38" > .venv38/.stamp
  else
    say "could not build .venv38; the Python 3.8 run of the unit tests will be skipped" >&2
    rm -rf .venv38
  fi
}
venv38_job=""
if [ "$edition" != student ]; then
  want38="$(printf '%s' "$want" | sha256sum | cut -c1-16)"
  py38=""
  if [ "$(cat .venv38/.stamp 2>/dev/null || true)" != "$want38" ]; then
    for candidate in "$(command -v python3.8 || true)" "${PYENV_ROOT:-$HOME/.pyenv}"/versions/3.8*/bin/python3.8; do
      if [ -n "$candidate" ] && [ -x "$candidate" ] && "$candidate" -c 'import sys' >/dev/null 2>&1; then
        py38="$candidate"; break
      fi
    done
  fi
  if [ -n "$py38" ] && [ "$("$system_python" -c 'import sys; print(sys.version_info[:2] != (3, 8))')" = "True" ]; then
    build_venv38 &
    venv38_job=$!
    trap '[ -z "$venv38_job" ] || kill "$venv38_job" 2>/dev/null || true' EXIT
  fi
fi

# .venv's install also builds the simulated arm's compiled cycle: a changed C file reinstalls it too
want_venv="$want-$( (cat setup.py hri_teleop/sim/arm_cycle.c 2>/dev/null || true) | sha256sum | cut -c1-16)"
have="$(cat "$stamp" 2>/dev/null || true)"
if [ "$want_venv" != "$have" ] || ! "$venv/bin/python" -c 'import hri_teleop' 2>/dev/null; then
  # Ubuntu 20.04's pip 20.0 cannot install a pyproject-only project in editable mode.
  if ! "$venv/bin/python" -c 'import sys, pip; sys.exit(tuple(map(int, pip.__version__.split(".")[:2])) < (21, 3))' 2>/dev/null; then
    say "upgrading pip in .venv (editable installs need pip >= 21.3)"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check "pip>=21.3"
  fi
  say "installing hri-teleop and its dependencies into .venv"
  if [ "$edition" = student ]; then extras=""; else extras="[test]"; fi
  "$venv/bin/python" -m pip install -q --disable-pip-version-check ${pins[@]+"${pins[@]}"} -e ".$extras"
  echo "$want_venv" > "$stamp"
fi

# Noetic machines may lack catkin_lint (not part of ros-noetic-desktop): take it from PyPI.
if [ "$edition" != student ] && [ -n "${ROS_DISTRO:-}" ] && ! command -v catkin_lint >/dev/null 2>&1 && [ ! -x "$venv/bin/catkin_lint" ]; then
  say "installing catkin_lint into .venv"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "catkin_lint>=1.6"
fi

if ! "$venv/bin/python" -c 'import rospy, actionlib, rosbag, genpy' 2>/dev/null; then
  say "rospy is not importable from .venv; remove .venv and run 'make setup' again" >&2
  exit 1
fi
if [ -n "$venv38_job" ]; then wait "$venv38_job" || true; venv38_job=""; fi
say "ready ($("$venv/bin/python" --version), ROS from ${ROS_DISTRO:-Debian packages})"
