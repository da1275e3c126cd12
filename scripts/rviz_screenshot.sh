#!/usr/bin/env bash
# A real rviz check: runs the main-job pipeline (scripts/run_pipeline.sh) on a
# bag with rviz (rviz/hapi.rviz) on a virtual X server (Xvfb, software
# OpenGL), takes a screenshot of the empty scene before the bag starts and one
# while the pipeline runs, and checks that the landmark map is drawn in the 3D
# view (scripts/rviz_screenshot_check.py: changed, non-display-colour pixels
# in the region of rviz's background colour).
#
#   scripts/rviz_screenshot.sh BAG [OUT_DIR]
#
# Env: HAPI_SHOT_AT (seconds of bag time before the second shot, default 10),
#      HAPI_SHOT_DELAY (seconds the player waits so rviz is up first, default 25),
#      HAPI_SHOT_MIN_PIXELS (default 1500), HAPI_WS (workspace, default .ws).
# Writes OUT_DIR/rviz.png, OUT_DIR/rviz_before.png, OUT_DIR/run/ (the
# pipeline's report). Exit 0 map visible, 1 not visible / run broken,
# 77 a tool is missing (Xvfb, xwd, xwininfo, rviz: ctest reports a skip).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
[ $# -ge 1 ] || { echo "usage: $0 BAG [OUT_DIR]" >&2; exit 1; }
BAG="$1"
OUT="${2:-$WS/rviz_shot}"
AT="${HAPI_SHOT_AT:-10}"
DELAY="${HAPI_SHOT_DELAY:-25}"
MIN_PIXELS="${HAPI_SHOT_MIN_PIXELS:-1500}"

for tool in Xvfb xwd xwininfo rviz; do
  command -v "$tool" >/dev/null || { echo "[rviz-shot] MISSING: $tool (Debian: xvfb x11-apps x11-utils rviz)" >&2; exit 77; }
done
mkdir -p "$OUT"
rm -f "$OUT"/*.xwd "$OUT"/rviz*.png

XVFB_PID=""; RUN_PID=""
cleanup() {
  if [ -n "$RUN_PID" ] && kill -0 "$RUN_PID" 2>/dev/null; then kill -INT "$RUN_PID" 2>/dev/null || true; wait "$RUN_PID" 2>/dev/null || true; fi
  if [ -n "$XVFB_PID" ]; then kill "$XVFB_PID" 2>/dev/null || true; fi
}
trap cleanup EXIT

# -displayfd: Xvfb picks a free display number and writes it to fd 3.
exec 3>"$OUT/display"
Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp >"$OUT/xvfb.log" 2>&1 &
XVFB_PID=$!
exec 3>&-
for _ in $(seq 100); do [ -s "$OUT/display" ] && break; sleep 0.1; done
[ -s "$OUT/display" ] || { echo "[rviz-shot] ERROR: Xvfb did not start (see $OUT/xvfb.log)" >&2; exit 1; }
export DISPLAY=":$(head -n1 "$OUT/display")"
export LIBGL_ALWAYS_SOFTWARE=1   # Mesa llvmpipe: no GPU needed
echo "[rviz-shot] Xvfb on $DISPLAY; pipeline with rviz on $BAG"

T0=$(date +%s)
HAPI_RUN_DIR="$OUT/run" HAPI_REPLAY_ARGS="rviz:=true delay:=$DELAY" \
  bash "$REPO/scripts/run_pipeline.sh" "$BAG" >"$OUT/pipeline.out" 2>&1 &
RUN_PID=$!

# The first shot: rviz is up (its main window is mapped) but the player is
# still in its delay, so no map, path or pose exists yet.
for _ in $(seq 600); do
  xwininfo -root -tree 2>/dev/null | grep -q 'RViz' && break
  kill -0 "$RUN_PID" 2>/dev/null || break
  sleep 0.1
done
xwininfo -root -tree 2>/dev/null | grep -q 'RViz' || { echo "[rviz-shot] ERROR: no rviz window (see $OUT/pipeline.out)" >&2; exit 1; }
sleep 4   # let rviz draw its first frames
xwd -root -silent >"$OUT/before.xwd"
T_BEFORE=$(( $(date +%s) - T0 ))
# roscore + roslaunch take a few seconds before the player's delay starts, so
# a shot within DELAY-3 s of our start is certainly before the first message.
if [ "$T_BEFORE" -ge $((DELAY - 3)) ]; then
  echo "[rviz-shot] ERROR: rviz took ${T_BEFORE} s to come up, too close to the bag start (HAPI_SHOT_DELAY=$DELAY)" >&2
  exit 1
fi

sleep $((DELAY + AT - T_BEFORE))
kill -0 "$RUN_PID" 2>/dev/null || { echo "[rviz-shot] ERROR: the pipeline ended before the shot:" >&2; tail -20 "$OUT/pipeline.out" >&2; exit 1; }
xwd -root -silent >"$OUT/after.xwd"
echo "[rviz-shot] shots at ${T_BEFORE} s (before the bag) and $((DELAY + AT)) s (~${AT} s into the bag)"

set +e
wait "$RUN_PID"; run_rc=$?; RUN_PID=""
/usr/bin/python3 "$REPO/scripts/rviz_screenshot_check.py" "$OUT/before.xwd" "$OUT/after.xwd" "$OUT/rviz.png" \
  --min-pixels "$MIN_PIXELS"
rc=$?
set -e
rm -f "$OUT"/*.xwd
echo "[rviz-shot] pipeline exit status $run_rc (its output: $OUT/pipeline.out)"
exit "$rc"
