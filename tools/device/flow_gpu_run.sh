#!/usr/bin/env bash
# One device call for the image flow's CUDA tracker (docs/BENCHMARKS.md
# "Image flow"): builds hapi_dataset, hapi_sim and hapi_frontend without ROS
# with the carried OpenCV (prepare.sh opencv, which packs the video module),
# runs the image-flow gtests (the host check of the CUDA arithmetic against
# OpenCV, the CPU tracker's criteria) and the GPU gtests (ORB, matcher, and
# CUDA vs CPU image flow), then hapi_frontend_flow_bench's backend table (CPU and
# CUDA in one process, same frames) on the waves and skin textures. Logs and
# tables come back in $OUT (or ./device-out).
#   tools/device/flow_gpu_run.sh [FRAMES]
#   carry .device/eigen3, .device/googletest and .device/opencv.tar.xz
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
FRAMES="${1:-100}"
B="$REPO/build-device-flow"
unpack_opencv video || exit 1
{
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv
  echo "host cores: $(nproc)"
  c++ --version | head -1
  nvcc --version | tail -1
  git -C "$REPO" log -1 --format='commit %h %cs' 2>/dev/null || true
} | tee "$OUT/device.txt"
build_with_opencv "$B" "hapi_dataset;hapi_sim;hapi_frontend" || exit 1
BENCH="$B/hapi_frontend/bench/hapi_frontend_flow_bench"
[ -x "$BENCH" ] && [ -x "$B/hapi_frontend/test/gpu/hapi_frontend_flow_gpu_test" ] ||
  { echo "the image-flow targets were not built"; grep -i "opencv\|video" "$OUT/build.log" | head; exit 1; }
rc=0
(cd "$B" && ctest --output-on-failure -R "hapi_frontend_(flow_test|flow_gpu_test|gpu_test)" 2>&1) >"$OUT/ctest.log" || rc=1
tail -8 "$OUT/ctest.log"
"$B/hapi_frontend/test/gpu/hapi_frontend_flow_gpu_test" >"$OUT/flow_gpu_test.log" 2>&1 || rc=1
for texture in waves skin; do
  echo "== $texture"
  "$BENCH" --frames "$FRAMES" --texture "$texture" --backends-only 1 2>&1 | tee "$OUT/flow_bench_$texture.md" || rc=1
done
exit $rc
