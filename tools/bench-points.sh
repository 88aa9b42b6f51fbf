#!/usr/bin/env bash
# Point-cloud benchmarks (issue 5): synthetic surveys of 1 M, 5 M and 20 M points (orbis-make-las,
# written once into build/bench-data, ignored by git) filling the view at 1920x1080, every point
# drawn ("pointBudget": 0), the compute rasteriser against the point-list pipeline side by side
# in one run (--sweep renderer=0,1), then the point budget's error against run time on 5 M, then
# a cloud larger than the CPU budget (BIG million points, 0 to skip; 3.4 GB of LAS for 100):
# octree cache built on first load (its time and peak RSS), then loaded from the cache.
#   usage: tools/bench-points.sh [BUILD_DIR]   env: SIZES="1 5 20" FRAMES=10 SIZE=1920x1080 BIG=100
#   DEVICE=cpu|discrete|... (orbis bench --device; default: the first discrete GPU, else lavapipe)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
data="$build/bench-data"
sizes="${SIZES:-1 5 20}" frames="${FRAMES:-10}" size="${SIZE:-1920x1080}" big="${BIG:-100}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
dev=(); [ -n "${DEVICE:-}" ] && dev=(--device "$DEVICE")
mkdir -p "$data" "$XDG_RUNTIME_DIR"
scene() {   # scene FILE.las BUDGET [ORDER] [ADAPTIVE] -> a scene file next to it
    local las="$1" budget="$2" order="${3:-morton}" adaptive="${4:-false}" out="${1%.las}-$2-${3:-morton}-${4:-false}.json"
    cat > "$out" <<JSON
{"name": "Synthetic survey ($(basename "$las"))",
 "viewpoint": {"lon": 9.0, "lat": 46.0087, "height": 820, "heading": 20, "pitch": -55, "range": 1900},
 "fovDeg": 45, "time": {"start": "2026-06-21T09:00:00Z", "end": "2026-06-21T09:00:00Z"}, "background": [0, 0, 0],
 "layers": [{"type": "points", "name": "Survey", "path": "$las", "pointBudget": $budget, "gpuMemoryMB": 1536, "pointOrder": "$order", "adaptiveSize": $adaptive}]}
JSON
    echo "$out"
}
for m in $sizes; do
    las="$data/survey-${m}m.las"
    [ -f "$las" ] || "$build/bin/orbis-make-las" --points "${m}000000" --out "$las"
    echo "== $m M points, compute (0) vs point list (1), $size"
    "$build/bin/orbis" bench "${dev[@]}" "$(scene "$las" 0)" --size "$size" --frames "$frames" --warmup 2 --sweep renderer=0,1
done
# Points in a node in Z order against the octree's random key order (issue 26), every point
# drawn, runs alternating so that the machine's drift hits both alike.
for m in $sizes; do
    las="$data/survey-${m}m.las"
    for run in 1 2; do
        for order in random morton; do
            echo "== $m M points, $order order, run $run, $size"
            "$build/bin/orbis" bench "${dev[@]}" "$(scene "$las" 0 "$order")" --size "$size" --frames "$frames" --warmup 2 | grep -E "frame|gpu|points" | head -4
        done
    done
done
[ "${ORDER_ONLY:-0}" = 1 ] && exit 0
las="$data/survey-5m.las"
[ -f "$las" ] || "$build/bin/orbis-make-las" --points 5000000 --out "$las"
for adaptive in false true; do
    echo "== point budget on 5 M points (reference: all), level-aware sizes $adaptive, $size"
    "$build/bin/orbis" bench "${dev[@]}" "$(scene "$las" 0 morton "$adaptive")" --size "$size" --frames "$frames" --warmup 2 \
        --sweep pointBudget=0,3000000,1000000,300000,100000 --plot "$build/points-budget-$adaptive.png"
done
[ "$big" = 0 ] && exit 0
las="$data/survey-${big}m.las"
[ -f "$las" ] || "$build/bin/orbis-make-las" --points "${big}000000" --out "$las"
rm -f "$las.orbis-points"
for run in "building the octree cache" "from the cache"; do
    echo "== $big M points, budget 3 M, $run, $size"
    "$build/bin/orbis" -v bench "${dev[@]}" "$(scene "$las" 3000000)" --size "$size" \
        --frames "$frames" --warmup 2 2>&1 | grep -v "^\[orbis\] \(debug\|trace\)"
done
