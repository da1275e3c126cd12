#!/usr/bin/env bash
# One device call for hapi_surface's CUDA parts (docs/BENCHMARKS.md
# "Surface"): builds hapi_surface without ROS (no OpenCV on the GPU machine:
# the TSDF core and the dense-depth block matcher, which need none), runs
# its gtests with the GPU ones required (TSDF integration and the block
# matcher, CUDA against the CPU), then hapi_surface_bench (CPU and CUDA
# integration, meshing and projection per keyframe at the defaults). Logs
# come back in $OUT (or ./device-out).
#   tools/device/surface_gpu_run.sh [KEYFRAMES]
#   carry .device/eigen3 and .device/googletest
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
KEYFRAMES="${1:-8}"
B="$REPO/build-device-surface"
{
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv
  echo "host cores: $(nproc)"
  git -C "$REPO" log -1 --format='commit %h %cs' 2>/dev/null || true
} | tee "$OUT/surface_device.txt"
bash "$REPO/tools/device/build_core.sh" "$B" "hapi_surface" >"$OUT/surface_build.log" 2>&1 ||
  { tail -40 "$OUT/surface_build.log"; exit 1; }
echo "build ok"
rc=0
(cd "$B" && ctest --output-on-failure -R "hapi_surface" 2>&1) >"$OUT/surface_ctest.log" || rc=1
tail -8 "$OUT/surface_ctest.log"
"$B/hapi_surface/bench/hapi_surface_bench" "$KEYFRAMES" 2>&1 | tee "$OUT/surface_bench.txt" || rc=1
exit $rc
