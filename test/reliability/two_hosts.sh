#!/usr/bin/env bash
# Two "hosts" on one machine: the robot (front end, robot.launch, plays the
# globe bag as its cameras) and the server (roscore + back end, server.launch,
# headless; the dense depth and the surface off: this tests the link) in two
# network namespaces joined by a slow, lossy link: 20 ms
# delay + 5 % packet loss in each direction. The link is a veth pair with
# `tc qdisc netem` where the kernel has sch_netem; otherwise (e.g. small VM
# kernels: "Specified qdisc kind is unknown") delay_line.py makes the same
# link in user space over two TUN devices; without /dev/net/tun either, a
# veth with iptables random loss and NO delay (said loudly in the report).
#
#   test/reliability/two_hosts.sh [BAG]        (root; after setup.sh)
#
# Phases (each watched from the server side by ros_probe.py):
#   1. play the bag once: the system runs across the lossy link (odometry
#      published; link losses and message drops reported);
#   2. play it again (stamps jump backwards: the back end must reset) and
#      kill + restart the front end HAPI_RESTART_AT s in (default 10), bag
#      looping for HAPI_AFTER_RESTART s more (default 25): odometry must come
#      back without touching the back end (same process);
#   3. play it in a loop for 1.6 bag lengths: the loop's backwards jump must
#      reset the filter cleanly (first pose of the new timeline at the
#      origin, odometry continues, no filter error).
# HAPI_SCENARIO=outage runs one other phase instead: the bag (longer than
# the outage) plays once and HAPI_OUTAGE_AT s (default 6) after the first
# odometry the link goes down for HAPI_OUTAGE_LEN s (default 30) and comes
# back; outage_verdict.py
# judges it (odometry resumes, the back end relocalises, no backlog of old
# frames, both managers' memory flat, the back end never restarted).
# Results in $HAPI_RUN_DIR (default <ws>/reliability/two_hosts): phase*.json,
# link.json, logs, report.txt (two_hosts_verdict.py). Exit 0 when every
# check passes, 77 (skip) when this machine cannot make network namespaces
# (not root / no CAP_NET_ADMIN / no netns), anything else on failure.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true
DELAY_MS="${HAPI_NET_DELAY_MS:-20}"
LOSS="${HAPI_NET_LOSS:-5}"            # percent, each direction
LINK="${HAPI_LINK:-auto}"             # auto | netem | tun | iptables (force one kind of link)
RESTART_AT="${HAPI_RESTART_AT:-10}"   # [s] into phase 2
AFTER_RESTART="${HAPI_AFTER_RESTART:-25}"  # [s] phase 2 goes on after the restart command
SCENARIO="${HAPI_SCENARIO:-phases}"    # phases | outage
OUTAGE_AT="${HAPI_OUTAGE_AT:-6}"       # [s] after the first odometry (outage scenario)
OUTAGE_LEN="${HAPI_OUTAGE_LEN:-30}"    # [s] the link is down
OUT="${HAPI_RUN_DIR:-$WS/reliability/two_hosts}"
SFX="$$"                              # two concurrent runs never share a namespace
NS_R="hapi_robot_$SFX" NS_S="hapi_server_$SFX"
IF_R="hapi-r$SFX" IF_S="hapi-s$SFX"
IP_R=10.77.0.1 IP_S=10.77.0.2
MASTER="http://$IP_S:11311"

die() { echo "[two_hosts] ERROR: $*" >&2; exit 1; }
skip() { echo "[two_hosts] SKIP: $*" >&2; exit 77; }
log() { echo "[two_hosts] $*"; }
case "$LINK" in auto | netem | tun | iptables) ;; *) die "HAPI_LINK must be auto, netem, tun or iptables" ;; esac
[ "$(id -u)" -eq 0 ] || skip "needs root (ip netns, tc/TUN, iptables)"
command -v ip >/dev/null || skip "iproute2 missing (scripts/debian-packages.sh lists it)"
ip netns add "$NS_R" 2>/dev/null || skip "cannot create a network namespace (no CAP_NET_ADMIN or no netns support)"
ip netns del "$NS_R"
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash" || die "no workspace at $WS (run scripts/setup.sh)"
set -u
BAG="${1:-${HAPI_DATA:-$REPO/.data}/globe.bag}"
mkdir -p "$OUT"
rm -f "$OUT"/outage.json "$OUT"/phase*.json "$OUT"/*.log "$OUT"/report.txt "$OUT"/link.json "$OUT"/link.ready
if [ ! -s "$BAG" ]; then
  BAG="$OUT/globe.bag"
  [ -s "$BAG" ] || rosrun hapi_sim make_globe_bag --output "$BAG" --seed 1 --duration 25 --rate 10 --imu 1
fi
BAG_LEN="$(python3 -c "import rosbag,sys; b=rosbag.Bag(sys.argv[1]); print(int(b.get_end_time()-b.get_start_time()+0.999))" "$BAG")"
log "bag $BAG ($BAG_LEN s), results in $OUT"
[ "$SCENARIO" = outage ] || [ "$RESTART_AT" -lt "$BAG_LEN" ] || die "HAPI_RESTART_AT=$RESTART_AT s must be shorter than the bag ($BAG_LEN s)"
PLAYER=/usr/lib/rosbag/play   # the player itself (not the Python wrapper): $! is the process to stop
[ -x "$PLAYER" ] || PLAYER="$(command -v rosbag) play"

PIDS=()
DELAY_LINE_PID=""
stop_pid() {  # SIGINT, up to 15 s to shut down (roslaunch stops its nodes), then SIGKILL
  kill -INT "$1" 2>/dev/null || return 0
  for _ in $(seq 30); do kill -0 "$1" 2>/dev/null || return 0; sleep 0.5; done
  kill -KILL "$1" 2>/dev/null
}
cleanup() {
  set +e
  # Newest first, the link and the master last: nodes shut down cleanly
  # only while they can still reach the master.
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do stop_pid "${PIDS[$i]}"; done
  # Whatever still runs inside our namespaces (e.g. a node orphaned by a
  # killed roslaunch) is ours: `ip netns pids` names exactly those.
  for ns in "$NS_R" "$NS_S"; do
    for p in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$p" 2>/dev/null; done
  done
  [ -n "$DELAY_LINE_PID" ] && kill -TERM "$DELAY_LINE_PID" 2>/dev/null && wait "$DELAY_LINE_PID" 2>/dev/null
  ip netns del "$NS_R" 2>/dev/null
  ip netns del "$NS_S" 2>/dev/null
}
trap cleanup EXIT

# ------------------------------------------------------------- the link
ip netns add "$NS_R"
ip netns add "$NS_S"
for ns in "$NS_R" "$NS_S"; do ip -n "$ns" link set lo up; done
veth_up() {
  ip link add "$IF_R" type veth peer name "$IF_S"
  ip link set "$IF_R" netns "$NS_R"
  ip link set "$IF_S" netns "$NS_S"
  ip -n "$NS_R" addr add "$IP_R/24" dev "$IF_R"
  ip -n "$NS_S" addr add "$IP_S/24" dev "$IF_S"
  ip -n "$NS_R" link set "$IF_R" up
  ip -n "$NS_S" link set "$IF_S" up
}
veth_up
if [[ "$LINK" == auto || "$LINK" == netem ]] &&
   ip -n "$NS_R" qdisc add dev "$IF_R" root netem delay "${DELAY_MS}ms" loss "$LOSS%" 2>/dev/null &&
   ip -n "$NS_S" qdisc add dev "$IF_S" root netem delay "${DELAY_MS}ms" loss "$LOSS%" 2>/dev/null; then
  LINK_KIND=netem
  IMPAIR="veth + tc netem delay ${DELAY_MS} ms, loss $LOSS % each way"
elif [ "$LINK" = netem ]; then
  die "HAPI_LINK=netem but this kernel has no netem qdisc"
elif [[ "$LINK" == auto || "$LINK" == tun ]] && [ -c /dev/net/tun ]; then
  ip -n "$NS_R" link del "$IF_R"    # (takes its peer along)
  LINK_KIND=tun
  IMPAIR="TUN pair + delay_line.py (user-space netem; this kernel has no sch_netem): delay ${DELAY_MS} ms, loss $LOSS % each way"
  python3 "$REPO/test/reliability/delay_line.py" --ns-a "$NS_R" --ip-a "$IP_R" --ns-b "$NS_S" --ip-b "$IP_S" \
    --dev-a "$IF_R" --dev-b "$IF_S" --delay-ms "$DELAY_MS" --loss "$LOSS" --stats "$OUT/link.json" \
    --ready "$OUT/link.ready" >"$OUT/delay_line.log" 2>&1 &
  DELAY_LINE_PID=$!
  for _ in $(seq 50); do [ -e "$OUT/link.ready" ] && break; sleep 0.1; done
  [ -e "$OUT/link.ready" ] || die "delay_line.py did not bring the link up (see $OUT/delay_line.log)"
elif [ "$LINK" = tun ]; then
  die "HAPI_LINK=tun but there is no /dev/net/tun"
else
  LINK_KIND=iptables
  p="$(python3 -c "print($LOSS / 100.0)")"
  ip netns exec "$NS_R" iptables -A INPUT -i "$IF_R" -m statistic --mode random --probability "$p" -j DROP
  ip netns exec "$NS_S" iptables -A INPUT -i "$IF_S" -m statistic --mode random --probability "$p" -j DROP
  why="no netem qdisc, no /dev/net/tun"
  [ "$LINK" = iptables ] && why="HAPI_LINK=iptables"
  IMPAIR="veth + iptables random loss $LOSS % each way; NO delay ($why)"
fi
log "link $IP_R <-> $IP_S: $IMPAIR"
if command -v ping >/dev/null; then
  ip netns exec "$NS_R" ping -c 100 -i 0.02 -q "$IP_S" | tail -2 >"$OUT/ping.txt" || true
  sed "s/^/[two_hosts] ping: /" "$OUT/ping.txt"
fi

# A process of one host, talking ROS over the link. Background starts run
# `ip netns exec ... &` as a simple command so that $! is the process itself.
ENV_R=(env ROS_MASTER_URI="$MASTER" ROS_IP="$IP_R" ROS_HOSTNAME="$IP_R" ROS_HOME="$OUT/ros_home_robot")
ENV_S=(env ROS_MASTER_URI="$MASTER" ROS_IP="$IP_S" ROS_HOSTNAME="$IP_S" ROS_HOME="$OUT/ros_home_server")
server() { ip netns exec "$NS_S" "${ENV_S[@]}" "$@"; }
wait_for() {  # wait_for SECONDS DESCRIPTION cmd...
  local t="$1" what="$2"
  shift 2
  for ((i = 0; i < t * 2; i++)); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.5
  done
  die "timed out after $t s waiting for $what"
}
now_rel() { python3 -c "import time; print('%.2f' % (time.time() - $1))"; }

# ------------------------------------------------------------- start
ip netns exec "$NS_S" "${ENV_S[@]}" roscore -p 11311 >"$OUT/roscore.log" 2>&1 &
PIDS+=($!)
wait_for 60 "roscore on the server" server rosparam get /rosdistro
ip netns exec "$NS_S" "${ENV_S[@]}" roslaunch hapi_slam server.launch rviz:=false surface:=false >"$OUT/server.log" 2>&1 &
SERVER_PID=$!
PIDS+=("$SERVER_PID")
start_robot() {
  ip netns exec "$NS_R" "${ENV_R[@]}" roslaunch hapi_slam robot.launch dense_depth:=false >>"$OUT/robot.log" 2>&1 &
  ROBOT_PID=$!
  PIDS+=("$ROBOT_PID")
}
start_robot
has_node() { grep -qx "$1" <<<"$(server rosnode list 2>/dev/null)"; }
wait_for 90 "the back end (/eskf)" has_node /eskf
wait_for 90 "the front end (/stereo_frontend), seen from the server" has_node /stereo_frontend
# The back end's TCPROS connection to the front end is made asynchronously
# over the slow link (master -> publisherUpdate -> requestTopic -> connect);
# frames published before it exists are never counted as sent.
# (Nodelets subscribe through their manager's node: /hapi_server_manager;
# rosnode info lists only connected links under "Connections".)
be_connected() {
  grep -q "topic: /stereo_frontend/landmarks" <<<"$(server rosnode info /hapi_server_manager 2>/dev/null | sed -n '/^Connections/,$p')"
}
wait_for 90 "the back end's connection to the front end" be_connected
# The back end's manager process: the same pid from start to end proves the
# front end restart did not touch it.
server_manager_pid() { pgrep -f "__name:=hapi_server_manager" | head -1; }
MGR_PID_START="$(server_manager_pid)"
sleep 2

probe() {  # probe SECONDS NAME [INPUT_TOPIC] (background; PROBE_PID, PROBE_START)
  PROBE_START=$(python3 -c "import time; print(time.time())")
  ip netns exec "$NS_S" "${ENV_S[@]}" python3 "$REPO/test/reliability/ros_probe.py" --duration "$1" \
    --out "$OUT/$2.json" --input "${3:-}" >"$OUT/$2.log" 2>&1 &
  PROBE_PID=$!
}
end_probe() {  # the last messages cross the link, then the probe writes its JSON
  sleep 3
  kill -TERM "$PROBE_PID" 2>/dev/null || true
  wait "$PROBE_PID" || true
}
play_bg() {  # play_bg [rosbag play options]: PLAY_PID
  # shellcheck disable=SC2086
  # -d 2: the front end's image subscriptions (set up through the master,
  # across the link) get 2 s to connect before the first frame.
  ip netns exec "$NS_R" "${ENV_R[@]}" $PLAYER -q -d 2 "$@" "$BAG" </dev/null >>"$OUT/rosbag.log" 2>&1 &
  PLAY_PID=$!
}

# The link out of service (every packet lost, both ways) and back.
link_down() {
  case "$LINK_KIND" in
    tun) kill -USR1 "$DELAY_LINE_PID" ;;
    netem) ip -n "$NS_R" qdisc change dev "$IF_R" root netem delay "${DELAY_MS}ms" loss 100%
           ip -n "$NS_S" qdisc change dev "$IF_S" root netem delay "${DELAY_MS}ms" loss 100% ;;
    iptables) ip netns exec "$NS_R" iptables -I INPUT 1 -i "$IF_R" -j DROP
              ip netns exec "$NS_S" iptables -I INPUT 1 -i "$IF_S" -j DROP ;;
  esac
}
link_up() {
  case "$LINK_KIND" in
    tun) kill -USR2 "$DELAY_LINE_PID" ;;
    netem) ip -n "$NS_R" qdisc change dev "$IF_R" root netem delay "${DELAY_MS}ms" loss "$LOSS%"
           ip -n "$NS_S" qdisc change dev "$IF_S" root netem delay "${DELAY_MS}ms" loss "$LOSS%" ;;
    iptables) ip netns exec "$NS_R" iptables -D INPUT -i "$IF_R" -j DROP
              ip netns exec "$NS_S" iptables -D INPUT -i "$IF_S" -j DROP ;;
  esac
}
rss_kib() { awk '/^VmRSS/ {print $2}' "/proc/$1/status" 2>/dev/null || echo 0; }
robot_manager_pid() { pgrep -f "__name:=robot_manager" | head -1; }

if [ "$SCENARIO" = outage ]; then
  [ "$OUTAGE_AT" -lt "$BAG_LEN" ] || die "HAPI_OUTAGE_AT=$OUTAGE_AT s must be shorter than the bag ($BAG_LEN s)"
  ROBOT_MGR="$(robot_manager_pid)"
  log "outage: the bag once, link down $OUTAGE_AT s after the first odometry, for $OUTAGE_LEN s"
  # The bag's truth poses (10 Hz, nothing else subscribes to them across the
  # link) show how late the player itself delivered the bag.
  probe $((BAG_LEN + 60)) outage /ground_truth/pose
  sleep 1
  play_bg
  # The outage clock starts at the first odometry on the server, not at the
  # player: the player's image connections are set up through the master
  # across the lossy link, and one that a lost packet delays past the start
  # of the outage is not made until after it (the front end then saw no
  # frame at all and the run judged nothing).
  has_odometry() { server timeout 2 rostopic echo -n 1 /eskf/odom; }
  wait_for 20 "the first odometry on the server (the front end's image connections)" has_odometry
  log "first odometry at $(now_rel "$PROBE_START") s"
  sleep "$OUTAGE_AT"
  RSS=("$(rss_kib "$MGR_PID_START")" "$(rss_kib "$ROBOT_MGR")")
  DOWN_WALL="$(now_rel "$PROBE_START")"
  link_down
  log "link down at $DOWN_WALL s"
  sleep "$OUTAGE_LEN"
  RSS+=("$(rss_kib "$MGR_PID_START")" "$(rss_kib "$ROBOT_MGR")")
  link_up
  UP_WALL="$(now_rel "$PROBE_START")"
  log "link up at $UP_WALL s"
  wait "$PLAY_PID" || true
  RSS+=("$(rss_kib "$MGR_PID_START")" "$(rss_kib "$ROBOT_MGR")")
  end_probe
  kill -0 "$SERVER_PID" 2>/dev/null || die "the back end died during the outage scenario"
  [ "$LINK_KIND" = tun ] && sleep 1.5   # delay_line.py rewrites link.json every second
  python3 "$REPO/test/reliability/outage_verdict.py" --probe "$OUT/outage.json" --link "$IMPAIR" \
    --link-json "$OUT/link.json" --down-wall "$DOWN_WALL" --up-wall "$UP_WALL" \
    --manager-pids "$MGR_PID_START" "$(server_manager_pid)" --rss-kib "${RSS[@]}" | tee "$OUT/report.txt"
  exit "${PIPESTATUS[0]}"
fi

# Phase 1: one pass across the lossy link.
log "phase 1: play the bag once"
probe $((BAG_LEN + 60)) phase1
sleep 1
play_bg
wait "$PLAY_PID" || true
end_probe

# Phase 2: replay (time jump) and restart the front end RESTART_AT s in.
# The bag plays in a loop here so that the restarted front end always has
# images, however long its start over the slow link takes; the phase ends
# AFTER_RESTART s after the restart command.
log "phase 2: replay + front end restart after $RESTART_AT s"
probe $((RESTART_AT + AFTER_RESTART + 60)) phase2
sleep 1
play_bg -l
sleep "$RESTART_AT"
KILL_WALL="$(now_rel "$PROBE_START")"
kill -INT "$ROBOT_PID"
wait "$ROBOT_PID" 2>/dev/null || true
log "front end stopped at $KILL_WALL s of phase 2; restarting it"
start_robot
RESTART_WALL="$(now_rel "$PROBE_START")"
sleep "$AFTER_RESTART"
kill -INT "$PLAY_PID" 2>/dev/null || true
wait "$PLAY_PID" 2>/dev/null || true
end_probe
kill -0 "$SERVER_PID" 2>/dev/null || die "the back end died during phase 2"

# Phase 3: loop the bag (backwards jump at the loop point). 1.9 bag lengths:
# the front end restarted in phase 2 can still take seconds to deliver its
# first frames here (6.6 s once), which delays the loop point in wall time,
# and the check needs odometry after it; a second loop point needs 2 lengths.
LOOP_LEN=$((BAG_LEN * 19 / 10))
log "phase 3: rosbag play -l for $LOOP_LEN s"
probe $((LOOP_LEN + 60)) phase3
sleep 1
play_bg -l
sleep "$LOOP_LEN"
kill -INT "$PLAY_PID" 2>/dev/null || true
wait "$PLAY_PID" 2>/dev/null || true
end_probe
kill -0 "$SERVER_PID" 2>/dev/null || die "the back end died during phase 3"
MGR_PID_END="$(server_manager_pid)"

# Link counters: netem's own drop counts, or the user-space link's JSON.
if [ "$LINK_KIND" = netem ]; then
  for d in "$NS_R $IF_R" "$NS_S $IF_S"; do
    set -- $d
    echo "== $1"
    ip -n "$1" -s qdisc show dev "$2"
  done >"$OUT/netem_stats.txt"
elif [ "$LINK_KIND" = iptables ]; then
  # Dropped = the DROP rule's packet count; offered = packets received by
  # the interface (counted before netfilter sees them).
  stats=()
  for d in "$NS_S $IF_S $NS_R" "$NS_R $IF_R $NS_S"; do
    set -- $d
    drop="$(ip netns exec "$1" iptables -L INPUT -v -n -x | awk '/statistic/ {print $1; exit}')"
    rx="$(ip -n "$1" -s link show dev "$2" | awk '/RX:/ {getline; print $2; exit}')"
    stats+=("$3->$1" "${rx:-0}" "${drop:-0}")
  done
  python3 - "$OUT/link.json" "${stats[@]}" <<'PYEOF'
import json, sys
d = {}
a = sys.argv[2:]
for name, rx, drop in zip(a[0::3], a[1::3], a[2::3]):
    rx, drop = int(rx), int(drop)
    d[name] = {"packets_in": rx, "packets_dropped": drop, "packets_out": rx - drop,
               "loss_measured_pct": 100.0 * drop / max(1, rx)}
json.dump({"directions": d}, open(sys.argv[1], "w"), indent=1)
PYEOF
elif [ "$LINK_KIND" = tun ]; then
  sleep 1.5   # delay_line.py rewrites link.json every second; the link stays up for the shutdown
fi

# ------------------------------------------------------------- verdict
python3 "$REPO/test/reliability/two_hosts_verdict.py" --out "$OUT" --bag-len "$BAG_LEN" --link "$IMPAIR" \
  --link-kind "$LINK_KIND" --kill-wall "$KILL_WALL" --restart-wall "$RESTART_WALL" \
  --manager-pids "$MGR_PID_START" "$MGR_PID_END" --bag "$BAG" --max-motion-error "${HAPI_MAX_MOTION_ERROR:-0.25}" |
  tee "$OUT/report.txt"
exit "${PIPESTATUS[0]}"
