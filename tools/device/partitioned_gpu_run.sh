#!/usr/bin/env bash
# One device call for the partitioned CUDA update (docs/DESIGN.md
# "Partitioned update", "Staged flush", "Background shares"): build the
# ROS-free core, run the partitioned tests (GPU and CPU), then the benchmark,
# FP64, dense against partitioned in the same run, the partitioned rows with
# the flush at once and staged (--partition-flush-shares, default 1,4), each
# share inside an update or between frames (--partition-flush-background,
# default 0,1):
#  * the sweep (the view advances 10 of 200 visible landmarks per frame) at
#    K = 8000 and 32000, frames back to back and at a camera's 10 Hz
#    (--frame-period-ms 100, where background shares run between frames);
#  * the worst case (the visible set jumps every frame) at K = 32000, shares
#    inside updates;
#  * with `45000` as the first argument also the 10 Hz sweep at K = 45000 (C
#    alone takes 136 of the card's 140 GiB).
# The other tests last. Logs go to $OUT (or ./device-out); the tables are
# printed at the end.
#   tools/device/partitioned_gpu_run.sh [45000]     (carry .device, see prepare.sh)
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT, B
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm,power.limit --format=csv | tee "$OUT/device.txt"
bash "$REPO/tools/device/build_core.sh" "$B" "hapi_eskf" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
echo "build ok"
# The partitioned tests first (GPU and CPU), the rest after the benchmark.
FIRST="cuda_partitioned|cpu_backend_variants|partitioned_filter"
(cd "$B" && ctest -R "$FIRST" --timeout 400 --output-on-failure 2>&1) >"$OUT/ctest.log"
grep -E "tests passed|Failed|\*\*\*|FAILED|Test +#" "$OUT/ctest.log" | tail -12
BENCH="$B/hapi_eskf/bench/hapi_eskf_bench"
SHARES="${PARTITION_FLUSH_SHARES:-1,4}"
BACKGROUND="${PARTITION_FLUSH_BACKGROUND:-0,1}"
COMMON=(--backend cuda --covariance-update dense,partitioned --partition-flush-shares "$SHARES"
        --partition-flush-background "$BACKGROUND" --rank-reps 0)
timeout 240 "$BENCH" "${COMMON[@]}" --scenario sweep --k 8000,32000 --iters 60 >"$OUT/bench_sweep.log" 2>&1
timeout 240 "$BENCH" "${COMMON[@]}" --scenario sweep --k 8000,32000 --iters 60 --frame-period-ms 100 \
  >"$OUT/bench_sweep_10hz.log" 2>&1
timeout 150 "$BENCH" "${COMMON[@]}" --partition-flush-background 0 --scenario random --k 32000 --iters 20 \
  >"$OUT/bench_random.log" 2>&1
if [ "${1:-}" = 45000 ]; then
  timeout 240 "$BENCH" "${COMMON[@]}" --scenario sweep --k 45000 --iters 40 --frame-period-ms 100 \
    >"$OUT/bench_45000.log" 2>&1
fi
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw,clocks_event_reasons.active --format=csv,noheader \
  | tee -a "$OUT/device.txt"
# One test at a time: the GPU tests size pools by the device's free memory
# (the fault test fills it on purpose), so parallel runs starve each other.
(cd "$B" && ctest -E "$FIRST" --timeout 400 --output-on-failure 2>&1) >>"$OUT/ctest.log"
grep -E "tests passed|\*\*\*|FAILED" "$OUT/ctest.log" | tail -12
for f in bench_sweep bench_sweep_10hz bench_random bench_45000; do
  [ -f "$OUT/$f.log" ] || continue
  echo "=== $f"
  grep -E "^scenario|^frames|^device|^ceilings|^\| (backend|cuda)" "$OUT/$f.log"
done
