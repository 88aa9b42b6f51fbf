// orbis-make-fmv: the FMV fixture: a synthetic DEM and an MPEG-TS with H.264 frames and a
// synchronous MISB ST 0601 KLV stream from a scripted flight over it (layers/fmv/SyntheticFlight.h),
// so that tests and benchmarks know where every corner of every frame must land.
//
//   orbis-make-fmv OUTDIR [--frames 100] [--fps 10] [--size 640x480] [--async] [--csv]
//
// Writes OUTDIR/flight-dem.tif (EPSG:4979 heights over lon 9.00..9.06, lat 46.00..46.04, 1/7200
// degree cells: about 11 x 15 m), OUTDIR/flight.ts, and with --csv OUTDIR/flight.csv (the same
// poses as a CSV sidecar). Frames: a checkerboard of 8 x 6 squares (the image's corners are
// coloured: upper left red, upper right green, lower right blue, lower left yellow), the frame
// number in digits and as 12 bits in blocks along the bottom. One KLV packet per frame, at the
// frame's time. Deterministic.
#include "globe/Ellipsoid.h"
#include "layers/fmv/St0601Encode.h"
#include "layers/fmv/SyntheticFlight.h"
#include "layers/fmv/VideoWriter.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using orbis::fmv::SyntheticFlight;

int usage() {
    std::fprintf(stderr, "usage: orbis-make-fmv OUTDIR [--frames N] [--fps F] [--size WxH] [--async] [--csv]\n");
    return 2;
}

// 3 x 5 digit glyphs, rows top to bottom, 3 bits a row (bit 2 = left).
constexpr uint8_t kDigits[10][5] = {{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
                                    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

std::vector<uint8_t> frameImage(int n, int w, int h) {
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

int main(int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') return usage();
    const std::filesystem::path out = argv[1];
    int frames = 100, fps = 10, width = 640, height = 480;
    bool async = false, csv = false;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--async") {
            async = true;
            continue;
        }
        if (a == "--csv") {
            csv = true;
            continue;
        }
        if (i + 1 >= argc) return usage();
        const char* v = argv[++i];
        if (a == "--frames") frames = std::atoi(v);
        else if (a == "--fps") fps = std::atoi(v);
        else if (a == "--size") {
            if (std::sscanf(v, "%dx%d", &width, &height) != 2) return usage();
        } else return usage();
    }
    if (frames < 1 || frames > 100000 || fps < 1 || fps > 240 || width < 16 || height < 16 || width > 4096 || height > 4096 ||
        width % 2 || height % 2) {
        std::fprintf(stderr, "orbis-make-fmv: frames 1..100000, fps 1..240, an even size from 16x16 to 4096x4096\n");
        return 2;
    }
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    GDALAllRegister();
    const std::string dem = (out / "flight-dem.tif").string();
    if (!writeDem(dem)) {
        std::fprintf(stderr, "orbis-make-fmv: %s: cannot write the DEM\n", dem.c_str());
        return 1;
    }
    orbis::fmv::VideoWriteOptions o;
    o.width = width;
    o.height = height;
    o.fps = fps;
    o.gop = fps;
    o.klvSynchronous = !async;
    const std::string ts = (out / "flight.ts").string();
    auto writer = orbis::fmv::VideoWriter::create(ts, o);
    if (!writer) {
        std::fprintf(stderr, "orbis-make-fmv: %s\n", writer.message().c_str());
        return 1;
    }
    std::ofstream poses;
    if (csv) {
        poses.open(out / "flight.csv");
        poses << "time_us,sensor_lat,sensor_lon,sensor_hae,platform_heading,platform_pitch,platform_roll,"
                 "sensor_rel_az,sensor_rel_el,sensor_rel_roll,hfov,vfov\n";
        poses.precision(12);
    }
    for (int n = 0; n < frames; ++n) {
        const double t = double(n) / fps;
        const orbis::fmv::St0601Packet packet = SyntheticFlight::packet(t);
        if (auto r = (*writer)->writeKlv(t, orbis::fmv::encodeSt0601(packet)); !r) {
            std::fprintf(stderr, "orbis-make-fmv: %s\n", r.message().c_str());
            return 1;
        }
        if (auto r = (*writer)->writeFrame(frameImage(n, width, height)); !r) {
            std::fprintf(stderr, "orbis-make-fmv: %s\n", r.message().c_str());
            return 1;
        }
        if (csv) {
            const orbis::fmv::SensorPose p = SyntheticFlight::pose(t);
            poses << *packet.precisionTimeUs << ',' << p.latDeg << ',' << p.lonDeg << ',' << p.height << ',' << p.platformHeadingDeg
                  << ',' << p.platformPitchDeg << ',' << p.platformRollDeg << ',' << p.sensorAzimuthDeg << ','
                  << p.sensorElevationDeg << ',' << p.sensorRollDeg << ',' << p.hfovDeg << ',' << p.vfovDeg << '\n';
        }
    }
    if (auto r = (*writer)->close(); !r) {
        std::fprintf(stderr, "orbis-make-fmv: %s\n", r.message().c_str());
        return 1;
    }
    std::printf("orbis-make-fmv: %s (%d frames, %dx%d, %d fps, %s KLV), %s%s\n", ts.c_str(), frames, width, height, fps,
                async ? "asynchronous" : "synchronous", dem.c_str(), csv ? ", flight.csv" : "");
    return 0;
}
