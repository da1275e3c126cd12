#!/usr/bin/env bash
# The fuzz targets of test/fuzz as ctest runs them (docs/RELIABILITY.md
# "Coverage-guided fuzzing"):
#   smoke.sh build BUILD_DIR MSGS_INCLUDE_DIR      configure + build with clang (once per build folder)
#   smoke.sh run BUILD_DIR TARGET SECONDS [ARGS]   fuzz TARGET for SECONDS from its seed corpus
#   smoke.sh gtests BUILD_DIR                      the cores' gtests on the same instrumented build
# "run" starts from test/fuzz/corpus/TARGET (the seeds and every input that
# once crashed, kept as regression inputs) plus what earlier runs in
# BUILD_DIR found, and fails on any crash, sanitizer report, leak, timeout
# (> 1 s per input) or memory limit; the input that failed is saved as
# BUILD_DIR/artifacts/TARGET/<kind>-<sha1>. Exit 77 (ctest: skipped) when
# clang-14 or libFuzzer is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
# One process per core (ctest -j, xargs -P): OpenBLAS's own threads would
# only wait for a core (a quarter of a gtest's time went to sched_yield).
export OPENBLAS_NUM_THREADS=1
MODE="${1:-}"
BUILD="${2:?usage: smoke.sh build|run BUILD_DIR ...}"

case "$MODE" in
  build)
    MSGS="${3:?usage: smoke.sh build BUILD_DIR MSGS_INCLUDE_DIR}"
    if ! command -v clang++-14 >/dev/null || ! ls /usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a \
        >/dev/null 2>&1; then
      echo "smoke.sh: clang++-14 or libFuzzer (libclang-rt-14-dev) missing: fuzz targets skipped"
      exit 77
    fi
    launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    cmake -S "$HERE" -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++-14 -DHAPI_MSGS_INCLUDE_DIR="$MSGS" "${launcher[@]}" >/dev/null
    cmake --build "$BUILD" -j"${HAPI_JOBS:-$(nproc)}" --target landmarks_fuzzer imu_fuzzer image_pair_fuzzer compressed_fuzzer image_flow_fuzzer surface_motion_flow_fuzzer \
      surface_input_fuzzer dense_depth_pair_fuzzer map_file_fuzzer camera_info_fuzzer \
      sanitized_gtests
    ;;
  gtests)
    LIST="$BUILD/sanitized_gtests.txt"
    [ -s "$LIST" ] || { echo "smoke.sh: $LIST missing (smoke.sh build first)"; exit 77; }
    # Any ASan/UBSan/LeakSanitizer report aborts its test (exit status != 0).
    export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    # One binary per core (ctest gives this entry PROCESSORS 2), taken in the
    # list's order, which puts the longest first (test/fuzz/CMakeLists.txt).
    # Each verdict is printed whole when its binary ends.
    run_gtest() {
      local t="$1" start=$SECONDS report
      if "$BUILD/$t" --gtest_brief=1 >"$BUILD/$t.log" 2>&1; then
        echo "smoke.sh: $t passed ($((SECONDS - start)) s)"
      else
        report="$(tail -n 60 "$BUILD/$t.log")"
        printf 'smoke.sh: %s FAILED (%d s):\n%s\n' "$t" $((SECONDS - start)) "$report"
        return 1
      fi
    }
    export -f run_gtest
    export BUILD
    grep -v '^$' "$LIST" | xargs -P "${HAPI_JOBS:-$(nproc)}" -I{} bash -c 'run_gtest "$1"' _ {} \
      | tee "$BUILD/sanitized_gtests.out" || true  # the verdict is the FAILED lines
    failed="$(sed -n 's/^smoke.sh: \([^ ]*\) FAILED.*/\1/p' "$BUILD/sanitized_gtests.out" | tr '\n' ' ')"
    [ -z "$failed" ] || { echo "smoke.sh: failed: $failed"; exit 1; }
    ;;
  run)
    TARGET="${3:?usage: smoke.sh run BUILD_DIR TARGET SECONDS}"
    SECONDS_="${4:?usage: smoke.sh run BUILD_DIR TARGET SECONDS}"
    shift 4
    BIN="$BUILD/${TARGET}_fuzzer"
    [ -x "$BIN" ] || { echo "smoke.sh: $BIN not built (smoke.sh build first)"; exit 77; }
    WORK="$BUILD/work/$TARGET"
    ART="$BUILD/artifacts/$TARGET"
    mkdir -p "$WORK" "$ART"
    # New inputs go to WORK (first folder); the committed corpus is read only.
    # A leak or a sanitizer report is a crash (exit 1), as is a timeout.
    LOG="$BUILD/$TARGET.log"
    set +e
    "$BIN" -max_total_time="$SECONDS_" -timeout=1 -rss_limit_mb=2048 -error_exitcode=1 -timeout_exitcode=1 \
      -print_final_stats=1 -artifact_prefix="$ART/" "$@" "$WORK" "$HERE/corpus/$TARGET" >"$LOG" 2>&1
    status=$?
    set -e
    # The report (or the final statistics), without libFuzzer's progress lines.
    grep -v -E '^#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|RELOAD)' "$LOG" | tail -n 80
    echo "smoke.sh: $TARGET exit status $status"
    exit "$status"
    ;;
  *)
    echo "usage: smoke.sh build BUILD_DIR MSGS_INCLUDE_DIR | run BUILD_DIR TARGET SECONDS [libFuzzer args]" \
      "| gtests BUILD_DIR" >&2
    exit 2
    ;;
esac
