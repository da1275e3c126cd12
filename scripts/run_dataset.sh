#!/usr/bin/env bash
# Runs the whole system on an ASL/EuRoC recording and evaluates it:
#
#   bash scripts/run_dataset.sh DIR [--start S] [--duration S] [--rate-divisor auto|N] [--max-rate HZ]
#                               [--convert-only] [ARG:=VALUE ...]
#
# DIR is the folder holding mav0/ (or mav0 itself). Builds the workspace when
# the converter is missing (scripts/setup.sh), converts the recording to a
# bag once (hapi_dataset's asl_to_bag; cached under $HAPI_DATASET_CACHE,
# default <ws>/dataset_cache, keyed by folder and options), replays it through
# scripts/run_pipeline.sh and leaves report.yaml, the PNG plots, the
# trajectories and the logs in $HAPI_RUN_DIR (default <ws>/run/<recording>).
# --start/--duration [s] select a window after the first stereo frame,
# --rate-divisor N keeps every N-th stereo frame; auto (the default) the
# smallest N that brings the recording's stereo rate to at most --max-rate
# (default $HAPI_MAX_STEREO_HZ or 10 Hz: what the CPU front end holds on two
# cores; docs/RUNNING.md "EuRoC/ASL recordings"), 5 % of timing jitter
# allowed. --convert-only prints the bag's path as its last line and stops
# (tools/eval/accuracy.py --recording). ARG:=VALUE pairs go to
# launch/replay.launch (e.g. motion_model:=inertial where declared); the
# dense depth and the surface are off unless dense_depth:=true and
# surface:=true are among them (their defaults are the skin's).
# A recording without mav0/scene.yaml has no known geometry: its map error
# is not scored. Exit status: that of run_pipeline.sh (0 within bounds,
# 1 something missing, 2 a metric outside its bound); 1 for bad arguments.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV || true

die() { echo "[dataset] ERROR: $*" >&2; exit 1; }
usage="usage: $0 DIR [--start S] [--duration S] [--rate-divisor auto|N] [--max-rate HZ] [--convert-only] [ARG:=VALUE ...]"

[ $# -ge 1 ] || die "$usage"
SRC="$(cd "$1" 2>/dev/null && pwd)" || die "'$1' is not a folder"
shift
if [ -d "$SRC/mav0/cam0" ]; then MAV0="$SRC/mav0"; NAME="$(basename "$SRC")"
elif [ -d "$SRC/cam0" ]; then MAV0="$SRC"; NAME="$(basename "$(dirname "$SRC")")"
else die "neither '$SRC' nor '$SRC/mav0' holds cam0/ (an ASL/EuRoC recording)"; fi

CONVERT_ARGS=()
LAUNCH_ARGS=()
DIVISOR=auto
MAX_HZ="${HAPI_MAX_STEREO_HZ:-10}"
CONVERT_ONLY=0
while [ $# -gt 0 ]; do
  case "$1" in
    --start|--duration|--rate-divisor|--max-rate)
      [ $# -ge 2 ] || die "missing value for $1"
      case "$1" in
        --rate-divisor) DIVISOR="$2" ;;
        --max-rate) MAX_HZ="$2" ;;
        *) CONVERT_ARGS+=("$1" "$2") ;;
      esac
      shift 2 ;;
    --convert-only) CONVERT_ONLY=1; shift ;;
    *:=*) LAUNCH_ARGS+=("$1"); shift ;;
    *) die "unknown argument '$1'; $usage" ;;
  esac
done

# The recording's stereo rate (cam0 stamps) and the divisor that keeps at
# most MAX_HZ of it: a front end slower than the camera drops frames.
if ! [[ "$MAX_HZ" =~ ^[0-9]+([.][0-9]+)?$ ]] || ! awk -v m="$MAX_HZ" 'BEGIN { exit !(m > 0) }'; then
  die "--max-rate '$MAX_HZ' is not a positive rate [Hz]"
fi
[ -f "$MAV0/cam0/data.csv" ] || die "$MAV0/cam0 has no data.csv"
REC_HZ="$(awk -F, '!/^#/ && NF >= 2 { if (n == 0) t0 = $1; t1 = $1; n++ }
  END { if (n > 1 && t1 > t0) printf "%.3f", (n - 1) * 1e9 / (t1 - t0); else print 0 }' "$MAV0/cam0/data.csv")"
if [ "$DIVISOR" = auto ]; then
  DIVISOR="$(awk -v r="$REC_HZ" -v m="$MAX_HZ" 'BEGIN { d = r / m - 0.05; n = int(d); if (n < d) n++; print (n < 1 ? 1 : n) }')"
fi
[[ "$DIVISOR" =~ ^[1-9][0-9]*$ ]] || die "--rate-divisor '$DIVISOR' is neither auto nor a positive integer"
# Divisor 1 is the converter's default: left out, so the cache key is that of a plain conversion.
[ "$DIVISOR" = 1 ] || CONVERT_ARGS+=(--rate-divisor "$DIVISOR")
STEREO_HZ="$(awk -v r="$REC_HZ" -v d="$DIVISOR" 'BEGIN { printf "%.2f", r / d }')"
echo "[dataset] stereo rate: $STEREO_HZ Hz (--rate-divisor $DIVISOR of the recording's $REC_HZ Hz; at most $MAX_HZ Hz)"

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
if [ "$CONVERT_ONLY" = 1 ]; then
  echo "$BAG"
  exit 0
fi

# The dense depth searches 0.15-0.5 m and the surface's volume is a skin
# patch (their defaults, docs/SURFACE.md): on a room-sized recording they
# fuse nothing and only take the CPU that the front end and the filter need
# (frames dropped). Off unless asked for with dense_depth:=true surface:=true.
for part in dense_depth surface; do
  case " ${LAUNCH_ARGS[*]-} " in
    *" $part:="*) ;;
    *) LAUNCH_ARGS+=("$part:=false")
       echo "[dataset] $part off (its defaults are the skin's at 0.15-0.5 m; $part:=true turns it on)" ;;
  esac
done

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
