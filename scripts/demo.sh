#!/usr/bin/env bash
# The main job on the embedded default data, headless, no network beyond
# Debian's packages: build everything, generate the synthetic globe bag if it
# is missing, run the pipeline on it and print what it measured.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HAPI_WS:-$REPO/.ws}"
DATA="${HAPI_DATA:-$REPO/.data}"
BAG="$DATA/globe.bag"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"

HAPI_WS="$WS" bash "$REPO/scripts/setup.sh"
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

mkdir -p "$DATA"
if [ ! -s "$BAG" ]; then
  echo "[demo] generating the globe bag: $BAG"
  rosrun hapi_sim make_globe_bag --output "$BAG.tmp" --seed 1 --duration 25 --rate 10 --imu 1
  mv "$BAG.tmp" "$BAG"
fi
rosbag info "$BAG"

# The globe's depth range and surface volume (config/*_globe.yaml; the
# nodelets' defaults are the skin scan's).
exec bash "$REPO/scripts/run_pipeline.sh" "$BAG" dense_depth_config:="$REPO/config/dense_depth_globe.yaml" \
  surface_config:="$REPO/config/surface_globe.yaml"
