#!/usr/bin/env bash
# Two "hosts" on one machine: the robot (front end, robot.launch, plays the
# globe bag as its cameras) and the server (roscore + back end, server.launch,
# headless) in two network namespaces joined by a veth link that is made
# lossy and slow (netem delay 20 ms + 5 % loss each way; if the kernel has no
# netem, 5 % loss with iptables' statistic match and NO delay, said loudly).
#
#   scripts/reliability/two_hosts.sh [BAG]        (root; after setup.sh)
#
# Phases (each watched from the server side by ros_probe.py):
#   1. play the bag once: the system runs across the lossy link (odometry
#      published, losses/drops reported from both sides' diagnostics);
#   2. play it again (stamps jump backwards: the back end must reset) and
#      kill + restart the front end 10 s in: odometry must come back without
#      touching the back end (same process);
#   3. play it in a loop (rosbag play -l) for 1.6 bag lengths: the loop's
#      backwards jump must reset the filter cleanly (first pose of the new
#      timeline at the origin, no NaN, odometry continues).
# Results: $HAPI_RUN_DIR (default <ws>/reliability/two_hosts): phase*.json,
# logs, report.txt. Exit 0 when every check passes.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true
DELAY="${HAPI_NET_DELAY:-20ms}"
LOSS="${HAPI_NET_LOSS:-5}"            # percent, each direction
OUT="${HAPI_RUN_DIR:-$WS/reliability/two_hosts}"
NS_R=hapi_robot NS_S=hapi_server
IF_R=hapi-veth-r IF_S=hapi-veth-s
IP_R=10.77.0.1 IP_S=10.77.0.2
MASTER="http://$IP_S:11311"

die() { echo "[two_hosts] ERROR: $*" >&2; exit 1; }
log() { echo "[two_hosts] $*"; }
[ "$(id -u)" -eq 0 ] || die "needs root (ip netns, tc, iptables)"
command -v ip >/dev/null || die "iproute2 missing (scripts/debian-packages.sh lists it)"
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash" || die "no workspace at $WS (run scripts/setup.sh)"
set -u
BAG="${1:-${HAPI_DATA:-$REPO/.data}/globe.bag}"
mkdir -p "$OUT"
rm -f "$OUT"/phase*.json "$OUT"/*.log "$OUT"/report.txt
if [ ! -s "$BAG" ]; then
  BAG="$OUT/globe.bag"
  [ -s "$BAG" ] || rosrun hapi_sim make_globe_bag --output "$BAG" --seed 1 --duration 25 --rate 10 --imu 1
fi
BAG_LEN="$(python3 -c "import rosbag,sys; b=rosbag.Bag(sys.argv[1]); print(int(b.get_end_time()-b.get_start_time()+0.999))" "$BAG")"
log "bag $BAG ($BAG_LEN s), results in $OUT"

PIDS=()
cleanup() {
  set +e
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
    kill -INT "${PIDS[$i]}" 2>/dev/null
  done
  sleep 3
  for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null; done
  ip netns del "$NS_R" 2>/dev/null
  ip netns del "$NS_S" 2>/dev/null
}
trap cleanup EXIT

# ------------------------------------------------------------- the link
ip netns del "$NS_R" 2>/dev/null || true
ip netns del "$NS_S" 2>/dev/null || true
ip netns add "$NS_R"
ip netns add "$NS_S"
ip link add "$IF_R" type veth peer name "$IF_S"
ip link set "$IF_R" netns "$NS_R"
ip link set "$IF_S" netns "$NS_S"
ip -n "$NS_R" addr add "$IP_R/24" dev "$IF_R"
ip -n "$NS_S" addr add "$IP_S/24" dev "$IF_S"
for ns in "$NS_R" "$NS_S"; do ip -n "$ns" link set lo up; done
ip -n "$NS_R" link set "$IF_R" up
ip -n "$NS_S" link set "$IF_S" up
IMPAIR=""
if ip netns exec "$NS_R" tc qdisc add dev "$IF_R" root netem delay "$DELAY" loss "$LOSS%" 2>/dev/null &&
   ip netns exec "$NS_S" tc qdisc add dev "$IF_S" root netem delay "$DELAY" loss "$LOSS%" 2>/dev/null; then
  IMPAIR="netem delay $DELAY loss $LOSS% each way"
elif command -v iptables >/dev/null; then
  p="$(python3 -c "print($LOSS / 100.0)")"
  ip netns exec "$NS_R" iptables -A INPUT -i "$IF_R" -m statistic --mode random --probability "$p" -j DROP
  ip netns exec "$NS_S" iptables -A INPUT -i "$IF_S" -m statistic --mode random --probability "$p" -j DROP
  IMPAIR="iptables random loss $LOSS% each way; NO delay (this kernel has no netem qdisc)"
else
  IMPAIR="NONE (no netem qdisc and no iptables)"
fi
log "link $IP_R <-> $IP_S: $IMPAIR"
if command -v ping >/dev/null; then
  ip netns exec "$NS_R" ping -c 20 -i 0.05 -q "$IP_S" | tail -2 | sed "s/^/[two_hosts] ping: /" || true
fi

in_ns() {  # in_ns NS IP cmd...: a process of one host, talking ROS over the link
  local ns="$1" ipaddr="$2"
  shift 2
  ip netns exec "$ns" env ROS_MASTER_URI="$MASTER" ROS_IP="$ipaddr" ROS_HOSTNAME="$ipaddr" \
    ROS_HOME="$OUT/ros_home_$ns" "$@"
}
robot() { in_ns "$NS_R" "$IP_R" "$@"; }
server() { in_ns "$NS_S" "$IP_S" "$@"; }

wait_for() {  # wait_for SECONDS DESCRIPTION cmd...
  local t="$1" what="$2"
  shift 2
  for ((i = 0; i < t * 2; i++)); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.5
  done
  die "timed out after $t s waiting for $what"
}

# ------------------------------------------------------------- start
server roscore -p 11311 >"$OUT/roscore.log" 2>&1 &
PIDS+=($!)
wait_for 30 "roscore on the server" server rosparam get /rosdistro
server roslaunch hapi_slam server.launch landmarks_topic:=/stereo_frontend/landmarks rviz:=false \
  >"$OUT/server.log" 2>&1 &
SERVER_PID=$!
PIDS+=("$SERVER_PID")
start_robot() {
  robot roslaunch hapi_slam robot.launch >>"$OUT/robot.log" 2>&1 &
  ROBOT_PID=$!
  PIDS+=("$ROBOT_PID")
}
start_robot
has_node() { server rosnode list | grep -qx "$1"; }
wait_for 60 "the back end (/eskf)" has_node /eskf
wait_for 60 "the front end (/stereo_frontend), seen from the server" has_node /stereo_frontend
sleep 2

probe() {  # probe SECONDS NAME (background; PROBE_PID)
  PROBE_START=$(date +%s.%N)
  server python3 "$REPO/scripts/reliability/ros_probe.py" --duration "$1" --out "$OUT/$2.json" >"$OUT/$2.log" 2>&1 &
  PROBE_PID=$!
}
play() { robot rosbag play -q "$@" "$BAG" >>"$OUT/rosbag.log" 2>&1; }

# Phase 1: one pass across the lossy link.
log "phase 1: play the bag once"
probe $((BAG_LEN + 8)) phase1
sleep 1
play
wait "$PROBE_PID" || true

# Phase 2: replay (time jump) and restart the front end 10 s in.
log "phase 2: replay + front end restart"
probe $((BAG_LEN + 10)) phase2
sleep 1
play &
PLAY_PID=$!
sleep 10
kill -INT "$ROBOT_PID"
wait "$ROBOT_PID" 2>/dev/null || true
log "front end stopped; restarting it"
start_robot
wait_for 60 "the restarted front end" has_node /stereo_frontend
RESTART_WALL=$(python3 -c "import time; print(time.time() - $PROBE_START)")
log "front end back after $RESTART_WALL s of phase 2"
wait "$PLAY_PID" || true
wait "$PROBE_PID" || true
kill -0 "$SERVER_PID" 2>/dev/null || die "the back end died during phase 2"

# Phase 3: loop the bag (backwards jump at the loop point).
LOOP_LEN=$((BAG_LEN * 16 / 10))
log "phase 3: rosbag play -l for $LOOP_LEN s"
probe $((LOOP_LEN + 6)) phase3
sleep 1
play -l &
PLAY_PID=$!
sleep "$LOOP_LEN"
kill -INT "$PLAY_PID" 2>/dev/null || true
wait "$PLAY_PID" 2>/dev/null || true
wait "$PROBE_PID" || true
kill -0 "$SERVER_PID" 2>/dev/null || die "the back end died during phase 3"

# ------------------------------------------------------------- verdict
python3 - "$OUT" "$BAG_LEN" "$RESTART_WALL" "$IMPAIR" <<'EOF' | tee "$OUT/report.txt"
import json, sys
out, bag_len, restart_wall, impair = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
ph = [json.load(open("%s/phase%d.json" % (out, i))) for i in (1, 2, 3)]
ok = True
def check(cond, text):
    global ok
    ok &= bool(cond)
    print("  [%s] %s" % ("PASS" if cond else "FAIL", text))
def status(p, needle):
    for name, st in p["diagnostics"].items():
        if needle in name:
            return st["values"]
    return {}
def num(d, k):
    try:
        return float(d.get(k, "nan"))
    except ValueError:
        return float("nan")
print("two_hosts: link = %s" % impair)
for i, p in enumerate(ph, 1):
    be, fe = status(p, "eskf"), status(p, "frontend")
    print("phase %d: %d odometry (%.1f Hz), max gap %.2f s, max step %.3f m, stamp jumps %d" % (
        i, p["odom_count"], p.get("odom_rate_hz", 0), p.get("max_gap_s", 0), p.get("max_step_m", 0),
        len(p.get("stamp_jumps", []))))
    print("   back end: received %s accepted %s processed %s dropped %s rejected %s time_jumps %s resets %s" % tuple(
        be.get(k, "?") for k in ("frames_received", "frames_accepted", "frames_processed", "frames_dropped",
                                 "rejected_total", "time_jumps", "resets")))
    print("   front end: processed %s rejected %s dropped %s" % tuple(
        fe.get(k, "?") for k in ("frames processed", "rejected total", "dropped total")))
frames = bag_len * 10
p1, p2, p3 = ph
check(p1["odom_count"] >= 0.3 * frames, "phase 1: odometry for >= 30 %% of the %d frames across the link" % frames)
check(bool(status(p1, "eskf")) and bool(status(p1, "frontend")), "phase 1: diagnostics of both hosts seen on the server")
be1, be2, be3 = status(p1, "eskf"), status(p2, "eskf"), status(p3, "eskf")
check(num(be2, "time_jumps") >= num(be1, "time_jumps") + 1, "phase 2: replay detected as a time jump (filter reset)")
after = [o for o in p2["odom"] if o[0] > restart_wall + 5]
check(len(after) >= 20, "phase 2: odometry resumed after the front end restart at %.1f s (%d messages from 5 s later)" % (restart_wall, len(after)))
check(num(be3, "time_jumps") >= num(be2, "time_jumps") + 1, "phase 3: the loop point reset the filter")
j3 = p3.get("stamp_jumps", [])
check(len(j3) >= 1 and all(j["first_position_norm"] < 0.05 for j in j3),
      "phase 3: first pose after each loop at the origin (%s)" % ", ".join("%.3f m" % j["first_position_norm"] for j in j3))
tail = [o for o in p3["odom"] if j3 and o[0] > j3[-1]["wall"] + 2]
check(len(tail) >= 10, "phase 3: odometry continues after the loop (%d messages)" % len(tail))
check(num(be3, "filter_errors") == 0, "no filter errors (%s)" % be3.get("last_filter_error", ""))
print("VERDICT: %s" % ("PASS" if ok else "FAIL"))
sys.exit(0 if ok else 1)
EOF
