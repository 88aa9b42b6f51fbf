#!/usr/bin/env bash
# Model loading (issue 27): one large mesh (a terrain patch of TRIANGLES triangles written by
# orbis-make-mesh through Assimp's exporters) in each format the model layer reads, against the
# same mesh as glTF (.glb): the time to read it into the model layer's form (`orbis info`'s
# readSeconds) and the peak RSS of the process, RUNS runs each, formats alternating.
#   usage: tools/bench-models.sh [BUILD_DIR]   env: TRIANGLES=2000000 RUNS=3
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
triangles="${TRIANGLES:-2000000}" runs="${RUNS:-3}"
data="$build/bench-data/meshes"
mkdir -p "$data"
formats=(glb obj ply stl dae fbx)
for f in "${formats[@]}"; do
    [ -f "$data/mesh-$triangles.$f" ] || "$build/bin/orbis-make-mesh" --triangles "$triangles" --out "$data/mesh-$triangles.$f"
done
echo "== $triangles triangles; seconds to read, peak RSS (MB); $runs runs"
declare -A secs rss
for run in $(seq "$runs"); do
    for f in "${formats[@]}"; do
        out="$( { /usr/bin/time -f "RSS %M" "$build/bin/orbis" info "$data/mesh-$triangles.$f"; } 2>&1 )"
        secs[$f]+="$(echo "$out" | python3 -c 'import json,sys; t=sys.stdin.read(); print(json.loads(t[:t.rindex("}")+1])["readSeconds"])') "
        rss[$f]+="$(echo "$out" | awk '/^RSS/ {print int($2 / 1024)}') "
    done
done
for f in "${formats[@]}"; do
    printf "%-4s %8s MB file   read %s s   RSS %s MB\n" "$f" "$(( $(stat -c %s "$data/mesh-$triangles.$f") >> 20 ))" \
        "$(echo "${secs[$f]}" | tr ' ' '\n' | sed '/^$/d' | sort -g | paste -sd' ')" "$(echo "${rss[$f]}" | tr ' ' '\n' | sed '/^$/d' | sort -n | paste -sd' ')"
done
