#pragma once
// The FMV fixture (orbis-make-fmv, tests): the synthetic flight's DEM (GeoTIFF), its MPEG-TS
// (H.264 frames and one ST 0601 KLV packet a frame) and optionally its poses as a CSV sidecar.
// See layers/fmv/SyntheticFlight.h for the flight and the terrain.

#include "base/Result.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace orbis::fmv {

struct FmvFixtureOptions {
    int frames = 100, fps = 10, width = 640, height = 480;
    bool async = false;   ///< asynchronous KLV (stream type 0x06) instead of synchronous
    bool klv = true;      ///< false: a video without KLV
    bool csv = false;     ///< also DIR/flight.csv
    double flightStart = 0.0;   ///< seconds into the flight of frame 0 (the lap is 240 s)
};

/// Writes DIR/flight-dem.tif, DIR/flight.ts (and DIR/flight.csv). Errors name the file.
Result<void> writeFmvFixture(const std::filesystem::path& dir, const FmvFixtureOptions& options);

/// Frame n: a checkerboard of 8 x 6 squares with coloured corner squares (upper left red,
/// upper right green, lower right blue, lower left yellow), n in digits in the middle and as 12
/// bits (white 1, black 0) in blocks along the top of the bottom row.
std::vector<uint8_t> fixtureFrame(int n, int width, int height);

}  // namespace orbis::fmv
