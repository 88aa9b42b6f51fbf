#pragma once
// A synthetic XYZ tile pyramid for tests that read imagery over HTTP (with test::HttpServer):
// web-mercator 256-pixel PNG tiles root/z/x/y.png whose colour encodes where a pixel is, so a
// test can check that a tile landed in the right place: red grows with longitude, green with
// latitude, blue is 128.

#include <cstdint>
#include <filesystem>
#include <string>

namespace orbis::test {

/// The red channel the tiles carry at a longitude (degrees).
uint8_t xyzRedAt(double lonDeg);
/// The green channel the tiles carry at a latitude (degrees).
uint8_t xyzGreenAt(double latDeg);
/// Writes the tiles of zoom 0..maxZoom under `root` with GDAL's PNG driver. Returns "" or what
/// went wrong.
std::string writeXyzTiles(const std::filesystem::path& root, int maxZoom);

}  // namespace orbis::test
