#!/usr/bin/env bash
# One device call for the surface-motion path without ROS, image to output
# (docs/BENCHMARKS.md "Surface motion, image to output"): builds the
# ROS-free packages with the carried OpenCV (prepare.sh opencv, with the video
# module), runs the image-flow gtests (CPU and CUDA), then
# tools/latency/surface_motion_latency on each scenario given, its cpu and
# gpu tracker variants in one process (their times are ratios of one run).
# Logs and tables come back in $OUT (or ./device-out).
#   tools/device/surface_motion_gpu_run.sh "SCENARIO OPTIONS" ...
#   carry .device/eigen3, .device/googletest and .device/opencv.tar.xz
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
B="$REPO/build-device-surface-motion"
unpack_opencv video || exit 1
{
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv
  echo "host cores: $(nproc)"
  c++ --version | head -1
  git -C "$REPO" log -1 --format='commit %h %cs' 2>/dev/null || true
} | tee "$OUT/device.txt"
build_with_opencv "$B" "hapi_dataset;hapi_sim;hapi_eskf;hapi_frontend" || exit 1
TOOL="$B/tools/latency/surface_motion_latency"
[ -x "$TOOL" ] || { echo "surface_motion_latency was not built"; grep -i "opencv\|video" "$OUT/build.log" | head; exit 1; }
rc=0
(cd "$B" && ctest --output-on-failure -R "hapi_frontend_(flow_test|flow_gpu_test)|surface_motion" 2>&1) >"$OUT/ctest.log" || rc=1
tail -8 "$OUT/ctest.log"
n=0
for scenario in "$@"; do
  n=$((n + 1))
  echo "== $scenario"
  # shellcheck disable=SC2086
  "$TOOL" $scenario --variant cpu --variant gpu 2>&1 | tee "$OUT/surface_motion_run$n.md" || rc=1
done
exit $rc
