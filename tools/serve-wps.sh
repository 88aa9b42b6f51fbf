#!/usr/bin/env bash
# The demo processing server for a user who wants to try it: PyWPS 4.5 (tools/wps/serve.py:
# terrain, viewshed, profile, zonal statistics, a long task) over a DEM, on 127.0.0.1, in a
# temporary folder removed on exit. Prints its address; Ctrl+C stops it.
#   tools/serve-wps.sh [DEM] [PORT]     (default: the FMV showcase's hills, port 5000)
set -euo pipefail
cd "$(dirname "$0")/.."
dem="${1:-assets/generated/fmv/flight-dem.tif}"
port="${2:-5000}"
[ -f "$dem" ] || { echo "serve-wps: $dem: no such file (the build generates the default one: tools/build.sh)" >&2; exit 1; }
/usr/bin/python3 -c 'import pywps, osgeo.gdal' 2>/dev/null || { echo "serve-wps: PyWPS is not installed: run tools/install-deps.sh" >&2; exit 1; }
dir=$(mktemp -d /tmp/orbis-wps.XXXXXX)
trap 'rm -rf "$dir"' EXIT
echo "serve-wps: processes over $dem; try  curl '<address>?service=WPS&request=GetCapabilities'"
/usr/bin/python3 tools/wps/serve.py --dem "$dem" --dir "$dir" --port "$port"
