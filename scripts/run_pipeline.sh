#!/usr/bin/env bash
# The main job, headless: replays a globe bag through the whole system
# (front end + back end nodelets, launch/replay.launch, simulated time) and
# prints what the run measured:
#   * ATE: RMSE of the estimated camera positions after a rigid alignment to
#     the ground truth, in metres and in % of the distance travelled;
#   * map error: RMS distance of the landmark map to the true surfaces (after
#     the same alignment), when the bag states its geometry;
#   * the further metrics of tools/eval/run_analysis.py (Sim(3) ATE, rotation
#     error, RPE over 1 s, NEES, velocity error) and PNG plots next to the
#     report (tools/eval/plots.py: trajectory.png, error_over_time.png, nees.png);
#   * per-stage timing of the front end and the back end, from /diagnostics;
#   * the 3D surface (hapi_surface, unless surface:=false): mesh.ply (the
#     SurfaceNodelet's ~save_surface at the end of the run) and mesh.png next
#     to the report, with its RMS / 95th percentile distance to the true
#     surface, completeness, the perfusion pattern's registration error (a
#     bag made with --imaging-content perfusion) and the keyframes fused
#     (tools/eval/surface_run.py). A scene's depth range and volume come from
#     dense_depth_config:= / surface_config:= (config/*_globe.yaml: the demo).
#
#   scripts/run_pipeline.sh BAG [ARG:=VALUE ...]
#                                        (after `source <ws>/devel/setup.bash`,
#                                         or with HAPI_WS pointing at the workspace)
#
# ARG:=VALUE pairs go to launch/replay.launch (e.g. motion_model:=gyro); an
# ARG it does not declare is refused. Without motion_model:= the back end uses
# the inertial model when the bag has IMU samples (/imu/data), else
# config/eskf.yaml's.
# HAPI_SUMMARY_ARGS are passed to tools/eval/pipeline_summary.py (e.g.
# "--map-error if-known" for a recording without known geometry).
#
# A private roscore on a free port (ROS_HOME in the workspace) so it never
# touches a master the user is running. Results land in $HAPI_RUN_DIR
# (default <ws>/run): report.yaml, diagnostics.bag, pipeline.log.
# A ground truth that stands still (moves less than 5 mm from its start) is
# scored by the drift of the estimate from its first pose instead of ATE %:
# at most 1 cm and 1 deg (tools/eval/run_analysis.py), with the NEES anchored
# at the first pose. The summary also states the bag's stereo rate and the
# frames the front end dropped.
# Exit status: 0 results present and within bounds (ATE <= 2 % of distance or
# the standstill drift bounds, map RMS <= 1 cm), 1 something is missing
# (printed; nothing is made up), 2 a metric is outside its bound.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
# A virtualenv or pyenv must not shadow Debian's Python; the Python packages
# of a sourced catkin workspace (its generated messages) stay.
CATKIN_PY="$(tr ':' '\n' <<<"${PYTHONPATH:-}" | grep -E '/(devel|install)[^:]*/lib/python3/dist-packages/?$' | paste -sd: - || true)"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true
[ -z "$CATKIN_PY" ] || export PYTHONPATH="$CATKIN_PY"

die() { echo "[pipeline] ERROR: $*" >&2; exit 1; }

[ $# -ge 1 ] || die "usage: $0 BAG [ARG:=VALUE ...]"
BAG="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
[ -s "$BAG" ] || die "bag '$1' does not exist or is empty"
shift
LAUNCH_ARGS=()
for a in "$@"; do
  [[ "$a" =~ ^([A-Za-z_][A-Za-z0-9_]*):=(.*)$ ]] || die "'$a' is not ARG:=VALUE"
  grep -qE "<arg[[:space:]]+name=\"${BASH_REMATCH[1]}\"" "$REPO/launch/replay.launch" \
    || die "launch/replay.launch declares no arg '${BASH_REMATCH[1]}'"
  LAUNCH_ARGS+=("$a")
done

if ! rospack find hapi_slam >/dev/null 2>&1; then
  [ -f "$WS/devel/setup.bash" ] || die "no built workspace at $WS (run scripts/setup.sh)"
  set +u
  # shellcheck disable=SC1091
  source "$WS/devel/setup.bash"
  set -u
fi

# Everything the run needs, checked up front so a missing piece is named
# instead of surfacing as a silent empty result.
missing=()
# Declared nodelets as pluginlib sees them (rospack, C++): the Python
# `rosrun nodelet declared_nodelets` lists nothing without an initialised rosdep.
declared="$(rospack plugins --attrib=plugin nodelet 2>/dev/null | while read -r _ xml; do
  [ -f "$xml" ] && sed -nE 's/.*<class[^>]* name="([^"]+)".*/\1/p' "$xml"; done || true)"
needed=(hapi_frontend/StereoFrontendNodelet hapi_eskf/EskfNodelet)
printf '%s\n' "${LAUNCH_ARGS[@]}" | grep -qx "dense_depth:=false" || needed+=(hapi_surface/DenseDepthNodelet)
printf '%s\n' "${LAUNCH_ARGS[@]}" | grep -qx "surface:=false" || needed+=(hapi_surface/SurfaceNodelet)
for n in "${needed[@]}"; do
  grep -qx "$n" <<<"$declared" || missing+=("nodelet $n (not declared/built)")
done
for f in launch/robot.launch launch/server.launch launch/all_in_one.launch launch/replay.launch \
         config/frontend.yaml config/eskf.yaml; do
  [ -f "$REPO/$f" ] || missing+=("$f")
done
if ((${#missing[@]})); then
  for m in "${missing[@]}"; do echo "[pipeline] MISSING: $m" >&2; done
  exit 1
fi

RUN_DIR="${HAPI_RUN_DIR:-$WS/run}"
mkdir -p "$RUN_DIR"
REPORT="$RUN_DIR/report.yaml"
DIAG="$RUN_DIR/diagnostics.bag"
LOG="$RUN_DIR/pipeline.log"
rm -f "$REPORT" "$DIAG" "$DIAG.active" "$RUN_DIR"/{trajectory,error_over_time,nees}.png \
  "$RUN_DIR"/{estimate,ground_truth}.tum "$RUN_DIR/estimate_covariance.txt" "$RUN_DIR"/mesh.{ply,png}
: >"$LOG"

export ROS_HOME="${ROS_HOME:-$WS/ros_home}"
mkdir -p "$ROS_HOME"
PORT="${HAPI_ROS_PORT:-$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}"
export ROS_MASTER_URI="http://localhost:$PORT"
export ROS_HOSTNAME=localhost
unset ROS_IP || true

# Length, IMU, and the recording's camera-IMU time offset when it states one
# (/ground_truth/calibration of the simulated recordings, Kalibr's convention).
# The stereo rate: the median rate of the left images (from the bag's index).
read -r BAG_SECONDS BAG_HAS_IMU BAG_TIME_OFFSET BAG_STEREO_HZ BAG_IMAGING_HZ < <(/usr/bin/python3 -c "
import rosbag, sys, yaml
b = rosbag.Bag(sys.argv[1])
topics = b.get_type_and_topic_info().topics
offset = ''
for _, m, _ in b.read_messages(topics=['/ground_truth/calibration']):
    offset = repr(float(yaml.safe_load(m.data).get('time_offset_s', 0.0)))
    break
left = topics.get('/stereo/left/image_raw')
hz = '%.3f' % left.frequency if left is not None and left.frequency else '-'
imaging = topics.get('/imaging/image_raw')
imaging_hz = '%.3f' % imaging.frequency if imaging is not None and imaging.frequency else '-'
print(int(b.get_end_time() - b.get_start_time()) + 1, int('/imu/data' in topics), offset or '-', hz, imaging_hz)" "$BAG")
given() { printf '%s\n' "${LAUNCH_ARGS[@]}" | grep -q "^$1:="; }
# The inertial filter when the bag has IMU samples, unless told otherwise.
if [ "$BAG_HAS_IMU" = 1 ] && ! given motion_model; then
  LAUNCH_ARGS+=("motion_model:=inertial")
fi
if [ "$BAG_TIME_OFFSET" != "-" ] && ! given imu_time_offset; then
  LAUNCH_ARGS+=("imu_time_offset:=$BAG_TIME_OFFSET")
fi
# The imaging camera of the surface motion: the bag's own (/imaging, make_sim_bag
# --imaging-rate) when it has one, else the left camera at the stereo rate.
if ! given imaging_image; then
  if [ "$BAG_IMAGING_HZ" != "-" ]; then
    LAUNCH_ARGS+=("imaging_image:=/imaging/image_raw" "imaging_info:=/imaging/camera_info"
                  "imaging_frame_rate:=$(printf '%.0f' "$BAG_IMAGING_HZ")")
  elif [ "$BAG_STEREO_HZ" != "-" ]; then
    LAUNCH_ARGS+=("imaging_frame_rate:=$(printf '%.0f' "$BAG_STEREO_HZ")")
  fi
fi
echo "[pipeline] launch arguments: ${LAUNCH_ARGS[*]:-(none: the motion model of config/eskf.yaml)}"
# The evaluator ends the launch once the odometry has been quiet for a few
# seconds after the bag; this is only a guard against a hung run.
LIMIT=$((BAG_SECONDS * 6 + 180))

ROSCORE_PID=""
cleanup() {
  if [ -n "$ROSCORE_PID" ] && kill -0 "$ROSCORE_PID" 2>/dev/null; then
    kill -INT "$ROSCORE_PID" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$ROSCORE_PID" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$ROSCORE_PID" 2>/dev/null || true
  fi
}
trap cleanup EXIT

echo "[pipeline] bag $BAG (${BAG_SECONDS} s), master $ROS_MASTER_URI, results in $RUN_DIR"
roscore -p "$PORT" >"$RUN_DIR/roscore.log" 2>&1 &
ROSCORE_PID=$!
master_up() { /usr/bin/python3 -c 'import rosgraph, sys; sys.exit(0 if rosgraph.is_master_online() else 1)'; }
for _ in $(seq 100); do
  master_up && break
  kill -0 "$ROSCORE_PID" 2>/dev/null || die "roscore exited (see $RUN_DIR/roscore.log)"
  sleep 0.2
done
master_up || die "roscore did not come up on port $PORT"

# roslaunch runs in the background and we `wait` for it, so that an INT or
# TERM sent to this script (Ctrl-C, a test harness stopping it) is handled at
# once: forwarded to roslaunch through `timeout`, which shuts the nodes down
# cleanly before the master goes. (A script started in the background ignores
# INT, so harnesses send TERM.)
LAUNCH_PID=""
stop_launch() {
  echo "[pipeline] interrupted: stopping the launch" >&2
  if [ -n "$LAUNCH_PID" ]; then
    kill -INT "$LAUNCH_PID" 2>/dev/null || true
    wait "$LAUNCH_PID" 2>/dev/null || true
  fi
  exit 130
}
trap stop_launch INT TERM
timeout --signal=INT --kill-after=30 "$LIMIT" \
  roslaunch --wait hapi_slam replay.launch bag:="$BAG" evaluate:=true eval_output:="$REPORT" \
    record_diagnostics:="$DIAG" rviz:=false output:=log ${HAPI_REPLAY_ARGS:-} "${LAUNCH_ARGS[@]}" \
    > >(trap "" INT; exec tee "$LOG") 2>&1 &
LAUNCH_PID=$!
# Watchdog: a node that dies (e.g. a nodelet rejecting its parameters at
# start-up) would leave the evaluator waiting for odometry until its wall
# limit; roslaunch reports it as "process has died", so stop at once instead.
died=""
while kill -0 "$LAUNCH_PID" 2>/dev/null; do
  if died="$(grep -aoE '\[[A-Za-z0-9_.-]+\] process has died' "$LOG" 2>/dev/null | head -n1)" && [ -n "$died" ]; then
    echo "[pipeline] ERROR: a node died during the run: $died (see $LOG and its node log)" >&2
    kill -INT "$LAUNCH_PID" 2>/dev/null || true
    break
  fi
  sleep 1
done
set +e
wait "$LAUNCH_PID"
rc=$?
set -e
LAUNCH_PID=""
[ -z "$died" ] || exit 1
trap - INT TERM
[ "$rc" -eq 124 ] && echo "[pipeline] ERROR: run exceeded ${LIMIT} s and was stopped" >&2
[ -s "$REPORT" ] || { echo "[pipeline] ERROR: the evaluator wrote no report (roslaunch exit $rc; log: $LOG)" >&2; exit 1; }
[ -f "$DIAG" ] || echo "[pipeline] WARNING: no diagnostics bag ($DIAG)" >&2

set +e
SUMMARY_ARGS=()
[ "$BAG_STEREO_HZ" = "-" ] || SUMMARY_ARGS+=(--stereo-rate-hz "$BAG_STEREO_HZ")
# shellcheck disable=SC2086  # HAPI_SUMMARY_ARGS is a list of options
/usr/bin/python3 "$REPO/tools/eval/pipeline_summary.py" "$REPORT" "$DIAG" "${SUMMARY_ARGS[@]}" ${HAPI_SUMMARY_ARGS:-}
src=$?
set -e
echo "[pipeline] report: $REPORT, diagnostics: $DIAG, log: $LOG, node logs: $ROS_HOME/log"
exit "$src"
