#!/usr/bin/env bash
# Soak test: the whole system (all_in_one.launch, one nodelet manager holding
# the front end and the back end) on the globe bag played in a loop at its
# recorded 10 Hz for HAPI_SOAK_S seconds (default 600), sampling the
# manager's resident memory every HAPI_SOAK_PERIOD seconds (default 10).
# Prints a table (time, RSS, odometry in the period) and a verdict: memory
# growth after the warm-up must be bounded (the filter's pool is fixed-size;
# anything that grows with time is a leak or an unbounded buffer).
#
#   test/reliability/soak.sh [BAG]        (after scripts/setup.sh)
#
# Full-pool soak (HAPI_SOAK_FULL_POOL=1): BAG is played once, not looped
# (a long non-repeating bag: make_globe_bag --orbit spiral), the soak lasts
# until it ends (or HAPI_SOAK_S), and the verdict also requires the
# filter's map to stay at the pool size after the warm-up and reports the
# per-frame filter time's slope and the drops (soak_verdict.py).
# HAPI_SOAK_MAX_LANDMARKS=N runs the back end with a pool of N instead of
# config/eskf.yaml's (a copy of it with max_landmarks changed), so that a
# shorter bag fills it.
#
# Private roscore on a free port; results in $HAPI_RUN_DIR (default
# <ws>/reliability/soak): samples.csv, probe.json, logs, report.txt.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true
DURATION="${HAPI_SOAK_S:-600}"
PERIOD="${HAPI_SOAK_PERIOD:-10}"
WARMUP="${HAPI_SOAK_WARMUP_S:-120}"       # growth is judged after this
MAX_GROWTH_MB="${HAPI_SOAK_MAX_GROWTH_MB:-20}"
OUT="${HAPI_RUN_DIR:-$WS/reliability/soak}"
FULL_POOL="${HAPI_SOAK_FULL_POOL:-0}"
die() { echo "[soak] ERROR: $*" >&2; exit 1; }
log() { echo "[soak] $*"; }

set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash" || die "no workspace at $WS (run scripts/setup.sh)"
set -u
BAG="${1:-${HAPI_DATA:-$REPO/.data}/globe.bag}"
mkdir -p "$OUT"
rm -f "$OUT"/*.log "$OUT"/samples.csv "$OUT"/report.txt "$OUT"/probe.json
if [ ! -s "$BAG" ]; then
  BAG="$OUT/globe.bag"
  [ -s "$BAG" ] || rosrun hapi_sim make_globe_bag --output "$BAG" --seed 1 --duration 25 --rate 10 --imu 1
fi
PORT="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://127.0.0.1:$PORT" ROS_IP=127.0.0.1 ROS_HOME="$OUT/ros_home"
unset ROS_HOSTNAME || true

PIDS=()
cleanup() {
  set +e
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do kill -INT "${PIDS[$i]}" 2>/dev/null; done
  sleep 3
  for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null; done
}
trap cleanup EXIT

roscore -p "$PORT" >"$OUT/roscore.log" 2>&1 &
PIDS+=($!)
for _ in $(seq 60); do rosparam get /rosdistro >/dev/null 2>&1 && break; sleep 0.5; done
rosparam get /rosdistro >/dev/null 2>&1 || die "roscore did not start"
ESKF_ARGS=()
if [ -n "${HAPI_SOAK_MAX_LANDMARKS:-}" ]; then
  sed "s/^max_landmarks:.*/max_landmarks: $HAPI_SOAK_MAX_LANDMARKS/" "$REPO/config/eskf.yaml" >"$OUT/eskf.yaml"
  ESKF_ARGS=(eskf_config:="$OUT/eskf.yaml")
fi
roslaunch hapi_slam all_in_one.launch rviz:=false "${ESKF_ARGS[@]}" >"$OUT/system.log" 2>&1 &
LAUNCH_PID=$!
PIDS+=("$LAUNCH_PID")
# Both nodelets registered (one rosnode call per try: a loaded machine can
# make a single master query fail, so only a result counts, never an error).
UP=0
for _ in $(seq 120); do
  nodes="$(rosnode list 2>/dev/null || true)"
  if grep -qx /eskf <<<"$nodes" && grep -qx /stereo_frontend <<<"$nodes"; then UP=1; break; fi
  sleep 0.5
done
[ "$UP" = 1 ] || die "front end / back end did not start within 60 s (see $OUT/system.log)"
# The manager's process: the child of our roslaunch started as __name:=hapi_manager.
MGR_PID=""
for p in $(pgrep -P "$LAUNCH_PID"); do
  if grep -q "__name:=hapi_manager" <<<"$(tr '\0' ' ' <"/proc/$p/cmdline")"; then MGR_PID="$p"; fi
done
[ -n "$MGR_PID" ] || die "nodelet manager process not found"
log "manager pid $MGR_PID; looping $BAG for $DURATION s, sampling every $PERIOD s"

python3 "$REPO/test/reliability/ros_probe.py" --duration "$((DURATION + 5))" --out "$OUT/probe.json" \
  >"$OUT/probe.log" 2>&1 &
PROBE_PID=$!
PIDS+=("$PROBE_PID")
LOOP=(-l)
[ "$FULL_POOL" = 1 ] && LOOP=()
rosbag play -q "${LOOP[@]}" "$BAG" >"$OUT/rosbag.log" 2>&1 &
PLAY_PID=$!
PIDS+=("$PLAY_PID")

echo "t_s,rss_mib,threads" >"$OUT/samples.csv"
START=$(date +%s)
while :; do
  now=$(($(date +%s) - START))
  kill -0 "$MGR_PID" 2>/dev/null || die "the nodelet manager died after $now s (see $OUT/system.log)"
  rss_kb=$(awk '/^VmRSS/ {print $2}' "/proc/$MGR_PID/status")
  thr=$(awk '/^Threads/ {print $2}' "/proc/$MGR_PID/status")
  echo "$now,$(python3 -c "print('%.1f' % ($rss_kb / 1024.0))"),$thr" >>"$OUT/samples.csv"
  [ "$now" -ge "$DURATION" ] && break
  [ "$FULL_POOL" = 1 ] && ! kill -0 "$PLAY_PID" 2>/dev/null && break   # the bag ended
  sleep "$PERIOD"
done
kill -INT "$PLAY_PID" 2>/dev/null || true
sleep 3   # the last frames and diagnostics reach the probe
kill -TERM "$PROBE_PID" 2>/dev/null || true
wait "$PROBE_PID" || true
MAX_LANDMARKS="$(rosparam get /eskf/max_landmarks 2>/dev/null || echo 0)"

python3 "$REPO/test/reliability/soak_verdict.py" --out "$OUT" --warmup "$WARMUP" --max-growth "$MAX_GROWTH_MB" \
  --full-pool "$FULL_POOL" --max-landmarks "$MAX_LANDMARKS" | tee "$OUT/report.txt"
exit "${PIPESTATUS[0]}"
