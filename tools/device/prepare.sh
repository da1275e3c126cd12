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
