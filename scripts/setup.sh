#!/usr/bin/env bash
# One entry point that prepares a fresh Debian bookworm machine and builds the
# whole workspace. Idempotent: a second run installs nothing and rebuilds only
# what changed. Network: Debian's package mirrors only.
#
#   scripts/setup.sh            # install packages (if missing) + catkin_make
#   HAPI_WS=/path scripts/setup.sh   # use another workspace folder
#   HAPI_MAKE_TARGETS="a b" scripts/setup.sh   # build only these targets (tools/sanitize.sh)
#
# Prints the workspace path as its last line.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
JOBS="${HAPI_JOBS:-$(nproc)}"

# Debian's ROS tools are written for /usr/bin/python3; another python3 first on
# PATH (pyenv, conda, venv) has no ROS modules and breaks catkin and rospack.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true

# shellcheck source=debian-packages.sh
source "$REPO/scripts/debian-packages.sh"

missing=()
for p in "${HAPI_DEBIAN_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing ${#missing[@]} Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "[setup] all Debian packages present"
fi

# A catkin workspace whose src/ holds this repository (as a link, so the
# checkout itself stays where it is). catkin_pkg follows the link and stops at
# our root package.xml; the nested packages are added by our root CMakeLists.
mkdir -p "$WS/src"
if [ ! -e "$WS/src/hapi_slam" ]; then
  ln -s "$REPO" "$WS/src/hapi_slam"
fi
# Keep rospack and catkin from crawling the workspace folder if it lives
# inside the checkout.
touch "$WS/CATKIN_IGNORE" "$WS/rospack_nosubdirs"

set +u
# shellcheck disable=SC1091
source /usr/share/catkin/setup.sh 2>/dev/null || true
set -u
cd "$WS"
catkin_make -j"$JOBS" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCMAKE_BUILD_TYPE=Release \
  -DCATKIN_ENABLE_TESTING=ON \
  ${HAPI_CMAKE_ARGS:-} ${HAPI_MAKE_TARGETS:-}
# Offline rosdep view where the tests and run scripts keep ROS_HOME (see
# rosdep_offline.sh for why `rosrun nodelet declared_nodelets` needs it).
ROS_HOME="${ROS_HOME:-$WS/ros_home}" bash "$REPO/scripts/rosdep_offline.sh"
echo "$WS"
