#!/usr/bin/env bash
# README command 1: install the Debian packages, build, and show the default scene
# (assets/scenes/default.json): in the viewer's window when there is a display, else rendered
# headlessly to orbis-default.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh --target orbis
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
    exec build/bin/orbis view assets/scenes/default.json
fi
build/bin/orbis -v render assets/scenes/default.json -o orbis-default.png --size 1280x720
echo "demo: open orbis-default.png (with a display, this opens the viewer: orbis view SCENE)"
