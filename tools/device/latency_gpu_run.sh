#!/usr/bin/env bash
# One device call for the latency of the pipeline without ROS
# (docs/BENCHMARKS.md "Latency a user feels"): builds the ROS-free packages
# with the carried OpenCV (prepare.sh opencv), runs the front end's and the
# new link's gtests, then tools/latency's pipeline_latency on each scenario
# given, with the variants cpu:cpu, gpu:cpu and gpu:cuda in one process per
# scenario (their times are ratios of one run). Trajectories (TUM) and logs
# come back in $OUT (or ./device-out).
#   tools/device/latency_gpu_run.sh "SCENARIO OPTIONS [--frontend n=v ...]" ...
#   carry .device/eigen3, .device/googletest and .device/opencv.tar.xz
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
B="$REPO/build-device-latency"
unpack_opencv || exit 1
{
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv
  echo "host cores: $(nproc)"
  c++ --version | head -1
} | tee "$OUT/device.txt"
build_with_opencv "$B" "hapi_dataset;hapi_sim;hapi_eskf;hapi_frontend" || exit 1
TOOL="$B/tools/latency/pipeline_latency"
[ -x "$TOOL" ] || { echo "pipeline_latency was not built"; grep -i opencv "$OUT/build.log" | head; exit 1; }
(cd "$B" && ctest --output-on-failure -R "frontend|hapi_sim" 2>&1) >"$OUT/ctest.log"
tail -12 "$OUT/ctest.log"
n=0
for scenario in "$@"; do
  n=$((n + 1))
  echo "== $scenario"
  # shellcheck disable=SC2086
  "$TOOL" $scenario --variant cpu:cpu --variant gpu:cpu --variant gpu:cuda --out "$OUT/run$n" 2>&1 |
    tee "$OUT/run$n.log"
done
tar -C "$OUT" -czf "$OUT/trajectories.tgz" $(cd "$OUT" && ls ./*.tum ./*_times.txt) && rm -f "$OUT"/*.tum "$OUT"/*_times.txt
