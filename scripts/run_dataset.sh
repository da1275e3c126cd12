#!/usr/bin/env bash
# Runs the whole system on an ASL/EuRoC recording and evaluates it:
#
#   bash scripts/run_dataset.sh DIR [--start S] [--duration S] [--rate-divisor N] [ARG:=VALUE ...]
#
# DIR is the folder holding mav0/ (or mav0 itself). Builds the workspace when
# the converter is missing (scripts/setup.sh), converts the recording to a
# bag once (hapi_dataset's asl_to_bag; cached under $HAPI_DATASET_CACHE,
# default <ws>/dataset_cache, keyed by folder and options), replays it through
# scripts/run_pipeline.sh and leaves report.yaml, the PNG plots, the
# trajectories and the logs in $HAPI_RUN_DIR (default <ws>/run/<recording>).
# --start/--duration [s] select a window after the first stereo frame,
# --rate-divisor N keeps every N-th stereo frame. ARG:=VALUE pairs go to
# launch/replay.launch (e.g. motion_model:=inertial where declared).
# A recording without mav0/scene.yaml has no known geometry: its map error
# is not scored. Exit status: that of run_pipeline.sh (0 within bounds,
# 1 something missing, 2 a metric outside its bound); 1 for bad arguments.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true

die() { echo "[dataset] ERROR: $*" >&2; exit 1; }
usage="usage: $0 DIR [--start S] [--duration S] [--rate-divisor N] [ARG:=VALUE ...]"

[ $# -ge 1 ] || die "$usage"
SRC="$(cd "$1" 2>/dev/null && pwd)" || die "'$1' is not a folder"
shift
if [ -d "$SRC/mav0/cam0" ]; then MAV0="$SRC/mav0"; NAME="$(basename "$SRC")"
elif [ -d "$SRC/cam0" ]; then MAV0="$SRC"; NAME="$(basename "$(dirname "$SRC")")"
else die "neither '$SRC' nor '$SRC/mav0' holds cam0/ (an ASL/EuRoC recording)"; fi

CONVERT_ARGS=()
LAUNCH_ARGS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --start|--duration|--rate-divisor)
      [ $# -ge 2 ] || die "missing value for $1"
      CONVERT_ARGS+=("$1" "$2"); shift 2 ;;
    *:=*) LAUNCH_ARGS+=("$1"); shift ;;
    *) die "unknown argument '$1'; $usage" ;;
  esac
done

if [ ! -x "$WS/devel/lib/hapi_dataset/asl_to_bag" ]; then
  echo "[dataset] building the workspace (scripts/setup.sh)"
  HAPI_WS="$WS" bash "$REPO/scripts/setup.sh"
fi
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

# One bag per recording and option set; rebuilt when the converter is newer.
CACHE="${HAPI_DATASET_CACHE:-$WS/dataset_cache}"
mkdir -p "$CACHE"
KEY="$(printf '%s\n' "$MAV0" "${CONVERT_ARGS[@]}" | sha1sum | cut -c1-12)"
BAG="$CACHE/$NAME-$KEY.bag"
CONVERTER="$WS/devel/lib/hapi_dataset/asl_to_bag"
if [ ! -s "$BAG" ] || [ "$CONVERTER" -nt "$BAG" ]; then
  echo "[dataset] converting $MAV0 -> $BAG"
  "$CONVERTER" --asl "$MAV0" --output "$BAG.tmp" "${CONVERT_ARGS[@]}" || { rm -f "$BAG.tmp"; die "conversion failed"; }
  mv "$BAG.tmp" "$BAG"
else
  echo "[dataset] using the converted bag $BAG"
fi

export HAPI_RUN_DIR="${HAPI_RUN_DIR:-$WS/run/$NAME}"
if [ ! -f "$MAV0/scene.yaml" ]; then
  export HAPI_SUMMARY_ARGS="${HAPI_SUMMARY_ARGS:-} --map-error if-known"
fi
set +e
bash "$REPO/scripts/run_pipeline.sh" "$BAG" "${LAUNCH_ARGS[@]}"
rc=$?
set -e
echo "[dataset] results in $HAPI_RUN_DIR (report.yaml, plots, estimate.tum, ground_truth.tum)"
exit "$rc"
