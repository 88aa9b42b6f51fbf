// orbis-make-las: a synthetic LAS 1.2 point cloud (format 3: RGB, GPS time) for benchmarks, of
// any size, written in batches (memory stays bounded at tens of millions of points).
//
//   orbis-make-las --points 20000000 --out survey.las [--size 2000] [--epsg 32632]
//                  [--centre 500000,5095000] [--seed 1]
//
// The area: a square of --size metres centred on --centre, by default UTM zone 32N easting
// 500 000, northing 5 095 000 (lon 9.0, lat 46.01: the Alps), in EPSG:32632 (GeoTIFF keys in the
// file). --epsg only labels the coordinates: give a --centre in that CRS's units with it.
// Points are spread uniformly over the square: ground (class 2) on the analytic surface
//   z(x, y) = 800 + 60 sin(x / 150) cos(y / 210) + 0.02 x   (x, y metres from the centre),
// coloured by a smooth pattern; a grid of flat-roofed buildings (class 6, 20 m boxes every
// 100 m, 8 to 20 m tall) and trees (class 5, up to 15 m above the ground, first of two returns;
// half of the tree pulses also give a last return on the ground) scattered by the seed.
// GPS time advances 10 µs a point (a 100 kHz scanner). Deterministic: the same arguments give
// the same file.
#include "layers/points/LasReader.h"
#include "tools/gen/SplitMix.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

using Rng = orbis::gen::SplitMix;

double ground(double x, double y) { return 800.0 + 60.0 * std::sin(x / 150.0) * std::cos(y / 210.0) + 0.02 * x; }

int usage() {
    std::fprintf(stderr, "usage: orbis-make-las --points N --out FILE [--size METRES] [--epsg CODE] [--centre X,Y] [--seed N]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    uint64_t count = 0;
    std::string out;
    double size = 2000.0;
    int epsg = 32632;
    uint64_t seed = 1;
    glm::dvec2 centre{500000.0, 5095000.0};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) return usage();
        const char* v = argv[++i];
        char* end = nullptr;
        if (a == "--points") count = std::strtoull(v, &end, 10);
        else if (a == "--out") out = v, end = const_cast<char*>(v) + std::strlen(v);
        else if (a == "--size") size = std::strtod(v, &end);
        else if (a == "--epsg") epsg = int(std::strtol(v, &end, 10));
        else if (a == "--seed") seed = std::strtoull(v, &end, 10);
        else if (a == "--centre") {
            centre.x = std::strtod(v, &end);
            if (end && *end == ',') centre.y = std::strtod(end + 1, &end);
            else end = nullptr;
        }
        else return usage();
        if (!end || *end != 0) {
            std::fprintf(stderr, "orbis-make-las: %s: not a number: %s\n", a.c_str(), v);
            return 2;
        }
    }
    if (count == 0 || out.empty() || !(size > 0.0 && size <= 1e6)) return usage();
    const auto t0 = std::chrono::steady_clock::now();
    orbis::points::LasWriteOptions o;
    o.versionMinor = 2;
    o.pointFormat = 3;
    o.scale = glm::dvec3(0.001);
    o.offset = glm::dvec3(std::round(centre.x), std::round(centre.y), 0.0);
    o.epsg = epsg;
    auto writer = orbis::points::LasWriter::create(out, o);
    if (!writer) {
        std::fprintf(stderr, "orbis-make-las: %s\n", writer.message().c_str());
        return 1;
    }
    Rng rng{seed};
    std::vector<orbis::points::LasPoint> batch;
    const uint64_t perBatch = 1u << 20;
    for (uint64_t done = 0; done < count; done += perBatch) {
        batch.resize(size_t(std::min(perBatch, count - done)));
        for (size_t i = 0; i < batch.size(); ++i) {
            orbis::points::LasPoint& p = batch[i];
            const double x = (rng.uniform() - 0.5) * size, y = (rng.uniform() - 0.5) * size;
            const double z0 = ground(x, y);
            // Buildings: 20 m squares on a 100 m grid, some of the cells (fixed by the cell).
            const double cx = std::floor(x / 100.0), cy = std::floor(y / 100.0);
            Rng cell{uint64_t(int64_t(cx) * 73856093) ^ uint64_t(int64_t(cy) * 19349663) ^ seed};
            const bool hasBuilding = cell.uniform() < 0.35;
            const double height = 8.0 + 12.0 * cell.uniform();
            const double bx = x - (cx * 100.0 + 50.0), by = y - (cy * 100.0 + 50.0);
            double z = z0;
            double r, g, b;
            uint8_t cls = 2, returnNumber = 1, returns = 1;
            if (hasBuilding && std::abs(bx) < 10.0 && std::abs(by) < 10.0) {
                cls = 6;
                z = z0 + height;
                r = 0.75, g = 0.30 + 0.1 * cell.uniform(), b = 0.22;
            } else if (rng.uniform() < 0.18) {
                returns = 2;
                if (rng.uniform() < 0.5) {   // the canopy
                    cls = 5;
                    z = z0 + 15.0 * std::sqrt(rng.uniform());
                    r = 0.12, g = 0.35 + 0.25 * rng.uniform(), b = 0.12;
                } else {   // the ground under it, last return
                    returnNumber = 2;
                    r = 0.30, g = 0.25, b = 0.15;
                }
            } else {
                const double f = 0.5 + 0.5 * std::sin(x / 90.0 + std::cos(y / 130.0));
                r = 0.45 + 0.25 * f, g = 0.50 + 0.15 * (1.0 - f), b = 0.30;
            }
            p.position = {centre.x + x, centre.y + y, z};
            p.classification = cls;
            p.red = uint16_t(r * 65535.0), p.green = uint16_t(g * 65535.0), p.blue = uint16_t(b * 65535.0);
            p.intensity = uint16_t(cls == 6 ? 1800 : cls == 5 ? 600 : 1200 + 400 * rng.uniform());
            p.returnNumber = returnNumber;
            p.numberOfReturns = returns;
            p.gpsTime = double(done + i) * 1e-5;
        }
        (*writer)->write(batch);
    }
    if (auto closed = (*writer)->close(); !closed) {
        std::fprintf(stderr, "orbis-make-las: %s\n", closed.message().c_str());
        return 1;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("orbis-make-las: wrote %s: %llu points over %.0f m x %.0f m around (%.0f, %.0f) (EPSG:%d) in %.1f s\n",
                out.c_str(), (unsigned long long)count, size, size, centre.x, centre.y, epsg, s);
    return 0;
}
