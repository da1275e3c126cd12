#!/usr/bin/env bash
# Builds the ROS-free core on the lent GPU machine (CUDA, CMake and ninja, but
# no Debian -dev packages): Eigen headers and GoogleTest sources travel in
# .device/ (prepared by tools/device/prepare.sh, carried with the call).
#   tools/device/build_core.sh [build-dir] [packages]
# HAPI_DEVICE_CMAKE_ARGS adds configure options (e.g. -DHAPI_WITH_CUDA=OFF).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
B="${1:-$REPO/build-device}"
PKGS="${2:-hapi_eskf;hapi_frontend}"
cmake -S "$REPO" -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_DISABLE_FIND_PACKAGE_catkin=ON "-DHAPI_CORE_PACKAGES=$PKGS" \
  -DHAPI_EIGEN_INCLUDE_DIR="$REPO/.device/eigen3" -DHAPI_GTEST_SOURCE_DIR="$REPO/.device/googletest" \
  -DCMAKE_CUDA_ARCHITECTURES=90 ${HAPI_DEVICE_CMAKE_ARGS:-} >/dev/null
cmake --build "$B" -j"$(nproc)"
