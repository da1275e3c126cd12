#!/usr/bin/env bash
# Fills .device/ (git-ignored) with what the GPU machine lacks: Eigen headers
# and GoogleTest sources from this machine's Debian packages. Carry ".device"
# in every device run.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
mkdir -p "$REPO/.device"
[ -d "$REPO/.device/eigen3" ] || cp -r /usr/include/eigen3 "$REPO/.device/eigen3"
[ -d "$REPO/.device/googletest" ] || cp -r /usr/src/googletest "$REPO/.device/googletest"
# OpenBLAS for the CPU backend's benchmarks on the GPU machine's host cores
# (a quiet 16-core machine; it has no Debian -dev packages): the library and
# the runtime it needs, under the names the loader asks for. Carry
# ".device/openblas" (about 40 MB) only in the calls that use it.
if [ ! -d "$REPO/.device/openblas" ]; then
  mkdir -p "$REPO/.device/openblas"
  cp -L /usr/lib/x86_64-linux-gnu/openblas-pthread/libopenblas.so.0 "$REPO/.device/openblas/libopenblas.so.0"
  cp -L /usr/lib/x86_64-linux-gnu/libgfortran.so.5 /usr/lib/x86_64-linux-gnu/libquadmath.so.0 "$REPO/.device/openblas/"
fi
# libFuzzer targets for the GPU machine's 16 host cores (tools/device/fuzz_run.sh):
#   prepare.sh fuzz FUZZ_BUILD_DIR BUNDLE_NAME TARGET...
# packs the targets (debug info stripped) of a `test/fuzz/smoke.sh build` and
# the shared libraries they load, except the C library, which the machine has
# in a version at least as new, into .device/fuzz-BUNDLE_NAME.tar.xz. Carry
# that one file in the call that runs it.
if [ "${1:-}" = fuzz ]; then
  FUZZ_BUILD="${2:?usage: prepare.sh fuzz FUZZ_BUILD_DIR BUNDLE_NAME TARGET...}"
  NAME="${3:?usage: prepare.sh fuzz FUZZ_BUILD_DIR BUNDLE_NAME TARGET...}"
  shift 3
  STAGE="$(mktemp -d)"
  mkdir -p "$STAGE/$NAME/bin" "$STAGE/$NAME/lib"
  for t in "$@"; do
    objcopy --strip-debug "$FUZZ_BUILD/${t}_fuzzer" "$STAGE/$NAME/bin/${t}_fuzzer"
    ldd "$FUZZ_BUILD/${t}_fuzzer" | awk '$3 ~ /^\// {print $3}' |
      grep -v -E '/(libc|libm|libpthread|libdl|librt|ld-linux-x86-64)\.so' |
      xargs -I{} cp -L {} "$STAGE/$NAME/lib/"
  done
  tar -C "$STAGE" -cJf "$REPO/.device/fuzz-$NAME.tar.xz" "$NAME"
  rm -rf "$STAGE"
  ls -la "$REPO/.device/fuzz-$NAME.tar.xz"
fi
# OpenCV for the pipeline without ROS on the GPU machine
# (tools/device/latency_gpu_run.sh, tools/device/opencv/OpenCVConfig.cmake):
#   prepare.sh opencv
# packs Debian's OpenCV headers and the modules core, imgproc, features2d,
# calib3d, flann and video (the image flow's LK; it loads dnn) with the
# libraries they load, except the C and C++
# runtimes, which the machine's own compiler brings, into
# .device/opencv.tar.xz. Carry that one file in the call that uses it.
if [ "${1:-}" = opencv ]; then
  STAGE="$(mktemp -d)"
  mkdir -p "$STAGE/opencv/include" "$STAGE/opencv/lib"
  cp -r /usr/include/opencv4 "$STAGE/opencv/include/"
  for m in core imgproc features2d calib3d flann video dnn; do
    lib=/usr/lib/x86_64-linux-gnu/libopencv_$m.so.406
    cp -L "$lib" "$STAGE/opencv/lib/"
    ldd "$lib" | awk '$3 ~ /^\// {print $1, $3}' |
      grep -v -E '^(libc|libm|libpthread|libdl|librt|ld-linux-x86-64|libstdc\+\+|libgcc_s)\.so' |
      while read -r name path; do cp -L "$path" "$STAGE/opencv/lib/$name"; done
  done
  tar -C "$STAGE" -cJf "$REPO/.device/opencv.tar.xz" opencv
  rm -rf "$STAGE"
  ls -la "$REPO/.device/opencv.tar.xz"
fi
