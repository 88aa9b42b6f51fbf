#!/usr/bin/env bash
# Live FMV benchmarks (issue 27), on loopback: the fixture's flight sent in real time by
# orbis-make-fmv --stream (--wall-clock: each packet stamped with its send time) over UDP to
# live fmv layers over the flight's DEM, measured by `orbis bench --feeds` (glass-to-drape
# latency: send time to the frame on screen, GPU done; frames draped and footprint updates a
# second; frames lost):
#   1. one feed, then four at once;
#   2. the frame cost of four live feeds against four file feeds (the same video size and rate,
#      `orbis bench` on files playing), alternating, twice;
#   3. one feed through orbis-udp-relay dropping 1 %, 5 % and 20 % of the datagrams;
#   4. one feed over each protocol: UDP, RTP, TCP, SRT, HTTP (PROTOCOLS="udp rtp tcp srt http").
# The senders run on the same machine: their H.264 encoding takes CPU from the renderer.
#   usage: tools/bench-live-fmv.sh [BUILD_DIR]
#   env: SECONDS_EACH=20 SIZE=1280x720 (render) VIDEO=640x480 FPS=15 PORT=5700 SECTIONS="1 2 3 4"
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
data="$build/bench-data/live-fmv"
each="${SECONDS_EACH:-20}" size="${SIZE:-1280x720}" video="${VIDEO:-640x480}" fps="${FPS:-15}" port="${PORT:-5700}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
mkdir -p "$data" "$XDG_RUNTIME_DIR"
dem="$here/assets/generated/fmv/flight-dem.tif"
[ -f "$dem" ] || { echo "bench-live-fmv: $dem: not generated (tools/build.sh)" >&2; exit 1; }
pids=()
stop_all() { [ ${#pids[@]} -gt 0 ] && { kill "${pids[@]}" 2>/dev/null || true; }; wait 2>/dev/null || true; pids=(); }
trap stop_all EXIT INT TERM
frames=$(( (each + 15) * fps ))
send() {   # send PORT FLIGHT_START [URL [--listen]]
    "$build/bin/orbis-make-fmv" --stream "${3:-udp://127.0.0.1:$1}" --frames "$frames" --fps "$fps" --size "$video" \
        --flight-start "$2" --wall-clock ${4:-} > /dev/null &
    pids+=($!)
}
scene() {   # scene NAME KIND(live|file) N [EXTRA [URL]] -> a scene file with N fmv layers (EXTRA: more keys of the live ones; URL: the first one's)
    local out="$data/$1.json" kind="$2" n="$3" extra="${4:-}" url0="${5:-}" layers="{\"type\": \"terrain\", \"name\": \"Ground\", \"elevation\": [\"$dem\"]}"
    for i in $(seq 0 $(( n - 1 ))); do
        if [ "$kind" = live ]; then
            layers="$layers, {\"type\": \"fmv\", \"name\": \"UAV$i\", \"url\": \"${url0:-udp://127.0.0.1:$(( port + i ))}\", \"wholeFrames\": true$extra}"
        else
            layers="$layers, {\"type\": \"fmv\", \"name\": \"UAV$i\", \"path\": \"$data/file-$i/flight.ts\", \"start\": \"2026-06-21T09:00:00Z\"}"
        fi
    done
    cat > "$out" <<JSON
{"name": "live FMV benchmark", "viewpoint": {"lon": 9.03, "lat": 46.02, "height": 650, "heading": 20, "pitch": -60, "range": 9000},
 "time": {"start": "2026-06-21T09:00:01Z", "end": "2026-06-21T09:01:00Z", "playing": true}, "background": [0.1, 0.1, 0.15],
 "layers": [$layers]}
JSON
    echo "$out"
}
feeds() {   # feeds NAME N [RELAY_DROP [EXTRA]]: N senders (through a relay when RELAY_DROP is given), then orbis bench --feeds
    local name="$1" n="$2" drop="${3:-}" extra="${4:-}"
    for i in $(seq 0 $(( n - 1 ))); do
        if [ -n "$drop" ]; then
            "$build/bin/orbis-udp-relay" --listen $(( port + 100 + i )) --to $(( port + i )) --drop "$drop" --seed 7 > "$data/relay-$i.log" &
            pids+=($!)
            send $(( port + 100 + i )) $(( i * 60 ))
        else
            send $(( port + i )) $(( i * 60 ))
        fi
    done
    "$build/bin/orbis" bench "$(scene "$name" live "$n" "$extra")" --size "$size" --feeds "$each"
    stop_all
    [ -n "$drop" ] && cat "$data"/relay-*.log | tail -n 1
    true
}
want() { [[ " ${SECTIONS:-1 2 3 4} " == *" $1 "* ]]; }
if want 1; then
echo "== 1. glass-to-drape latency: one feed, then four ($video at $fps fps, render $size)"
feeds one 1
feeds four 4
fi
if want 2; then
echo "== 2. four live feeds against four file feeds (frame time)"
for i in 0 1 2 3; do
    [ -f "$data/file-$i/flight.ts" ] ||
        "$build/bin/orbis-make-fmv" "$data/file-$i" --frames $(( 60 * fps )) --fps "$fps" --size "$video" --flight-start $(( i * 60 )) > /dev/null
done
for round in 1 2; do
    echo "-- files, round $round"
    "$build/bin/orbis" bench "$(scene files file 4)" --size "$size" --frames 60 --warmup 5 | grep -E '^(frame|cpu)'
    echo "-- live, round $round"
    feeds four 4 | grep -E '^(run|all)'
done
fi
if want 3; then
echo "== 3. one feed through a lossy relay"
for drop in 0.01 0.05 0.20; do
    echo "-- $drop of the datagrams dropped"
    feeds lossy 1 "$drop"
done
fi
if want 4; then
echo "== 4. glass-to-drape latency by protocol (one feed)"
for proto in ${PROTOCOLS:-udp rtp tcp srt http}; do
    listen="" url="$proto://127.0.0.1:$port" receive=""
    case "$proto" in
        tcp) listen=--listen ;;
        srt) listen=--listen receive="$url?mode=caller" ;;
        http) listen=--listen url="$url/feed.ts" ;;
    esac
    echo "-- $proto"
    send "$port" 0 "$url" "$listen"
    "$build/bin/orbis" bench "$(scene "proto-$proto" live 1 "" "${receive:-$url}")" --size "$size" --feeds "$each" | grep -E '^(run|UAV|no latency)'
    stop_all
done
fi
