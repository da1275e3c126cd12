# Sourced by the tools/device/*_gpu_run.sh scripts: what every device call
# shares. A device test that skips for want of a GPU fails there
# (HAPI_REQUIRE_GPU, test/gtest/hapi_test/skip.hpp); REPO is the checkout,
# OUT the folder whose files come back (./device-out outside the device
# tool), B the default build folder.
export HAPI_REQUIRE_GPU=1
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="${OUT:-$REPO/device-out}"
mkdir -p "$OUT"
B="$REPO/build-device"

# unpack_opencv [video]: the carried OpenCV (tools/device/prepare.sh opencv,
# .device/opencv.tar.xz) into CV, on the library path, with the OpenBLAS
# that OpenCV's core loads linked for the CPU backend; `video`: fail without
# the video module (the image flow).
unpack_opencv() {
  CV="$(mktemp -d)"
  tar -C "$CV" -xJf "$REPO/.device/opencv.tar.xz"
  if [ "${1:-}" = video ] && [ ! -f "$CV/opencv/lib/libopencv_video.so.406" ]; then
    echo "the carried OpenCV has no video module: rerun tools/device/prepare.sh opencv"
    return 1
  fi
  export LD_LIBRARY_PATH="$CV/opencv/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  ln -sf libopenblas.so.0 "$CV/opencv/lib/libopenblas.so"
}

# build_with_opencv BUILD_DIR PACKAGES: the ROS-free packages against the
# unpacked OpenCV (unpack_opencv first), log in $OUT/build.log.
build_with_opencv() {
  HAPI_DEVICE_CMAKE_ARGS="-DOpenCV_DIR=$REPO/tools/device/opencv -DHAPI_DEVICE_OPENCV=$CV/opencv \
    -DHAPI_OPENBLAS_LIBRARY=$CV/opencv/lib/libopenblas.so" \
    bash "$REPO/tools/device/build_core.sh" "$1" "$2" >"$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; return 1; }
  echo "build ok"
}
