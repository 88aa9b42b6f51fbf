#include "tools/gen/FmvFixture.h"

#include "formats/fmv/St0601Encode.h"
#include "layers/fmv/SyntheticFlight.h"
#include "layers/fmv/VideoWriter.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>

namespace orbis::fmv {
namespace {

// 3 x 5 digit glyphs, rows top to bottom, 3 bits a row (bit 2 = left).
constexpr uint8_t kDigits[10][5] = {{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
                                    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

}  // namespace

std::vector<uint8_t> fixtureFrame(int n, int w, int h) {
    std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
    const auto put = [&](int x, int y, uint8_t r, uint8_t g, uint8_t b) {
        uint8_t* p = &rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
        p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int cx = x * 8 / w, cy = y * 6 / h;
            const uint8_t v = (cx + cy) % 2 ? 200 : 60;
            put(x, y, v, v, v);
            if (cx == 0 && cy == 0) put(x, y, 220, 40, 40);   // corner 1: red
            if (cx == 7 && cy == 0) put(x, y, 40, 200, 40);   // corner 2: green
            if (cx == 7 && cy == 5) put(x, y, 40, 60, 220);   // corner 3: blue
            if (cx == 0 && cy == 5) put(x, y, 230, 210, 40);  // corner 4: yellow
        }
    // The number in digits, centred, each glyph cell `s` pixels.
    const std::string text = std::to_string(n);
    const int s = std::max(2, h / 40), gw = 4 * s, x0 = w / 2 - int(text.size()) * gw / 2, y0 = h / 2 - 5 * s / 2;
    for (size_t k = 0; k < text.size(); ++k)
        for (int row = 0; row < 5; ++row)
            for (int col = 0; col < 3; ++col)
                if (kDigits[text[k] - '0'][row] >> (2 - col) & 1)
                    for (int dy = 0; dy < s; ++dy)
                        for (int dx = 0; dx < s; ++dx) put(x0 + int(k) * gw + col * s + dx, y0 + row * s + dy, 255, 255, 255);
    // 12 bits along the bottom row of squares' top edge: white 1, black 0.
    const int bw = w / 16, by = h * 5 / 6 - bw;
    for (int bit = 0; bit < 12; ++bit)
        for (int y = by; y < by + bw / 2; ++y)
            for (int x = (bit + 2) * bw; x < (bit + 3) * bw; ++x) {
                const uint8_t v = (n >> bit) & 1 ? 255 : 0;
                put(x, y, v, v, v);
            }
    return rgba;
}

namespace {

bool writeDem(const std::string& path) {
    const double cell = 1.0 / 7200.0;
    const int width = int(std::lround((SyntheticFlight::kEast - SyntheticFlight::kWest) / cell));
    const int height = int(std::lround((SyntheticFlight::kNorth - SyntheticFlight::kSouth) / cell));
    std::vector<float> heights(size_t(width) * size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)   // pixel centres (GDAL's area convention)
            heights[size_t(y) * size_t(width) + size_t(x)] =
                float(SyntheticFlight::height(SyntheticFlight::kWest + (x + 0.5) * cell, SyntheticFlight::kNorth - (y + 0.5) * cell));
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    const char* options[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", "TILED=YES", nullptr};
    GDALDatasetH ds = GDALCreate(driver, path.c_str(), width, height, 1, GDT_Float32, const_cast<char**>(options));
    if (!ds) return false;
    const double gt[6] = {SyntheticFlight::kWest, cell, 0.0, SyntheticFlight::kNorth, 0.0, -cell};
    GDALSetGeoTransform(ds, const_cast<double*>(gt));
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, 4979);   // heights above the ellipsoid
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    const CPLErr err = GDALDatasetRasterIO(ds, GF_Write, 0, 0, width, height, heights.data(), width, height, GDT_Float32, 1,
                                           nullptr, 0, 0, 0);
    GDALClose(ds);
    return err == CE_None;
}

}  // namespace

int fixtureFrameNumber(const std::vector<uint8_t>& rgba, int w, int h) {
    if (w < 16 || h < 16 || rgba.size() != size_t(w) * size_t(h) * 4) return -1;
    const int bw = w / 16, by = h * 5 / 6 - bw;
    int n = 0;
    for (int bit = 0; bit < 12; ++bit) {
        const int x = (bit + 2) * bw + bw / 2, y = by + bw / 4;   // the block's centre
        const uint8_t g = rgba[(size_t(y) * size_t(w) + size_t(x)) * 4 + 1];
        if (g > 128) n |= 1 << bit;
    }
    return n;
}

Result<void> writeFmvFixture(const std::filesystem::path& dir, const FmvFixtureOptions& o) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    GDALAllRegister();
    const std::string dem = (dir / "flight-dem.tif").string();
    if (!writeDem(dem)) return makeError(dem + ": cannot write the DEM");
    VideoWriteOptions v;
    v.width = o.width;
    v.height = o.height;
    v.fps = o.fps;
    v.gop = o.fps;
    v.withKlv = o.klv;
    v.klvSynchronous = !o.async;
    auto writer = VideoWriter::create((dir / "flight.ts").string(), v);
    if (!writer) return writer.error();
    std::ofstream poses;
    if (o.csv) {
        poses.open(dir / "flight.csv");
        if (!poses) return makeError((dir / "flight.csv").string() + ": cannot write");
        poses << "time_us,sensor_lat,sensor_lon,sensor_hae,platform_heading,platform_pitch,platform_roll,"
                 "sensor_rel_az,sensor_rel_el,sensor_rel_roll,hfov,vfov\n";
        poses.precision(12);
    }
    for (int n = 0; n < o.frames; ++n) {
        const double t = double(n) / o.fps, flight = o.flightStart + t;
        const St0601Packet packet = SyntheticFlight::packet(flight);
        if (o.klv)
            if (auto r = (*writer)->writeKlv(t, encodeSt0601(packet)); !r) return r;
        if (auto r = (*writer)->writeFrame(fixtureFrame(n, o.width, o.height)); !r) return r;
        if (o.csv) {
            const SensorPose p = SyntheticFlight::pose(flight);
            poses << *packet.precisionTimeUs << ',' << p.latDeg << ',' << p.lonDeg << ',' << p.height << ',' << p.platformHeadingDeg
                  << ',' << p.platformPitchDeg << ',' << p.platformRollDeg << ',' << p.sensorAzimuthDeg << ','
                  << p.sensorElevationDeg << ',' << p.sensorRollDeg << ',' << p.hfovDeg << ',' << p.vfovDeg << '\n';
        }
    }
    return (*writer)->close();
}

Result<int> streamFmvFixture(const std::string& url, const FmvStreamOptions& o, const std::atomic<bool>& stop) {
    VideoWriteOptions v;
    v.width = o.width;
    v.height = o.height;
    v.fps = o.fps;
    v.gop = o.fps;
    v.klvSynchronous = !o.async;
    v.live = true;
    v.listen = o.listen;
    v.interrupted = [&stop] { return stop.load(); };
    auto writer = VideoWriter::create(url, v);
    if (!writer) return writer.error();
    const auto start = std::chrono::steady_clock::now();
    int n = 0;
    for (; n < o.frames && !stop; ++n) {
        const double t = double(n) / o.fps;
        if (o.realTime) std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(t)));
        St0601Packet packet = SyntheticFlight::packet(o.flightStart + t);
        if (o.stampWallClock)
            packet.precisionTimeUs = uint64_t(std::chrono::duration_cast<std::chrono::microseconds>(
                                                  std::chrono::system_clock::now().time_since_epoch())
                                                  .count());
        // A write cut short because we were told to stop is the end, not an error.
        if (auto r = (*writer)->writeKlv(t, encodeSt0601(packet)); !r) return stop ? Result<int>(n) : r.error();
        if (auto r = (*writer)->writeFrame(fixtureFrame(n, o.width, o.height)); !r) return stop ? Result<int>(n) : r.error();
    }
    if (auto r = (*writer)->close(); !r && !stop) return r.error();
    return n;
}

}  // namespace orbis::fmv
