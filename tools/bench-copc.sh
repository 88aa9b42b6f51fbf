#!/usr/bin/env bash
# COPC over HTTP (issue 26): a synthetic survey (orbis-make-las) converted to COPC by
# `orbis convert`, served by lighttpd (Debian; honours range requests) on 127.0.0.1, then viewed
# by `orbis bench` from the server and from the disk, for a close view (a corner of the survey)
# and the whole survey: time to the first frame with content, frame time, and the bytes the
# server sent (lighttpd's access log) against the file's size. Runs alternate: from the server
# with an empty node cache, from the server again with the nodes the first run cached on the
# disk, and from the disk.
#   usage: tools/bench-copc.sh [BUILD_DIR]   env: POINTS=20000000 FRAMES=5 SIZE=1920x1080 DEVICE=cpu
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
points="${POINTS:-20000000}" frames="${FRAMES:-5}" size="${SIZE:-1920x1080}"
data="$build/bench-data"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}"
dev=(); [ -n "${DEVICE:-}" ] && dev=(--device "$DEVICE")
mkdir -p "$data" "$XDG_RUNTIME_DIR"
las="$data/survey-$((points / 1000000))m.las"
copc="$data/survey-$((points / 1000000))m.copc.laz"
[ -f "$las" ] || "$build/bin/orbis-make-las" --points "$points" --out "$las"
[ -f "$copc" ] || "$build/bin/orbis" convert "$las" "$copc"
work="$(mktemp -d)"
trap 'kill "$server" 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$work"' EXIT
mkdir -p "$work/docs"
ln -s "$copc" "$work/docs/survey.copc.laz"
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
cat > "$work/lighttpd.conf" <<CONF
server.modules = ("mod_accesslog")
server.document-root = "$work/docs"
server.follow-symlink = "enable"
server.bind = "127.0.0.1"
server.port = $port
server.errorlog = "$work/error.log"
accesslog.filename = "$work/access.log"
accesslog.format = "%m %U %s %b"
CONF
start_server() {
    : > "$work/access.log"
    /usr/sbin/lighttpd -D -f "$work/lighttpd.conf" & server=$!
    for _ in $(seq 200); do (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && return; sleep 0.05; done
}
stop_server() { kill "$server"; wait "$server" 2>/dev/null || true; }
scene() {   # scene PATH VIEW NAME CACHE -> a scene file
    local view
    if [ "$2" = close ]; then view='{"lon": 8.9985, "lat": 46.0015, "height": 450, "heading": 30, "pitch": -40, "range": 250}'
    else view='{"lon": 9.0, "lat": 46.0087, "height": 820, "heading": 20, "pitch": -55, "range": 1900}'; fi
    cat > "$work/$2-$3.json" <<JSON
{"name": "COPC survey ($2 view)", "viewpoint": $view, "fovDeg": 45,
 "time": {"start": "2026-06-21T09:00:00Z", "end": "2026-06-21T09:00:00Z"}, "background": [0, 0, 0],
 "layers": [{"type": "points", "name": "Survey", "path": "$1", "pointBudget": 3000000, "cacheFolder": "$4"}]}
JSON
    echo "$work/$2-$3.json"
}
echo "== $copc: $(stat -c %s "$copc") bytes, $points points, $size"
for view in close whole; do
    for run in 1 2; do
        cache="$work/cache-$view-$run"
        for from in server cached disk; do
            if [ "$from" != disk ]; then start_server; path="http://127.0.0.1:$port/survey.copc.laz"; else path="$copc"; fi
            echo "-- $view view, from the $from, run $run"
            "$build/bin/orbis" bench "${dev[@]}" "$(scene "$path" "$view" "$from" "$cache")" --size "$size" --frames "$frames" --warmup 1 \
                | grep -E "frame \(wall\)|items drawn|loading"
            if [ "$from" != disk ]; then
                stop_server
                awk '{ n++; b += ($4 == "-" ? 0 : $4) } END { printf "server: %d requests, %d bytes sent\n", n, b }' "$work/access.log"
            fi
        done
    done
done
