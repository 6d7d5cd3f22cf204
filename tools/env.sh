# Sourced by the Makefile (and by you: `. tools/env.sh`) to get the shell the lab's nodes need:
# ROS (Noetic when installed, else Debian's ROS 1), the project's .venv first on PATH so the
# nodes' `#!/usr/bin/env python3` finds rospy and hri_teleop, and hri_lab on ROS_PACKAGE_PATH.
_hri_root="$(cd "$(dirname "${BASH_SOURCE[0]:-$0}")/.." && pwd)"
if [ -f /opt/ros/noetic/setup.sh ] && [ -z "${ROS_DISTRO:-}" ]; then
  . /opt/ros/noetic/setup.sh
fi
# The package folder itself, not the repository: rospack searches a folder's subfolders, and
# a copy of hri_lab under out/ (make grade's, make bench's course) would shadow the lab's.
case ":${ROS_PACKAGE_PATH:-}:" in
  *":$_hri_root/hri_lab:"*) ;;
  *) export ROS_PACKAGE_PATH="$_hri_root/hri_lab${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}" ;;
esac
# The student bundle: sourced in an assignment folder beside this toolkit (task4/preparation or
# task4/lab, which hold the student's hri_lab/package.xml), the student's package goes first, so
# `rosrun hri_lab mapping_node.py` and `roslaunch hri_lab sensor.launch` find the student's files
# (the toolkit's hri_lab lacks them). HRI_STUDENT_PACKAGE remembers it, so sourcing again in the
# other folder swaps it; tools/kernel.sh sets HRI_ENV_TOOLKIT_FIRST (the notebooks start the
# toolkit's nodes themselves). Never in the project's checkout, which has no toolkit/ around it.
_hri_student=""
if [ -z "${HRI_ENV_TOOLKIT_FIRST:-}" ] && [ -f "$PWD/hri_lab/package.xml" ] && [ -d "$PWD/../toolkit" ] &&
   [ "$(cd "$PWD/../toolkit" && pwd -P)" = "$(cd "$_hri_root" && pwd -P)" ]; then
  _hri_student="$(cd "$PWD/hri_lab" && pwd -P)"
fi
if [ -n "$_hri_student" ] || [ -n "${HRI_STUDENT_PACKAGE:-}" ]; then
  _hri_rest="$(printf '%s' "${ROS_PACKAGE_PATH:-}" | tr ':' '\n' |
    grep -vxF -e "" -e "${_hri_student:-}" -e "${HRI_STUDENT_PACKAGE:-}" | paste -sd: -)"
  if [ -n "$_hri_student" ]; then
    export ROS_PACKAGE_PATH="$_hri_student${_hri_rest:+:$_hri_rest}" HRI_STUDENT_PACKAGE="$_hri_student"
  else
    export ROS_PACKAGE_PATH="$_hri_rest"
    unset HRI_STUDENT_PACKAGE
  fi
  unset _hri_rest
fi
unset _hri_student
# Debian installs ROS package manifests under /usr/share; the message definitions without one get
# theirs from make setup (.venv/share/hri-ros-msgs), so that rosmsg show finds std_msgs.
if [ -z "${ROS_DISTRO:-}" ]; then
  case ":$ROS_PACKAGE_PATH:" in *":/usr/share:"*) ;; *) export ROS_PACKAGE_PATH="$ROS_PACKAGE_PATH:/usr/share" ;; esac
  if [ -d "$_hri_root/.venv/share/hri-ros-msgs" ]; then
    case ":$ROS_PACKAGE_PATH:" in *":$_hri_root/.venv/share/hri-ros-msgs:"*) ;;
      *) export ROS_PACKAGE_PATH="$ROS_PACKAGE_PATH:$_hri_root/.venv/share/hri-ros-msgs" ;; esac
  fi
fi
case ":$PATH:" in *":$_hri_root/.venv/bin:"*) ;; *) export PATH="$_hri_root/.venv/bin:$PATH" ;; esac
# A machine without a resolvable hostname still talks to itself.
export ROS_HOSTNAME="${ROS_HOSTNAME:-127.0.0.1}"
unset _hri_root
