#!/usr/bin/env bash
# Side by side with the VTK peer (../shared/peers/vtk_peer.py: VTK 9.1's GPU ray-cast mapper on
# llvmpipe): the same field, size, samples per diagonal, transfer function and view, run
# alternately (VTK, Orbis, VTK, Orbis, ...) so that both see the same machine. Prints one line
# per run and the medians of the per-run medians (ms per frame: VTK Render + glFinish; Orbis
# the whole frame until the GPU is done).
#   usage: tools/peer-volume.sh [BUILD_DIR]   env: SIZE=1920x1080 REPEATS=3 FRAMES=10 CASES="volume iso"
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
peer="$here/../shared/peers/vtk_peer.py"
size="${SIZE:-1920x1080}" repeats="${REPEATS:-3}" frames="${FRAMES:-10}" cases="${CASES:-volume iso}"
[ -f "$peer" ] || { echo "peer-volume: $peer not found (../shared is needed)" >&2; exit 2; }
/usr/bin/python3 -c 'import vtk' 2>/dev/null || {
    echo "peer-volume: VTK for /usr/bin/python3 is missing: apt-get install python3-vtk9 xvfb xauth" >&2; exit 2; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}" LIBGL_ALWAYS_SOFTWARE=1
mkdir -p "$XDG_RUNTIME_DIR" /tmp/vtk-peer-out
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
declare -A results
for rep in $(seq "$repeats"); do
    for c in $cases; do
        scene="$here/assets/scenes/volume-peer.json"
        [ "$c" = iso ] && scene="$here/assets/scenes/volume-peer-iso.json"
        v=$(xvfb-run -a -s "-screen 0 1920x1080x24" /usr/bin/python3 "$peer" --case "$c" --size "$size" \
              --frames "$frames" --warmup 2 --dim 256 --out "/tmp/vtk-peer-out/vtk_${c}_${size}.png" 2>/dev/null |
            /usr/bin/python3 -c 'import json,sys; print(json.loads(sys.stdin.readline())["median_ms"])')
        o=$("$build/bin/orbis" bench "$scene" --size "$size" --frames "$frames" --warmup 2 --json 2>/dev/null |
            /usr/bin/python3 -c 'import json,sys; print(round(json.load(sys.stdin)["frame_ms"]["median"], 1))')
        echo "run $rep  $c  $size  vtk $v ms  orbis $o ms"
        results[$c.vtk]+="$v "
        results[$c.orbis]+="$o "
    done
done
for c in $cases; do
    v=$(echo ${results[$c.vtk]} | tr ' ' '\n' | median)
    o=$(echo ${results[$c.orbis]} | tr ' ' '\n' | median)
    echo "$c $size: vtk $v ms, orbis $o ms, vtk/orbis $(awk -v a="$v" -v b="$o" 'BEGIN {printf "%.2f", a / b}')"
done
