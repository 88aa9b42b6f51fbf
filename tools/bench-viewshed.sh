#!/usr/bin/env bash
# The GPU viewshed against GDAL's (issue 25), in one run on this machine:
#   1. 6 km around at 30 m cells (401 x 401) on generated hills: the GPU, GDAL's algorithm in
#      memory, the same rings on the CPU and the exact sight lines: agreement and times, then the
#      error against run time as the cells grow (orbis viewshed --compare --sweep);
#   2. 30 km around (2001 x 2001): the GPU and GDAL's algorithm in memory, then the gdal_viewshed
#      program on the same grid written as a GeoTIFF, timed whole (read, compute, write).
# On a machine with a GPU, orbis-viewshed-bench (no GDAL) gives the GPU's figures.
#   tools/bench-viewshed.sh [DEVICE]      (default: cpu, lavapipe)
set -euo pipefail
cd "$(dirname "$0")/.."
device="${1:-cpu}"
bin=build/bin
out=build/bench-data/viewshed
mkdir -p "$out"
repeat=${REPEAT:-10}
echo "== 6 km around, 30 m cells: agreement, times, error against run time"
"$bin/orbis" viewshed --synthetic 1 --observer 8.5,46.5 --radius 6000 --cell 30 --height 10 --compare --sweep --repeat "$repeat" --device "$device"
echo
echo "== 30 km around, 30 m cells"
for m in gpu gdal; do
  "$bin/orbis" viewshed --synthetic 1 --observer 8.5,46.5 --radius 30000 --cell 30 --height 10 --method "$m" --repeat 5 --device "$device" | grep "^$m"
done
"$bin/orbis" viewshed --synthetic 1 --observer 8.5,46.5 --radius 30000 --cell 30 --height 10 --repeat 1 --device "$device" \
  --grid "$out/grid.tif" > /dev/null
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2 ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2)}'; }
times() {   # times N COMMAND...: the wall time of each run in ms, one a line
  local n=$1; shift
  for _ in $(seq "$n"); do
    local s; s=$(date +%s%N); "$@" > /dev/null 2>&1; echo $(( ($(date +%s%N) - s) / 1000000 ))
  done
}
g=$(times 5 gdal_viewshed -q -ox 0 -oy 0 -oz 10 -md 30000 -cc 0.85714 "$out/grid.tif" "$out/gdal.tif" | median)
echo "programs    gdal_viewshed on the 2001 x 2001 GeoTIFF: median ${g} ms of 5 (read, compute, write)"
