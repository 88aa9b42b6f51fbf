// orbis-make-world: writes the synthetic planet that the default scene shows, so that the
// README's first command runs on nothing but the repository (no download, no ../shared).
//
//   orbis-make-world OUTPUT_FOLDER [--width 4096]
//
// Writes OUTPUT_FOLDER/world-relief.tif (Int16 metres, EPSG:4326, whole globe, tiled,
// deflate, with overviews) and OUTPUT_FOLDER/world-colour.tif (RGB Byte, the same grid).
// Heights come from 3-D gradient noise sampled on the unit sphere, so the planet has no seam
// at the antimeridian and no pinch at the poles. Deterministic: the same file every time.

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

// Improved Perlin noise (Ken Perlin, 2002) with a fixed permutation from a small LCG.
struct Noise {
    std::array<int, 512> p{};
    explicit Noise(uint32_t seed) {
        std::array<int, 256> q{};
        for (int i = 0; i < 256; ++i) q[size_t(i)] = i;
        uint32_t s = seed;
        for (int i = 255; i > 0; --i) {
            s = s * 1664525u + 1013904223u;
            std::swap(q[size_t(i)], q[size_t((s >> 8) % uint32_t(i + 1))]);
        }
        for (int i = 0; i < 512; ++i) p[size_t(i)] = q[size_t(i & 255)];
    }
    static double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
    static double grad(int h, double x, double y, double z) {
        const int k = h & 15;
        const double u = k < 8 ? x : y, v = k < 4 ? y : (k == 12 || k == 14) ? x : z;
        return ((k & 1) ? -u : u) + ((k & 2) ? -v : v);
    }
    double operator()(double x, double y, double z) const {
        const int X = int(std::floor(x)) & 255, Y = int(std::floor(y)) & 255, Z = int(std::floor(z)) & 255;
        x -= std::floor(x);
        y -= std::floor(y);
        z -= std::floor(z);
        const double u = fade(x), v = fade(y), w = fade(z);
        const int A = p[size_t(X)] + Y, AA = p[size_t(A)] + Z, AB = p[size_t(A + 1)] + Z;
        const int B = p[size_t(X + 1)] + Y, BA = p[size_t(B)] + Z, BB = p[size_t(B + 1)] + Z;
        const auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
        return lerp(w,
                    lerp(v, lerp(u, grad(p[size_t(AA)], x, y, z), grad(p[size_t(BA)], x - 1, y, z)),
                         lerp(u, grad(p[size_t(AB)], x, y - 1, z), grad(p[size_t(BB)], x - 1, y - 1, z))),
                    lerp(v, lerp(u, grad(p[size_t(AA + 1)], x, y, z - 1), grad(p[size_t(BA + 1)], x - 1, y, z - 1)),
                         lerp(u, grad(p[size_t(AB + 1)], x, y - 1, z - 1), grad(p[size_t(BB + 1)], x - 1, y - 1, z - 1))));
    }
    double fbm(double x, double y, double z, int octaves, double lacunarity = 2.0, double gain = 0.5) const {
        double sum = 0, amp = 1, norm = 0;
        for (int o = 0; o < octaves; ++o) {
            sum += amp * (*this)(x, y, z);
            norm += amp;
            amp *= gain;
            x *= lacunarity;
            y *= lacunarity;
            z *= lacunarity;
        }
        return sum / norm;
    }
};

struct Sample {
    float height;   // metres, 0 at sea
    uint8_t rgb[3];
};

Sample planet(const Noise& n, double lonDeg, double latDeg) {
    const double lon = lonDeg * kPi / 180.0, lat = latDeg * kPi / 180.0;
    const double x = std::cos(lat) * std::cos(lon), y = std::cos(lat) * std::sin(lon), z = std::sin(lat);
    // Continents: low-frequency noise, warped so coasts are not blobs.
    const double wx = n.fbm(x * 2 + 11.3, y * 2, z * 2, 3), wy = n.fbm(x * 2, y * 2 + 7.1, z * 2, 3);
    const double c = n.fbm(x * 1.6 + wx * 0.6, y * 1.6 + wy * 0.6, z * 1.6, 6);
    // Ridged mountains where land is high.
    const double r = 1.0 - std::abs(n.fbm(x * 6 + 3.7, y * 6, z * 6 - 1.9, 7));
    const double land = c - 0.02;
    double h;
    if (land <= 0) {
        h = land * 20000.0;   // ocean floor (negative)
    } else {
        h = land * 3500.0 + std::pow(std::max(r, 0.0), 3.0) * std::min(land * 8.0, 1.0) * 3200.0;
    }
    Sample s{};
    if (h <= 0) {
        s.height = 0.0f;   // a flat sea; the colour shows the depth
        const double d = std::min(-h / 5000.0, 1.0);
        s.rgb[0] = uint8_t(18 - 12 * d);
        s.rgb[1] = uint8_t(70 - 45 * d);
        s.rgb[2] = uint8_t(120 - 55 * d);
    } else {
        s.height = float(h);
        const double alat = std::abs(latDeg);
        const double t = std::min(h / 3500.0, 1.0);
        // Lowland green -> dry ochre -> rock grey with height; deserts near 25 degrees.
        const double dry = std::exp(-std::pow((alat - 25.0) / 10.0, 2.0)) * 0.8;
        double rr = 60 + 90 * dry, gg = 105 + 40 * dry, bb = 45 + 30 * dry;
        rr = rr + (130 - rr) * t;
        gg = gg + (118 - gg) * t;
        bb = bb + (105 - bb) * t;
        const double snowLine = 4300.0 - 3700.0 * std::pow(std::min(alat / 75.0, 1.0), 2.0);
        const double snow = std::clamp((h - snowLine) / 600.0, 0.0, 1.0);
        rr += (240 - rr) * snow;
        gg += (244 - gg) * snow;
        bb += (248 - bb) * snow;
        s.rgb[0] = uint8_t(std::clamp(rr, 0.0, 255.0));
        s.rgb[1] = uint8_t(std::clamp(gg, 0.0, 255.0));
        s.rgb[2] = uint8_t(std::clamp(bb, 0.0, 255.0));
    }
    // Ice caps.
    if (std::abs(latDeg) > 72.0) {
        const double ice = std::clamp((std::abs(latDeg) - 72.0) / 4.0, 0.0, 1.0);
        for (auto& ch : s.rgb) ch = uint8_t(ch + (236 - ch) * ice);
    }
    return s;
}

bool writeTiff(const std::string& path, int width, int height, GDALDataType type, int bands, const void* data,
               const char* extraOption) {
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    const char* opts[] = {"TILED=YES", "COMPRESS=DEFLATE", "PREDICTOR=2", extraOption, nullptr};
    GDALDatasetH ds = GDALCreate(drv, path.c_str(), width, height, bands, type, const_cast<char**>(opts));
    if (!ds) return false;
    const double gt[6] = {-180.0, 360.0 / width, 0.0, 90.0, 0.0, -180.0 / height};
    GDALSetGeoTransform(ds, const_cast<double*>(gt));
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, 4326);
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    const int size = GDALGetDataTypeSizeBytes(type);
    const CPLErr err = GDALDatasetRasterIO(ds, GF_Write, 0, 0, width, height, const_cast<void*>(data), width, height,
                                           type, bands, nullptr, size * bands, size * bands * width, size);
    CPLErr overviews = CE_None;
    if (err == CE_None) {
        const int levels[] = {2, 4, 8, 16, 32};
        overviews = GDALBuildOverviews(ds, "AVERAGE", 5, const_cast<int*>(levels), 0, nullptr, nullptr, nullptr);
    }
    GDALClose(ds);
    return err == CE_None && overviews == CE_None;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: orbis-make-world OUTPUT_FOLDER [--width N]\n");
        return 2;
    }
    const std::filesystem::path out = argv[1];
    int width = 4096;
    for (int i = 2; i + 1 < argc; i += 2)
        if (std::string(argv[i]) == "--width") width = std::atoi(argv[i + 1]);
    if (width < 64 || width > 65536 || width % 2) {
        std::fprintf(stderr, "orbis-make-world: --width must be an even number from 64 to 65536\n");
        return 2;
    }
    const int height = width / 2;
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) {
        std::fprintf(stderr, "orbis-make-world: %s: %s\n", out.string().c_str(), ec.message().c_str());
        return 1;
    }
    GDALAllRegister();
    const Noise noise(20261124u);
    std::vector<int16_t> relief(size_t(width) * size_t(height));
    std::vector<uint8_t> colour(size_t(width) * size_t(height) * 3);
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (int j = int(t); j < height; j += int(threads)) {
                const double lat = 90.0 - (j + 0.5) * 180.0 / height;
                for (int i = 0; i < width; ++i) {
                    const double lon = -180.0 + (i + 0.5) * 360.0 / width;
                    const Sample s = planet(noise, lon, lat);
                    const size_t k = size_t(j) * size_t(width) + size_t(i);
                    relief[k] = int16_t(std::lround(s.height));
                    std::copy(s.rgb, s.rgb + 3, &colour[k * 3]);
                }
            }
        });
    for (auto& th : pool) th.join();
    const std::string reliefPath = (out / "world-relief.tif").string(), colourPath = (out / "world-colour.tif").string();
    if (!writeTiff(reliefPath, width, height, GDT_Int16, 1, relief.data(), nullptr) ||
        !writeTiff(colourPath, width, height, GDT_Byte, 3, colour.data(), "PHOTOMETRIC=RGB")) {
        std::fprintf(stderr, "orbis-make-world: cannot write into %s: %s\n", out.string().c_str(), CPLGetLastErrorMsg());
        return 1;
    }
    std::printf("orbis-make-world: wrote %s and %s (%dx%d)\n", reliefPath.c_str(), colourPath.c_str(), width, height);
    return 0;
}
