#!/usr/bin/env bash
# PostGIS benchmarks (issue 24), the README's figures, against the demo's server
# (tools/serve-demo.sh --serve, vehicles still: FEEDER=0), stopped at the end:
#   1. 1 M generated building polygons (orbis-make-vector, written once into build/bench-data,
#      ignored by git) loaded into PostGIS (ogr2ogr, GiST index), then read by the vector
#      layer's reader from the GeoPackage and from PostGIS, in one run: features per second for
#      the whole source, one level-14 tile, one page (orbis bench --vector);
#   2. the time to the first frame and to a settled view of the same 1 M, paged, from each
#      (orbis bench SCENE: "first content" and "settled");
#   3. the latency from a committed UPDATE to the frame that shows it, LIVE times (default 100),
#      one vehicle moved each time (orbis bench --live), at SIZE (default 640x360).
#   usage: tools/bench-postgis.sh [BUILD_DIR]   env: LIVE=100 SIZE=640x360 RUNS=3 ONLY=read|frame|live
#   GLIDE=auto|false|SECONDS (the vehicles' "glide" for the latency; default the scene's auto)
#   DEVICE=cpu|discrete|... (orbis bench --device; default: the first discrete GPU, else lavapipe)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
data="$build/bench-data"
live="${LIVE:-100}" size="${SIZE:-640x360}" runs="${RUNS:-3}" only="${ONLY:-}"
dev=(); [ -n "${DEVICE:-}" ] && dev=(--device "$DEVICE")
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
mkdir -p "$data" "$XDG_RUNTIME_DIR"
gpkg="$data/city-1m.gpkg"
[ -f "$gpkg" ] || "$build/bin/orbis-make-vector" city --buildings 1000000 --out "$gpkg" --centre 9.0,46.0 >/dev/null

log=$(mktemp)
FEEDER=0 bash "$here/tools/serve-demo.sh" --serve >"$log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null; rm -f "$log"' EXIT
for _ in $(seq 1 120); do grep -q "^serve-demo: for other programs" "$log" && break; sleep 0.5; done
eval "$(grep -o 'export PG.*' "$log")" || { cat "$log" >&2; exit 1; }
grep "^serve-demo: PostgreSQL" "$log"

if [ -z "$only" ] || [ "$only" != live ]; then
    t0=$(date +%s.%N)
    ogr2ogr -f PostgreSQL "PG:dbname=orbis" "$gpkg" buildings -nln buildings_1m -lco GEOMETRY_NAME=geom -gt 65536
    psql -q -c "ANALYZE buildings_1m"
    echo "bench-postgis: 1 M polygons loaded into PostGIS (ogr2ogr, GiST index, ANALYZE) in $(echo "$(date +%s.%N) - $t0" | bc) s"
fi
if [ -z "$only" ] || [ "$only" = read ]; then
    "$build/bin/orbis" bench --vector "$gpkg" --runs "$runs"
    "$build/bin/orbis" bench --vector "PG:dbname=orbis tables=buildings_1m" --runs "$runs"
fi
if [ -z "$only" ] || [ "$only" = frame ]; then
    # The 1 M buildings draped, paged, over the demo's hills, from 6 km.
    for source in "$gpkg" "PG:dbname=orbis"; do
        scene="$data/postgis-1m.json"
        cat >"$scene" <<JSON
{"orbis": 1, "name": "bench-postgis 1 M buildings",
 "viewpoint": {"lon": 9.0, "lat": 46.0, "heading": 20, "pitch": -50, "range": 6000},
 "time": {"start": "2026-06-21T10:00:00Z", "end": "2026-06-21T10:00:00Z"},
 "layers": [{"type": "terrain", "name": "World", "elevation": ["$here/assets/generated/world-relief.tif"],
             "imagery": [{"path": "$here/assets/generated/world-colour.tif"}]},
            {"type": "vector", "name": "Buildings", "path": "$source", "layers": ["$( [ "$source" = "$gpkg" ] && echo buildings || echo buildings_1m)"],
             "paging": true, "style": {"fill": [0.9, 0.8, 0.6], "color": [0.4, 0.3, 0.2], "width": 1}}]}
JSON
        echo "bench-postgis: first frame and settled view, 1 M buildings paged from $source"
        "$build/bin/orbis" bench "${dev[@]}" "$scene" --size 1280x720 --frames 5 --warmup 1 | grep -E "load|frame|device" || true
    done
fi
if [ -z "$only" ] || [ "$only" = live ]; then
    echo "bench-postgis: commit to changed frame, $live updates of one vehicle each (assets/scenes/postgis-live.json, $size)"
    scene="$here/assets/scenes/postgis-live.json"
    if [ "${GLIDE:-auto}" != auto ]; then   # the vehicles' glide set otherwise (false: they jump)
        scene="$data/postgis-live-glide-$GLIDE.json"
        sed -e "s|\"glide\": \"auto\"|\"glide\": $GLIDE|" -e "s|\.\./generated/|$here/assets/generated/|g" \
            "$here/assets/scenes/postgis-live.json" > "$scene"
    fi
    "$build/bin/orbis" bench "${dev[@]}" "$scene" --size "$size" --live "$live" \
        --update "UPDATE vehicles SET geom = ST_Translate(geom, 0.0004 * (({i} % 2) * 2 - 1), 0) WHERE id = {i} % 40 + 1"
fi
