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
# Debian installs ROS package manifests under /usr/share.
if [ -z "${ROS_DISTRO:-}" ]; then
  case ":$ROS_PACKAGE_PATH:" in *":/usr/share:"*) ;; *) export ROS_PACKAGE_PATH="$ROS_PACKAGE_PATH:/usr/share" ;; esac
fi
case ":$PATH:" in *":$_hri_root/.venv/bin:"*) ;; *) export PATH="$_hri_root/.venv/bin:$PATH" ;; esac
# A machine without a resolvable hostname still talks to itself.
export ROS_HOSTNAME="${ROS_HOSTNAME:-127.0.0.1}"
unset _hri_root
