#!/usr/bin/env bash
# FMV benchmarks (issue 6): the synthetic flight (orbis-make-fmv, written once into
# build/bench-data/fmv, ignored by git) over its DEM at 1920x1080: the terrain alone, with one
# FMV layer and with four (four flights around the target, a quarter lap apart, all playing at
# once), then the video's CPU side (orbis bench --video: KLV packets/s, playback, exact seeks).
#   usage: tools/bench-fmv.sh [BUILD_DIR]   env: FRAMES=20 SIZE=1920x1080 HEIGHTFIELD=129
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
data="$build/bench-data/fmv"
frames="${FRAMES:-20}" size="${SIZE:-1920x1080}" hf="${HEIGHTFIELD:-129}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
mkdir -p "$data" "$XDG_RUNTIME_DIR"
for start in 0 60 120 180; do
    [ -f "$data/flight-$start/flight.ts" ] ||
        "$build/bin/orbis-make-fmv" "$data/flight-$start" --frames 300 --fps 30 --size 1280x720 --flight-start "$start" > /dev/null
done
scene() {   # scene NAME LAYERS... -> a scene file; every video starts at 09:00:00
    local out="$data/$1.json"; shift
    local layers='{"type": "terrain", "name": "Ground", "elevation": ["flight-0/flight-dem.tif"]}'
    for start in "$@"; do
        layers="$layers, {\"type\": \"fmv\", \"name\": \"UAV $start\", \"path\": \"flight-$start/flight.ts\", \"start\": \"2026-06-21T09:00:00Z\", \"heightfield\": $hf}"
    done
    cat > "$out" <<JSON
{"name": "FMV benchmark", "viewpoint": {"lon": 9.03, "lat": 46.02, "height": 650, "heading": 20, "pitch": -60, "range": 9000},
 "time": {"start": "2026-06-21T09:00:02Z", "end": "2026-06-21T09:00:09Z"}, "background": [0.1, 0.1, 0.15],
 "layers": [$layers]}
JSON
    echo "$out"
}
for run in "terrain" "one 0" "four 0 60 120 180"; do
    set -- $run
    name="$1"; shift
    echo "== $name: terrain + $# FMV layers, $size"
    "$build/bin/orbis" bench "$(scene "$name" "$@")" --size "$size" --frames "$frames" --warmup 3 | grep -E '^(orbis|frame|gpu|loading)'
done
echo "== the video's CPU side (1280x720 H.264, 30 fps, one key frame a second)"
"$build/bin/orbis" bench --video "$data/flight-0/flight.ts" --seeks 100
