#!/usr/bin/env bash
# Vector benchmarks (issue 22), the README's figures: the default scene with its vector layer
# hidden and shown (the layer's cost), then generated data (orbis-make-vector, written once into
# build/bench-data, ignored by git) over the generated world terrain, seen from 6 km: 100 000
# buildings draped, extruded, extruded on the FMV valley's hills; the same extruded and paged;
# 1 M road vertices whole and paged. Each pair alternates, PAIRS times. BIG=1 adds 1 M
# buildings (maxRange 10 km) and 20 M road vertices (maxRange 50 km; 424 MB of GeoPackage),
# whole and paged. Then error against run time: the drape's simplifyPx and maxLevel swept on the
# default scene looking at Europe. Peak RSS from /usr/bin/time when it is installed.
#   usage: tools/bench-vector.sh [BUILD_DIR]   env: PAIRS=3 FRAMES=5 SIZE=1920x1080 BIG=0
#   ONLY=default|city|roads|sweeps|big (one part)
#   DEVICE=cpu|discrete|... (orbis bench --device; default: the first discrete GPU, else lavapipe)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
data="$build/bench-data"
pairs="${PAIRS:-3}" frames="${FRAMES:-5}" size="${SIZE:-1920x1080}" big="${BIG:-0}" only="${ONLY:-}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
dev=(); [ -n "${DEVICE:-}" ] && dev=(--device "$DEVICE")
mkdir -p "$data" "$XDG_RUNTIME_DIR"
world="$here/assets/generated"
[ -f "$world/world-relief.tif" ] || { echo "bench-vector: $world/world-relief.tif is missing (build the project first)" >&2; exit 1; }

# scene OUT VECTOR_JSON PITCH [DEM]: a vector layer over the generated world terrain (or DEM).
scene() {
    local out="$data/$1.json" vector="$2" pitch="$3" dem="${4:-$world/world-relief.tif}"
    cat > "$out" <<JSON
{"orbis": 1, "name": "bench-vector $1",
 "viewpoint": {"lon": 9.0, "lat": 46.0, "heading": 20, "pitch": $pitch, "range": 6000},
 "time": {"start": "2026-06-21T10:00:00Z", "end": "2026-06-21T10:00:00Z"},
 "layers": [{"type": "terrain", "name": "World", "elevation": ["$dem"], "imagery": [{"path": "$world/world-colour.tif"}]},
            $vector]}
JSON
    echo "$out"
}
# run LABEL SCENE: one line: label, frame median, load, peak RSS
run() {
    local label="$1" s="$2" out rss=""
    if [ -x /usr/bin/time ]; then
        out=$(/usr/bin/time -v "$build/bin/orbis" bench "${dev[@]}" "$s" --size "$size" --frames "$frames" --warmup 2 2>&1)
        rss=$(awk '/Maximum resident/{printf "%.0f MB", $6/1024}' <<<"$out")
    else
        out=$("$build/bin/orbis" bench "${dev[@]}" "$s" --size "$size" --frames "$frames" --warmup 2 2>&1)
    fi
    local frame load gpu caches
    frame=$(awk '/frame \(wall\)/{print $4}' <<<"$out")
    load=$(sed -n 's/.*everything in view after \([0-9.]*\) s.*/\1 s/p' <<<"$out")
    gpu=$(sed -n "s/.*layers' GPU \([0-9.]*\) MB max, layers' caches \([0-9.]*\) MB max.*/GPU \1 MB, caches \2 MB/p" <<<"$out")
    printf '%-34s frame %8s ms   loaded %-8s peak RSS %-8s %s\n' "$label" "$frame" "$load" "$rss" "$gpu"
}
pair() {   # pair LABEL_A SCENE_A LABEL_B SCENE_B, PAIRS times
    for _ in $(seq "$pairs"); do run "$1" "$2"; run "$3" "$4"; done
}
versus() {   # versus LABEL NAME LAYER FILE STYLE PITCH: one source whole and paged, in pairs
    local label="$1" name="$2" layer="$3" file="$4" style="$5" pitch="$6" whole paged
    whole=$(scene "$name-whole" "{\"type\": \"vector\", \"name\": \"$layer\", \"path\": \"$file\", \"paging\": false, $style}" "$pitch")
    paged=$(scene "$name-paged" "{\"type\": \"vector\", \"name\": \"$layer\", \"path\": \"$file\", \"paging\": true, $style}" "$pitch")
    pair "$label, whole" "$whole" "$label, paged" "$paged"
}
city() {   # city N -> the GeoPackage
    local f="$data/city-$1.gpkg"
    [ -f "$f" ] || "$build/bin/orbis-make-vector" city --buildings "$1" --out "$f" >&2
    echo "$f"
}
roads() {  # roads N -> the GeoPackage
    local f="$data/roads-$1.gpkg"
    [ -f "$f" ] || "$build/bin/orbis-make-vector" network --vertices "$1" --out "$f" >&2
    echo "$f"
}

if [ -z "$only" ] || [ "$only" = default ]; then
    off="$data/default-off.json"
    python3 - "$here/assets/scenes/default.json" "$off" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
next(l for l in s['layers'] if l['type'] == 'vector')['visible'] = False
json.dump(s, open(sys.argv[2], 'w'), indent=1)
PY
    echo "== the default scene, $size, its vector layer hidden and shown (--frames 10)"
    saved="$frames"; frames=10
    pair "default, vector hidden" "$off" "default, vector shown" "$here/assets/scenes/default.json"
    frames="$saved"
fi
if [ -z "$only" ] || [ "$only" = city ]; then
    c=$(city 100000)
    style='"style": {"fill": [0.86, 0.8, 0.7], "color": [0.3, 0.3, 0.3], "width": 1}'
    xstyle='"style": {"fill": [0.86, 0.8, 0.7], "extrude": "height"}'
    echo "== 100 000 buildings from 6 km, 45 degrees down"
    draped=$(scene city-draped "{\"type\": \"vector\", \"name\": \"City\", \"path\": \"$c\", $style}" -45)
    hills=$(scene city-hills "{\"type\": \"vector\", \"name\": \"City\", \"path\": \"$c\", $xstyle}" -45 \
        "$world/fmv/flight-dem.tif")
    run "100k buildings draped" "$draped"
    run "100k buildings extruded, FMV hills" "$hills"
    versus "100k buildings extruded" city City "$c" "$xstyle" -45
fi
if [ -z "$only" ] || [ "$only" = roads ]; then
    r=$(roads 1000000)
    rstyle='"style": {"color": [0.92, 0.92, 0.88], "width": 1.5}'
    echo "== 1 M road vertices from 6 km, 60 degrees down"
    versus "1M road vertices" roads Roads "$r" "$rstyle" -60
fi
if [ -z "$only" ] || [ "$only" = sweeps ]; then
    europe="$data/default-europe.json"
    python3 - "$here/assets/scenes/default.json" "$europe" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s['viewpoint'] = {"lon": 10.0, "lat": 50.0, "height": 0, "heading": 0, "pitch": -30, "range": 2500000}
json.dump(s, open(sys.argv[2], 'w'), indent=1)
PY
    echo "== error against run time: the default scene looking at Europe from 2500 km, 60 degrees from the vertical"
    "$build/bin/orbis" bench "${dev[@]}" "$europe" --size "$size" --frames "$frames" --sweep simplifyPx=0.5,1,2,4,8,16 \
        --plot "$build/vector-simplify.png"
    "$build/bin/orbis" bench "${dev[@]}" "$europe" --size "$size" --frames "$frames" --sweep maxLevel=18,6,5,4,3 \
        --plot "$build/vector-maxlevel.png"
fi
[ "$big" = 1 ] || [ "$only" = big ] || exit 0
c=$(city 1000000)
xstyle='"style": {"fill": [0.86, 0.8, 0.7], "extrude": "height", "maxRange": 10000}'
echo "== 1 M buildings (maxRange 10 km) from 6 km, 45 degrees down"
versus "1M buildings" city1m City "$c" "$xstyle" -45
r=$(roads 20000000)
rstyle='"style": {"color": [0.92, 0.92, 0.88], "width": 1.5, "maxRange": 50000}'
echo "== 20 M road vertices (maxRange 50 km) from 6 km, 60 degrees down"
versus "20M road vertices" roads20m Roads "$r" "$rstyle" -60
