#!/usr/bin/env bash
# The benchmark figures of the volume, point-cloud and model issues in one run, on whatever device
# `orbis bench` picks (the first discrete GPU, else lavapipe; DEVICE=cpu forces lavapipe). Volumes:
# the synthetic 256^3 field, ECHAM5 (when ../shared is there) and the VTK peer's scenes, DVR / iso /
# slices at 1920x1080 and 960x540, the step sweep and the isosurface error. Points:
# tools/bench-points.sh. Models: 0, 1, 100 and 1000 wagons on the train track, and 1, 100, 1000
# animated ones.
#   usage: tools/bench-suite.sh [BUILD_DIR]
#   env: PARTS="vol pts train" OUT=DIR (plots and images) FRAMES=30 BIG=0 (see bench-points.sh)
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
orbis="$build/bin/orbis"
parts=" ${PARTS:-vol pts train} " out="${OUT:-$build/bench-suite}" frames="${FRAMES:-30}"
scenes="$out/scenes"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
mkdir -p "$out" "$XDG_RUNTIME_DIR"
python3 "$here/tools/gen/bench-scenes.py" "$scenes" ${ECHAM5:+--echam5 "$ECHAM5"} ${DEM:+--dem "$DEM"} || exit 1
dev=(); [ -n "${DEVICE:-}" ] && dev=(--device "$DEVICE")
bench() { echo "== orbis bench $*"; timeout 600 "$orbis" bench "${dev[@]}" "$@" 2>&1 | grep -v "^\[orbis\] \(debug\|trace\)"; }
"$orbis" info "${dev[@]}" | head -8
if [[ "$parts" == *" vol "* ]]; then
    for size in 1920x1080 960x540; do
        for c in synth-dvr synth-iso synth-slice echam5-dvr echam5-iso echam5-slice peer-dvr peer-iso; do
            [ -f "$scenes/$c.json" ] && bench "$scenes/$c.json" --size "$size" --frames "$frames" --warmup 5
        done
    done
    bench "$scenes/synth-dvr.json" --sweep steps=1600,25,50,100,200,400 --size 1920x1080 \
        --frames "$frames" --warmup 3 --plot "$out/volume-steps.png"
    bench "$scenes/peer-iso.json" --iso-error 25,50,100,200,400 --size 1920x1080 --frames 10 --warmup 2
fi
if [[ "$parts" == *" pts "* ]]; then
    BIG="${BIG:-0}" FRAMES="$frames" bash "$here/tools/bench-points.sh" "$build"
fi
if [[ "$parts" == *" train "* ]]; then
    for n in 0 1 100 1000; do bench "$scenes/train-$n.json" --frames 40 --warmup 5; done
    for n in 1 100 1000; do bench "$scenes/train-anim-$n.json" --frames 40 --warmup 5; done
fi
