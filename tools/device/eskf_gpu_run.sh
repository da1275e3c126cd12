#!/usr/bin/env bash
# One device call for the ES-EKF core: build, every hapi_eskf test
# (GPU tests included), the benchmark table (CPU and GPU in one run) and the
# in-filter comparison of the CUDA variants. Logs go to $OUT (or ./device-out).
#   tools/device/eskf_gpu_run.sh            (carry .device, see prepare.sh)
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT, B
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm,power.limit --format=csv | tee "$OUT/device.txt"
git -C "$REPO" log -1 --format='commit %H' 2>/dev/null | tee -a "$OUT/device.txt"
git -C "$REPO" status --short 2>/dev/null | head -20 | tee -a "$OUT/device.txt"
bash "$REPO/tools/device/build_core.sh" "$B" "hapi_eskf" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
echo "build ok"
(cd "$B" && ctest --output-on-failure 2>&1) >"$OUT/ctest.log"; tail -15 "$OUT/ctest.log"
BENCH="$B/hapi_eskf/bench/hapi_eskf_bench"
smi() {  # clocks, temperature, power and throttle reasons between the runs
  nvidia-smi --query-gpu=clocks.sm,clocks.mem,temperature.gpu,power.draw,clocks_event_reasons.active \
    --format=csv,noheader | sed "s|^|[$1] |" | tee -a "$OUT/smi.log"
}
smi "before the table"
# The table: defaults (by-size choice), every K, CPU rows where the Eigen
# reference is affordable, the isolated rank update with its controls.
"$BENCH" --k 1000,2000,4000,8000,16000,32000 --iters 50 --cpu-iters 5 --cpu-max-k 2000 --backend both \
  --cuda-stage-times >"$OUT/bench_table.log" 2>&1
smi "after the table"
# In-filter A/B at the target sizes: the defaults against the previous
# defaults (panelled GEMM + TRSM), alternated so that drift of the card's
# clock hits both alike.
for round in 1 2; do
  for v in "auto auto" "gemm trsm"; do
    set -- $v
    echo "=== round $round: rank update $1, solve $2" >>"$OUT/bench_ab.log"
    "$BENCH" --cuda-rank-update "$1" --cuda-solve "$2" --k 8000,32000 --iters 30 --backend cuda \
      --rank-reps 1 --cuda-stage-times >>"$OUT/bench_ab.log" 2>&1
    smi "after round $round $1/$2"
  done
done
grep -A 10 "^| backend | K | iters" "$OUT/bench_table.log"
grep -A 9 "^update stages" "$OUT/bench_table.log"
grep -A 8 "alone" "$OUT/bench_table.log"
grep "^===\|cuda-fp64 | [0-9]* | 30" "$OUT/bench_ab.log"
