#!/usr/bin/env bash
# Error against run time, side by side with the VTK peer (../shared/peers/vtk_peer.py: VTK 9.1's
# GPU ray-cast mapper on llvmpipe): the same field, size, transfer function and view, at a range
# of sample counts, each renderer's image compared with its own high-sample reference; runs
# alternate (VTK, Orbis, VTK, Orbis, ...) so that both see the same machine. The body, its
# options (env: SIZE, REPEATS, FRAMES, CASES, COUNTS, ORBIS_COUNTS, REF, ORBIS_SETTINGS, PLOT,
# OUT) and its output are described in tools/peer_volume.py.
#   usage: tools/peer-volume.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
/usr/bin/python3 -c 'import vtk' 2>/dev/null || {
    echo "peer-volume: VTK for /usr/bin/python3 is missing: apt-get install python3-vtk9 xvfb xauth" >&2; exit 2; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/orbis-xdg}" LIBGL_ALWAYS_SOFTWARE=1
mkdir -p "$XDG_RUNTIME_DIR"
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
exec /usr/bin/python3 "$here/tools/peer_volume.py" "${1:-$here/build}"
