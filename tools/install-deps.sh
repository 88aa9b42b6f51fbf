#!/usr/bin/env bash
# Installs every Debian 12 package Orbis needs to build, run and test.
# Each layer issue adds what it needs here (GLFW/ImGui with the viewer, netCDF with volumes...).
# Idempotent and non-interactive; needs root (or sudo). Downloads nothing but Debian packages.
set -euo pipefail

packages=(
  # toolchain (a minbase Debian has none of these)
  build-essential cmake ninja-build pkg-config git ca-certificates
  # Vulkan: loader, headers, lavapipe (mesa), validation layer, shader compiler
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-tools spirv-tools
  # the viewer: windows (GLFW surfaces; tests run them under Xvfb), Dear ImGui, images
  libglfw3-dev libimgui-dev xvfb xauth libstb-dev
  # maths, geodesy, data, scene files
  libglm-dev libgeographiclib-dev libgdal-dev gdal-bin nlohmann-json3-dev
  # checksums of the point caches (CRC-32)
  zlib1g-dev
  # 3-D models (glTF 2.0; OBJ, FBX, COLLADA, 3DS, PLY, STL through Assimp, with its test
  # models for the tests) and the live feed's XML messages
  libtinygltf-dev libassimp-dev assimp-testmodels libexpat1-dev
  # label text: the default font (DejaVu Sans; the glyph tests skip without it)
  fonts-dejavu-core
  # the default scene: NASA's Blue Marble and city lights (xplanet-images), Natural Earth's
  # countries, states and disputed borders (qgis-common's world_map.gpkg)
  xplanet-images qgis-common
  # full-motion video: MPEG-TS demuxing (KLV), H.264 decoding and encoding (fixtures), RGBA
  libavformat-dev libavcodec-dev libavutil-dev libswscale-dev
  # database sources: libpq for live layers (LISTEN/NOTIFY); PostgreSQL + PostGIS, started on
  # loopback by the server tests (tests/server)
  libpq-dev postgresql-15 postgresql-15-postgis-3
  # OGC services (WMS, WFS) from MapServer's CGI, WMTS from MapCache's, behind lighttpd, started
  # on loopback by the server tests (tests/support/MapServer) and tools/serve-demo.sh
  cgi-mapserver mapcache-cgi lighttpd
  # a processing server: PyWPS 4.5 (WSGI through werkzeug) with processes in Python on GDAL,
  # started on loopback by the server tests and tools/serve-wps.sh (tools/wps/)
  python3-pywps python3-gdal
  # tests; the fuzz targets (libFuzzer, ASan and UBSan through clang: tools/fuzz.sh)
  libgtest-dev clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
