#!/usr/bin/env bash
# Test helper (rostest node): renders a short deterministic globe bag with
# hapi_sim's make_globe_bag into a temporary folder, then plays it.
#   play_globe_bag.sh DURATION_S [rosbag play options...]
# roslaunch appends __name:=/__log:= arguments; they are dropped here.
set -euo pipefail
duration="$1"; shift
play_args=()
for a in "$@"; do [[ "$a" == __* ]] || play_args+=("$a"); done
dir="$(mktemp -d /tmp/hapi_frontend_globe.XXXXXX)"
trap 'rm -rf "$dir"' EXIT
rosrun hapi_sim make_globe_bag --output "$dir/globe.bag" --seed 1 --duration "$duration" --rate 10 --imu 0
rosbag play --quiet "${play_args[@]}" "$dir/globe.bag"
