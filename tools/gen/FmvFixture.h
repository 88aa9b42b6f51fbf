#pragma once
// The FMV fixture (orbis-make-fmv, tests): the synthetic flight's DEM (GeoTIFF), its MPEG-TS
// (H.264 frames and one ST 0601 KLV packet a frame) and optionally its poses as a CSV sidecar.
// See layers/fmv/SyntheticFlight.h for the flight and the terrain.

#include "base/Result.h"

#include <atomic>
#include <cstdint>
#include <string>
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

/// The fixture's flight sent live to `url` (VideoWriter's live mode: udp://, tcp://...), frame
/// n at n / fps seconds after the start when `realTime`, with its KLV packet just before it.
struct FmvStreamOptions {
    int frames = 100, fps = 10, width = 320, height = 240;
    bool async = false;
    double flightStart = 0.0;
    bool realTime = true;
    /// The KLV precision time stamps are the wall clock when each frame is sent (glass-to-drape
    /// latency is then the receiver's clock minus the stamp of the frame it shows), not the
    /// flight's 2026-06-21T09:00Z.
    bool stampWallClock = false;
    /// Wait for the receiver to connect (tcp://, srt://, http://: see VideoWriteOptions::listen).
    bool listen = false;
};

/// Sends until `options.frames` are sent or `stop` becomes true; returns the frames sent.
/// Errors name the URL (cannot open, a write failed: a TCP receiver that went away).
Result<int> streamFmvFixture(const std::string& url, const FmvStreamOptions& options, const std::atomic<bool>& stop);

/// Frame n: a checkerboard of 8 x 6 squares with coloured corner squares (upper left red,
/// upper right green, lower right blue, lower left yellow), n in digits in the middle and as 12
/// bits (white 1, black 0) in blocks along the top of the bottom row.
std::vector<uint8_t> fixtureFrame(int n, int width, int height);
/// n read back from such a frame (after coding: each bit from its block's centre); -1 for a
/// buffer of the wrong size.
int fixtureFrameNumber(const std::vector<uint8_t>& rgba, int width, int height);

}  // namespace orbis::fmv
