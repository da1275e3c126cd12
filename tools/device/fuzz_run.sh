#!/usr/bin/env bash
# Runs libFuzzer targets on the GPU machine's host cores, many workers per
# target, to reach the execution counts a 2-core machine cannot
# (docs/RELIABILITY.md "Coverage-guided fuzzing").
#   tools/device/fuzz_run.sh .device/fuzz-NAME.tar.xz SECONDS TARGET:WORKERS...
# (bundle made by `tools/device/prepare.sh fuzz`). Each target runs through
# test/fuzz/smoke.sh with the flags of the test command (-timeout=1,
# -rss_limit_mb=2048, leaks and sanitizer reports are failures) and
# -jobs=WORKERS -workers=WORKERS; the workers share the target's corpus
# folder. Per target it prints the summed executions, the exec/s and the
# crash/leak/timeout artifacts; the logs and artifacts come back in
# $OUT/fuzz.tgz.
set -uo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="${OUT:-$REPO/device-out}"
BUNDLE="${1:?usage: fuzz_run.sh BUNDLE.tar.xz SECONDS TARGET:WORKERS...}"
SECS="${2:?usage: fuzz_run.sh BUNDLE.tar.xz SECONDS TARGET:WORKERS...}"
shift 2
STAGE="$(mktemp -d)"
tar -C "$STAGE" -xJf "$BUNDLE"
DIR="$(ls -d "$STAGE"/*/)"
export LD_LIBRARY_PATH="$DIR/lib"
ldd --version | head -1
nproc
for spec in "$@"; do
  t="${spec%%:*}"; w="${spec##*:}"
  mkdir -p "$OUT/fuzz/$t"
  # smoke.sh puts the work corpus and artifacts next to the binary; the
  # -jobs workers write fuzz-N.log into the current folder.
  (cd "$OUT/fuzz/$t" && bash "$REPO/test/fuzz/smoke.sh" run "$DIR/bin" "$t" "$SECS" -jobs="$w" -workers="$w" \
     >"$OUT/fuzz/$t/smoke.log" 2>&1; echo "$?" >"$OUT/fuzz/$t/status") &
done
wait
for spec in "$@"; do
  t="${spec%%:*}"
  execs=$(cat "$OUT/fuzz/$t"/fuzz-*.log 2>/dev/null | awk '/stat::number_of_executed_units/ {s += $NF} END {print s + 0}')
  rss=$(cat "$OUT/fuzz/$t"/fuzz-*.log 2>/dev/null | awk '/stat::peak_rss_mb/ {if ($NF > m) m = $NF} END {print m + 0}')
  logs=$(ls "$OUT/fuzz/$t"/fuzz-*.log 2>/dev/null | wc -l)
  arts=$(ls "$DIR/bin/artifacts/$t" 2>/dev/null | wc -l)
  echo "$t: exit $(cat "$OUT/fuzz/$t/status"), $logs workers, $execs executions in ${SECS} s" \
       "($((execs / SECS)) exec/s), peak RSS ${rss} MiB per worker, $arts artifacts"
  # Findings only (no llvm-symbolizer in the bundle: its warnings are noise).
  grep -h -E "ERROR: |SUMMARY: |Test unit written|==[0-9]+==" "$OUT/fuzz/$t"/fuzz-*.log 2>/dev/null |
    grep -v symbolizer | sort | uniq -c | head -20
  cp -r "$DIR/bin/artifacts/$t" "$OUT/fuzz/$t/artifacts" 2>/dev/null
done
# One archive: the call returns a limited number of files.
tar -C "$OUT" -czf "$OUT/fuzz.tgz" fuzz && rm -rf "$OUT/fuzz"
