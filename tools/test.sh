#!/usr/bin/env bash
# README command 2 (and what CI runs): install the Debian packages, build everything, run every
# test. GPU tests select lavapipe themselves and run with the validation layer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
# Window-surface tests need a display: use a private Xvfb when none is set.
if [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1280x720x24" ctest --test-dir build --output-on-failure --no-tests=error -j2 "$@"
fi
ctest --test-dir build --output-on-failure --no-tests=error -j2 "$@"
