#!/usr/bin/env bash
# The soak (issue 23): assets/scenes/soak.json, every layer kind at once, flown along
# assets/paths/soak-orbit.json (looping) while its time plays, for MINUTES (default 30) at 640x360
# on lavapipe with the validation layer, while orbis-feed plays the live drone's NMEA feed on
# udp://127.0.0.1:47100 (the port the scene names). `orbis bench --soak` samples RSS, the layers'
# GPU memory and caches, device memory, threads, descriptors and frame times, and exits 1 when
# a bound fails (memory not flat within +-5 % after the first quarter, more threads or
# descriptors, p99 rising, any validation message).
#
#   tools/soak.sh [MINUTES]      env: OUT (default build/soak), SIZE (default 640x360)
#
# Writes OUT/soak.json (every sample, the checks, each layer's status), OUT/soak.png (the
# timelines) and OUT/soak.log (orbis-feed's and orbis's messages). Needs a build (tools/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-30}"
out="${OUT:-build/soak}"
size="${SIZE:-640x360}"
case "$minutes" in ''|*[!0-9.]*) echo "soak.sh: MINUTES must be a number, got '$minutes'" >&2; exit 2;; esac
for f in build/bin/orbis build/bin/orbis-feed assets/generated/soak/survey.las assets/generated/fmv/flight.ts; do
    [ -e "$f" ] || { echo "soak.sh: $f is missing: build first (bash tools/build.sh)" >&2; exit 1; }
done
mkdir -p "$out"
seconds=$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }')
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

# The live drone: sent for the whole run, stopped however this script ends.
build/bin/orbis-feed --udp 127.0.0.1:47100 --centre 9.03,46.02 --radius 900 --height 1100 --seconds $((seconds + 120)) \
    > "$out/soak.log" 2>&1 &
feed=$!
trap 'kill $feed 2>/dev/null || true; wait $feed 2>/dev/null || true' EXIT

status=0
build/bin/orbis bench assets/scenes/soak.json --soak "$seconds" --size "$size" --device cpu --validation \
    --camera-path assets/paths/soak-orbit.json --plot "$out/soak.png" --json > "$out/soak.json" 2>> "$out/soak.log" || status=$?
grep -v '^\[' "$out/soak.log" | grep 'soak of' >&2 || true
echo "soak.sh: $minutes min, exit $status: $out/soak.json, $out/soak.png, $out/soak.log"
exit $status
