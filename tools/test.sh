#!/usr/bin/env bash
# README command 2 (and what CI runs): install the Debian packages, build everything, run every
# test. GPU tests select lavapipe themselves and run with the validation layer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
ctest --test-dir build --output-on-failure --no-tests=error -j2 "$@"
