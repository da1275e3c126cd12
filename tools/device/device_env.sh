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
