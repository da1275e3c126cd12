#!/usr/bin/env bash
# Builds everything (scripts/setup.sh) and runs every test: the ROS-free
# gtests of each package, the system gtests and the rostests, through ctest in
# the catkin build folder. GPU tests skip cleanly on machines without a GPU.
# Ends with ctest's summary line; exit status is ctest's.
#
#   scripts/test.sh                 # everything (.ci/run)
#   scripts/test.sh --quick         # only the tests labelled unit and system:
#                                   # no sanitizer build, fuzzing, two hosts, soak
#   scripts/test.sh [--quick] ARGS  # further ARGS go to ctest (e.g. -R NAME)
# Every ctest entry has one label: unit, system, reliability or sanitizer
# (cmake/HapiCommon.cmake); `ctest -L LABEL` in <ws>/build runs one kind.
set -euo pipefail
LABEL_ARGS=()
if [ "${1:-}" = "--quick" ]; then
  LABEL_ARGS=(-L "^(unit|system)$")
  shift
fi
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"

HAPI_WS="$WS" bash "$REPO/scripts/setup.sh"

cd "$WS"
set +u
# shellcheck disable=SC1091
source devel/setup.bash
set -u
# Test executables are EXCLUDE_FROM_ALL in catkin: build them explicitly.
catkin_make -j"${HAPI_JOBS:-$(nproc)}" tests
# Each ctest entry runs under the devel-space environment (catkin's env.sh);
# rostests start their own roscore on a free port. With -j only the sanitizer
# tests (fuzz runs, sanitized gtests) run beside each other; every other test
# is RUN_SERIAL (cmake/HapiCommon.cmake hapi_set_test_label).
export ROS_HOME="${ROS_HOME:-$WS/ros_home}"
mkdir -p "$ROS_HOME"
cd "$WS/build"
ctest -j"${HAPI_JOBS:-$(nproc)}" --output-on-failure --timeout "${HAPI_TEST_TIMEOUT:-900}" ${LABEL_ARGS[@]+"${LABEL_ARGS[@]}"} "$@"
