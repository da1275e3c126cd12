#!/usr/bin/env bash
# roslaunch env-loader for the <machine> tags of launch/distributed.launch:
# roslaunch runs `env_loader.sh <command...>` on each host (over SSH for
# remote ones); this sets up that host's ROS environment and execs the command.
#
#  * sources the catkin workspace: HAPI_WS, else <this checkout>/.ws
#    (scripts/setup.sh's default), so the host's own build is used;
#  * ROS_IP: HAPI_ROS_IP if set, else the source address this host uses to
#    reach the master (ROS_MASTER_URI, passed by roslaunch): the right
#    interface on a Jetson with Wi-Fi + Ethernet, no per-host file to edit.
set -e
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
if [ ! -f "$WS/devel/setup.bash" ]; then
  echo "env_loader: no workspace at $WS on $(hostname) (set HAPI_WS or run scripts/setup.sh)" >&2
  exit 1
fi
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
if [ -n "$HAPI_ROS_IP" ]; then
  export ROS_IP="$HAPI_ROS_IP"
elif [ -n "$ROS_MASTER_URI" ]; then
  master_host="$(sed -E 's#^[a-z]+://([^:/]+).*#\1#' <<<"$ROS_MASTER_URI")"
  master_ip="$(getent ahostsv4 "$master_host" | awk 'NR==1 {print $1}')"
  if [ -n "$master_ip" ]; then
    src="$(ip -4 route get "$master_ip" 2>/dev/null | sed -nE 's/.* src ([0-9.]+).*/\1/p')"
    [ -n "$src" ] && export ROS_IP="$src"
  fi
fi
exec "$@"
