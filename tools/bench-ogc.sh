#!/usr/bin/env bash
# OGC services benchmarks (issue 24), the README's figures, against the demo's MapServer and
# MapCache (tools/serve-demo.sh --serve), stopped at the end: tile throughput of the terrain's
# pager against a bare loop of GDAL reads of the same tiles on as many threads
# (orbis bench --tiles LEVEL), for the world imagery
#   - from the GeoTIFF itself (the file case, for reference),
#   - from MapServer's WMS (GetMap per block),
#   - from MapCache's WMTS (its own disk cache warm after the first run),
# cold (every tile a request, on an empty Orbis tile cache) and warm (every tile from Orbis's
# disk cache). The servers run on the same 2 cores as Orbis.
#   usage: tools/bench-ogc.sh [BUILD_DIR]   env: LEVEL=4 THREADS=(cores) RUNS=3
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
level="${LEVEL:-4}" runs="${RUNS:-3}"
threads=(); [ -n "${THREADS:-}" ] && threads=(--threads "$THREADS")
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
mkdir -p "$XDG_RUNTIME_DIR"
work=$(mktemp -d)
log=$work/serve.log
FEEDER=0 bash "$here/tools/serve-demo.sh" --serve >"$log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null; rm -rf "$work"' EXIT
for _ in $(seq 1 120); do grep -q "^serve-demo: serving" "$log" && break; sleep 0.5; done
grep -q "^serve-demo: serving" "$log" || { cat "$log" >&2; exit 1; }
port=$(grep -o 'http://127.0.0.1:[0-9]*' "$log" | head -1 | cut -d: -f3)
grep -E "^serve-demo: (MapServer|PostgreSQL)" "$log" | sed 's/^serve-demo: //' || true
scene() {   # name imagery-path
    cat >"$work/$1.json" <<JSON
{"orbis": 1, "name": "bench-ogc $1", "viewpoint": {"lon": 10, "lat": 40, "range": 12000000},
 "layers": [{"type": "terrain", "name": "World", "imagery": [{"path": "$2"}]}]}
JSON
    echo "$work/$1.json"
}
file=$(scene file "$here/assets/generated/world-colour.tif")
wms=$(scene wms "WMS:http://127.0.0.1:$port/ows?SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=world&SRS=EPSG:4326&BBOX=-180,-90,180,90&FORMAT=image/png")
wmts=$(scene wmts "WMTS:http://127.0.0.1:$port/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities,layer=world")
for r in $(seq 1 "$runs"); do
    for s in "$file" "$wms" "$wmts"; do
        echo "bench-ogc: run $r, $(basename "$s" .json)"
        "$build/bin/orbis" bench "$s" --tiles "$level" "${threads[@]}" | grep -E "pager|bare"
    done
done
