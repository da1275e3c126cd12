#!/usr/bin/env bash
# Creates an offline rosdep view under $ROS_HOME/rosdep (no network): sources =
# config/rosdep/hapi_system_deps.yaml, rosdistro index = an empty local one.
#
# Why: Debian's rospkg splits a package.xml's dependencies into ROS packages
# and system deps through rosdep; with no rosdep view every package has *no*
# dependencies, so tools built on rospkg.get_depends_on() -- notably
# `rosrun nodelet declared_nodelets` -- list nothing. pluginlib (C++) is not
# affected; this is only for the Python tools.
#
# Idempotent; skipped when a rosdep view already exists in $ROS_HOME.
#   ROS_HOME=/path/ros_home scripts/rosdep_offline.sh
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
: "${ROS_HOME:?set ROS_HOME (the view lives in \$ROS_HOME/rosdep)}"
if [ -f "$ROS_HOME/rosdep/sources.cache/index" ]; then
  echo "[rosdep] view present in $ROS_HOME/rosdep"
  exit 0
fi
command -v rosdep >/dev/null || { echo "[rosdep] rosdep not installed (python3-rosdep2)" >&2; exit 1; }
SRC="$ROS_HOME/rosdep/offline"
mkdir -p "$SRC/sources.list.d"
cp "$REPO/config/rosdep/hapi_system_deps.yaml" "$SRC/hapi_system_deps.yaml"
echo "yaml file://$SRC/hapi_system_deps.yaml" >"$SRC/sources.list.d/10-hapi-offline.list"
printf 'type: index\nversion: 4\ndistributions: {}\n' >"$SRC/index-v4.yaml"
ROSDEP_SOURCE_PATH="$SRC/sources.list.d" ROSDISTRO_INDEX_URL="file://$SRC/index-v4.yaml" \
  rosdep update >"$SRC/update.log" 2>&1 || { cat "$SRC/update.log" >&2; exit 1; }
echo "[rosdep] offline view created in $ROS_HOME/rosdep"
