#!/usr/bin/env bash
# The processing round trip in the viewer, on loopback: the demo WPS server (tools/wps) started
# on a free port, then RUNS viewer sessions per mode (stored job polled, synchronous), each
# drawing a box on assets/scenes/processing.json and running the terrain process on it. Prints
# the medians (and ranges) of DescribeProcess to form, Run to result layer added and Run to
# result layer on screen (loaded and drawn). Device: lavapipe under Xvfb at 1280x720.
#   tools/bench-processing.sh [RUNS]      (default 20)
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-20}"
orbis=build/bin/orbis
[ -x "$orbis" ] || { echo "bench-processing: build first (tools/build.sh)" >&2; exit 1; }
dir=$(mktemp -d /tmp/orbis-bench-processing.XXXXXX)
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
/usr/bin/python3 tools/wps/serve.py --dem assets/generated/fmv/flight-dem.tif --dir "$dir/server" --port "$port" > "$dir/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null; rm -rf "$dir"' EXIT
for i in $(seq 100); do curl -s -o /dev/null "http://127.0.0.1:$port/wps?service=WPS&request=GetCapabilities" && break; sleep 0.1; done
url="http://127.0.0.1:$port/wps"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
for mode in stored synchronous; do
  extra=""
  [ "$mode" = synchronous ] && extra='{"do": "click", "item": "synchronous##wps"},'
  cat > "$dir/script-$mode.json" <<JSON
[{"do": "settle"}, {"do": "click", "item": "Connect##wps"}, {"do": "settle"},
 {"do": "click", "item": "terrain##process"}, {"do": "settle"},
 {"do": "click", "item": "Box##tool"}, {"do": "settle"},
 {"do": "click", "at": [600, 300]}, {"do": "click", "at": [720, 420]}, {"do": "settle"}, $extra
 {"do": "click", "item": "Run##wps"}, {"do": "settle"}, {"do": "quit"}]
JSON
  : > "$dir/$mode.log"
  for i in $(seq "$runs"); do
    xvfb-run -a -s "-screen 0 1280x720x24" env VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \
      "$orbis" view assets/scenes/processing.json --device cpu --size 1280x720 --script "$dir/script-$mode.json" \
      --wps "$url" --results "$dir/results" >> "$dir/$mode.log" 2>&1
  done
  /usr/bin/python3 - "$dir/$mode.log" "$mode" <<'PY'
import re, statistics, sys
text = open(sys.argv[1]).read()
def show(label, values):
    if not values: print(f"  {label}: none measured"); return
    print(f"  {label}: median {statistics.median(values)*1000:.0f} ms ({min(values)*1000:.0f} .. {max(values)*1000:.0f}, {len(values)} runs)")
print(f"{sys.argv[2]} job (terrain: slope of a 1 km box), lavapipe 1280x720:")
show("DescribeProcess to form", [float(x) for x in re.findall(r'described "terrain" in ([0-9.]+) s', text)])
show("Run to result layer added", [float(x) for x in re.findall(r'\(([0-9.]+) s after Run\)', text)])
show("Run to result layer on screen", [float(x) for x in re.findall(r'result on screen ([0-9.]+) s after Run', text)])
PY
done
