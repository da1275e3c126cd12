#!/usr/bin/env bash
# One device call for the CPU backend on a quiet machine: the GPU machine's
# host cores (nothing else runs there). Builds hapi_eskf without CUDA against
# the carried OpenBLAS (prepare.sh; carry .device/eigen3, .device/googletest,
# .device/openblas), then the CPU benchmarks of docs/BENCHMARKS.md "CPU
# backend" on all cores and on 2 cores (taskset, OpenBLAS threads 2: the
# demo machine's core count), and OpenBLAS against Eigen with one thread.
# Logs go to $OUT (or ./device-out).
set -uo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="${OUT:-$REPO/device-out}"
mkdir -p "$OUT"
OB="$REPO/.device/openblas"
[ -f "$OB/libopenblas.so.0" ] || { echo "no $OB (tools/device/prepare.sh, carry .device/openblas)"; exit 1; }
ln -sf libopenblas.so.0 "$OB/libopenblas.so"
export LD_LIBRARY_PATH="$OB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
B="$REPO/build-device-cpu"
{ lscpu | grep -E "Model name|^CPU\(s\)|Thread|MHz"; nproc; git -C "$REPO" log -1 --format='commit %H' 2>/dev/null; } |
  tee "$OUT/host.txt"
HAPI_DEVICE_CMAKE_ARGS="-DHAPI_WITH_CUDA=OFF -DHAPI_OPENBLAS_LIBRARY=$OB/libopenblas.so" \
  bash "$REPO/tools/device/build_core.sh" "$B" "hapi_eskf" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
grep -m1 "OpenBLAS" "$B/CMakeCache.txt" "$OUT/build.log" | head -2
(cd "$B" && ctest -R "cpu_backend|partitioned" --output-on-failure 2>&1) >"$OUT/ctest.log"; tail -4 "$OUT/ctest.log"
BENCH="$B/hapi_eskf/bench/hapi_eskf_bench"
run() {  # run NAME [env/taskset prefix ...] -- bench args
  local name="$1"; shift
  echo "=== $name: $*" | tee -a "$OUT/runs.txt"
  timeout 240 "$@" >"$OUT/$name.log" 2>&1; echo "exit $?" >>"$OUT/$name.log"
  grep -E "^\| (backend|cpu)|ceiling|GFLOP|DGEMM|DSYRK" "$OUT/$name.log" | head -30
}
run all_random "$BENCH" --k 1000,2000,4000 --cpu-max-k 4000 --cpu-iters 8 --backend cpu --covariance-update dense,partitioned
run all_sweep "$BENCH" --k 2000,4000 --cpu-max-k 4000 --cpu-iters 40 --backend cpu --cpu-la blas --covariance-update dense,partitioned \
  --scenario sweep
run two_cores env OPENBLAS_NUM_THREADS=2 taskset -c 0,1 "$BENCH" --k 1000,2000 --cpu-iters 8 --backend cpu \
  --cpu-la blas,eigen
run one_thread env OPENBLAS_NUM_THREADS=1 taskset -c 0 "$BENCH" --k 1000,2000 --cpu-iters 8 --backend cpu \
  --cpu-la blas,eigen
