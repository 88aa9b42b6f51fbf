#!/usr/bin/env bash
# Configures and builds Orbis in ./build (Release, Ninja, warnings as errors). Extra arguments go to `cmake --build`
# (e.g. --target orbis). Incremental: a second run rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DORBIS_BUILD_TESTS=ON -DORBIS_WERROR=ON >/dev/null
cmake --build build "$@"
