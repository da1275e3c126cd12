#!/usr/bin/env bash
# One device call for the GPU-fault handling (docs/RELIABILITY.md "GPU
# faults"): build the ROS-free hapi_eskf core, run its gtests (the fault
# tests test_eskf_cuda_faults and the CPU/GPU parity tests included), then
# the replay soak of the CUDA backend on a long frame stream: a carried
# frames file or the synthetic orbit, which needs no carrying
# (docs/RELIABILITY.md "Full-pool soak"). Logs go to $OUT (or ./device-out).
#   tools/device/faults_gpu_run.sh [STREAM.txt|--synthetic-orbit=SEED,frames=N,...]
#   (carry .device/eigen3 and .device/googletest, see prepare.sh)
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT, B
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv | tee "$OUT/device.txt"
git -C "$REPO" log -1 --format='commit %H' 2>/dev/null | tee -a "$OUT/device.txt"
bash "$REPO/tools/device/build_core.sh" "$B" "hapi_eskf" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
echo "build ok"
(cd "$B" && ctest --output-on-failure 2>&1) >"$OUT/ctest.log"
tail -25 "$OUT/ctest.log"
# The fault test's own output (the CUDA error text; a missing device fails, HAPI_REQUIRE_GPU).
"$(find "$B" -name test_eskf_cuda_faults -type f | head -1)" 2>&1 | tee "$OUT/faults.log" | grep -E "CUDA error|OK|FAILED|SKIP|PASSED|HAPI_REQUIRE_GPU"
if [ -n "${1:-}" ]; then
  python3 "$REPO/test/reliability/replay_soak.py" --replay "$B/hapi_eskf/tools/eskf_replay" --stream="$1" \
    --out "$OUT/replay_soak" backend=cuda 2>&1 | tee "$OUT/replay_soak.log" | tail -20
fi
