#!/usr/bin/env bash
# Builds the whole catkin workspace with a sanitizer, in its own workspace
# folder, and runs every gtest and rostest under it (docs/RELIABILITY.md,
# "Sanitizers").
#
#   tools/sanitize.sh asan [ctest args]   # AddressSanitizer + UndefinedBehaviorSanitizer (+ LeakSanitizer)
#   tools/sanitize.sh tsan [ctest args]   # ThreadSanitizer
#
# HAPI_SANITIZE_TARGETS="targets" builds only those make targets (and what
# they need) instead of the whole workspace and its tests, for a reduced run
# with `-R <regex>` as ctest args, e.g. the back end's nodelet and rostests:
#   HAPI_SANITIZE_TARGETS="hapi_eskf_nodelet test_eskf_nodelet test_eskf_nodelet_imu_base
#     test_eskf_nodelet_concurrency" tools/sanitize.sh tsan -R "eskf_nodelet"
#
# Workspace: $HAPI_WS or <repo>/.ws-<mode>. CUDA is off (no sanitizer sees
# device code, and no GPU is needed). Any report aborts the process that
# made it, so a report fails its test; the reports are in ctest's output and
# in the ROS logs under <ws>/ros_home/log.
#
# Processes that are not ours (the nodelet manager, python's rosmaster,
# roslaunch and the test nodes) load our instrumented libraries, so the
# sanitizer runtime is preloaded into every process of the run; reports that
# originate in third-party code only are suppressed by the files in
# test/reliability/sanitizers/, each entry with its reason.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MODE="${1:-}"
[ $# -gt 0 ] && shift
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
SUPP="$REPO/test/reliability/sanitizers"

case "$MODE" in
  asan)
    FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
    RUNTIME="$(gcc -print-file-name=libasan.so)"
    export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=0"
    export LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp"
    ;;
  tsan)
    FLAGS="-fsanitize=thread"
    RUNTIME="$(gcc -print-file-name=libtsan.so)"
    # ignore_noninstrumented_modules: interceptors (locks, malloc/free,
    # memcpy, ...) called from uninstrumented libraries (roscpp, log4cxx,
    # nodeletlib, boost) are not checked: TSan sees none of those libraries'
    # own synchronisation, and without it reports their internals (lock
    # orders in log4cxx, roscpp's connection teardown).
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1:suppressions=$SUPP/tsan.supp"
    # With libtsan preloaded, Debian's sh and bash crash at start (SIGSEGV
    # before main; python and the nodelet manager do not), and ctest runs
    # every test through catkin's env.sh. So TSan is not preloaded
    # everywhere: our test executables link it, and every nodelet manager of
    # the launch and test files starts with it (launch-prefix from
    # HAPI_MANAGER_PREFIX; launch/*.launch: the manager_prefix argument).
    export HAPI_MANAGER_PREFIX="env LD_PRELOAD=$RUNTIME"
    # Eigen's products run on libgomp's threads where OpenMP is on; libgomp
    # is not instrumented, so TSan cannot see its barriers and reports the
    # product's result read after the parallel region as a race. One OpenMP
    # thread keeps every product on the calling thread: the threads left are
    # the nodelets' own and roscpp's.
    export OMP_NUM_THREADS=1
    ;;
  *)
    echo "usage: tools/sanitize.sh asan|tsan [ctest args]" >&2
    exit 2
    ;;
esac
# The instrumented pipeline runs a few times slower than the camera (TSan:
# the front end ~2.3 frames/s), so a bag played at its speed would test
# dropped frames instead of the code. The system rostests play their bags at
# this fraction of their speed (frontend_globe.test, test/system/*.test);
# their checks are in bag time or scale with it. two_hosts.sh keeps its
# wall-clock phases and does not read it. 0.05: under TSan the inertial
# rostest needs it (the filter's creation stalls the worker for seconds).
export HAPI_TEST_PLAY_RATE="${HAPI_TEST_PLAY_RATE:-0.05}"
[ -f "$RUNTIME" ] || { echo "sanitize.sh: $RUNTIME not found (gcc's sanitizer runtime)" >&2; exit 1; }

WS="${HAPI_WS:-$REPO/.ws-$MODE}"
# CMake takes CXXFLAGS/LDFLAGS on the first configure of a build folder.
CXXFLAGS="$FLAGS -g" LDFLAGS="$FLAGS" HAPI_WS="$WS" HAPI_MAKE_TARGETS="${HAPI_SANITIZE_TARGETS:-}" \
  HAPI_CMAKE_ARGS="-DHAPI_WITH_CUDA=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo ${HAPI_CMAKE_ARGS:-}" \
  bash "$REPO/scripts/setup.sh"

cd "$WS"
set +u
# shellcheck disable=SC1091
source devel/setup.bash
set -u
[ -n "${HAPI_SANITIZE_TARGETS:-}" ] || catkin_make -j"${HAPI_JOBS:-$(nproc)}" tests
export ROS_HOME="$WS/ros_home"
mkdir -p "$ROS_HOME"
[ "$MODE" = tsan ] || export LD_PRELOAD="$RUNTIME"
cd "$WS/build"
ctest --output-on-failure --timeout "${HAPI_TEST_TIMEOUT:-1800}" "$@"
