#!/usr/bin/env bash
# Fills .device/ (git-ignored) with what the GPU machine lacks: Eigen headers
# and GoogleTest sources from this machine's Debian packages. Carry ".device"
# in every device run.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
mkdir -p "$REPO/.device"
[ -d "$REPO/.device/eigen3" ] || cp -r /usr/include/eigen3 "$REPO/.device/eigen3"
[ -d "$REPO/.device/googletest" ] || cp -r /usr/src/googletest "$REPO/.device/googletest"
