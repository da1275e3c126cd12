#!/usr/bin/env bash
# One device call for the motion models on the GPU: build, every hapi_eskf
# test (the CUDA parity tests cover both pose blocks, 12 and 18), the
# benchmark at K = 8000, and the ROS-free replay (eskf_replay) of recorded
# landmark streams with the CUDA backend against the CPU backend, per motion
# model (and `inertial` with the scene motion states, a pose block of 24):
# the largest position difference of the per-frame estimates and the
# per-frame times. Streams: .device/streams/*.txt (dump_frames.py output,
# carried with the call). Logs go to $OUT (or ./device-out).
set -uo pipefail
# HAPI_REQUIRE_GPU=1, REPO, OUT, B
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv | tee "$OUT/device.txt"
bash "$REPO/tools/device/build_core.sh" "$B" "hapi_eskf" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
echo "build ok"
(cd "$B" && ctest --output-on-failure 2>&1) >"$OUT/ctest.log"; tail -6 "$OUT/ctest.log"
"$B/hapi_eskf/bench/hapi_eskf_bench" --k 8000 --iters 30 --backend cuda >"$OUT/bench_8000.log" 2>&1
grep -A 4 "^| backend | K | iters" "$OUT/bench_8000.log"
REPLAY="$B/hapi_eskf/tools/eskf_replay"
for s in "$REPO"/.device/streams/*.txt; do
  name="$(basename "$s" .txt)"
  offset=0
  case "$name" in skin_* | motion_*) offset=-0.003 ;; esac
  for model in constant_velocity inertial inertial_scene; do
    settings="motion_model=${model%_scene}"
    [ "$model" = inertial_scene ] && settings="$settings scene_motion=true"
    for backend in cpu cuda; do
      # shellcheck disable=SC2086  # settings: separate key=value words
      "$REPLAY" "$s" $settings backend=$backend imu_time_offset=$offset \
        --out "$OUT/${name}_${model}_${backend}" >"$OUT/${name}_${model}_${backend}.log" 2>&1
      echo "$name $model $backend: $(grep '^frames=' "$OUT/${name}_${model}_${backend}.log")"
      echo "  $(grep '^frame time' "$OUT/${name}_${model}_${backend}.log")"
    done
    python3 - "$OUT/${name}_${model}_cpu_estimate.tum" "$OUT/${name}_${model}_cuda_estimate.tum" <<'PY'
import sys
a = [list(map(float, l.split())) for l in open(sys.argv[1])]
b = [list(map(float, l.split())) for l in open(sys.argv[2])]
n = min(len(a), len(b))
d = max(((x[1] - y[1]) ** 2 + (x[2] - y[2]) ** 2 + (x[3] - y[3]) ** 2) ** 0.5 for x, y in zip(a[:n], b[:n]))
print(f"  cpu vs cuda: {n} of {len(a)}/{len(b)} frames, largest position difference {d:.3e} m")
PY
  done
done
