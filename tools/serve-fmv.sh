#!/usr/bin/env bash
# Four live UAV feeds for the live FMV scene (assets/scenes/fmv-live.json): the fixture's flight
# (orbis-make-fmv --stream) sent in real time over UDP to 127.0.0.1:5601..5604, each from
# another place on the lap, 640x480 at 10 fps with synchronous KLV (the fourth asynchronous),
# time-stamped with the wall clock (the layers' status then shows the glass-to-drape latency).
# Runs until Ctrl+C (or `tools/serve-fmv.sh SECONDS`), then stops every sender.
#   tools/serve-fmv.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
make=build/bin/orbis-make-fmv
[ -x "$make" ] || { echo "serve-fmv: $make: not built (tools/build.sh)" >&2; exit 1; }
frames=0
[ $# -ge 1 ] && frames=$(( $1 * 10 ))
pids=()
trap 'kill "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true' EXIT INT TERM
for i in 1 2 3 4; do
  extra=()
  [ "$i" = 4 ] && extra=(--async)
  "$make" --stream "udp://127.0.0.1:560$i" --frames "$frames" --size 640x480 --flight-start $(( (i - 1) * 60 )) --wall-clock "${extra[@]}" &
  pids+=($!)
done
echo "serve-fmv: 4 feeds on udp://127.0.0.1:5601..5604; open assets/scenes/fmv-live.json"
wait
