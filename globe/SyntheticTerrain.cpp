#include "globe/SyntheticTerrain.h"

#include "globe/Ellipsoid.h"

#include <cmath>

namespace orbis::globe {
namespace {

uint32_t hash(int64_t x, int64_t y, int64_t z, uint32_t seed) {
    uint64_t h = uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^ uint64_t(z) * 0x165667B19E3779F9ull ^ seed;
    h ^= h >> 31;
    h *= 0xD6E8FEB86659FD93ull;
    h ^= h >> 32;
    return uint32_t(h);
}

/// A unit-ish gradient at a lattice point: one of 12 edge directions of a cube.
double gradientDot(uint32_t h, double dx, double dy, double dz) {
    switch (h % 12) {
        case 0: return dx + dy;
        case 1: return -dx + dy;
        case 2: return dx - dy;
        case 3: return -dx - dy;
        case 4: return dx + dz;
        case 5: return -dx + dz;
        case 6: return dx - dz;
        case 7: return -dx - dz;
        case 8: return dy + dz;
        case 9: return -dy + dz;
        case 10: return dy - dz;
        default: return -dy - dz;
    }
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/// Gradient noise in about [-1, 1].
double noise(double x, double y, double z, uint32_t seed) {
    const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int64_t ix = int64_t(fx), iy = int64_t(fy), iz = int64_t(fz);
    const double dx = x - fx, dy = y - fy, dz = z - fz;
    double corners[8];
    for (int c = 0; c < 8; ++c) {
        const int ox = c & 1, oy = (c >> 1) & 1, oz = (c >> 2) & 1;
        corners[c] = gradientDot(hash(ix + ox, iy + oy, iz + oz, seed), dx - ox, dy - oy, dz - oz);
    }
    const double u = fade(dx), v = fade(dy), w = fade(dz);
    auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
    const double x00 = lerp(corners[0], corners[1], u), x10 = lerp(corners[2], corners[3], u);
    const double x01 = lerp(corners[4], corners[5], u), x11 = lerp(corners[6], corners[7], u);
    return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

}  // namespace

HeightAt syntheticTerrain(const SyntheticTerrainOptions& options) {
    return [options](double lonDeg, double latDeg) -> std::optional<double> {
        const glm::dvec3 p = Ellipsoid::wgs84().toEcef(lonDeg, latDeg, 0.0);
        double h = options.base, amplitude = options.relief, wavelength = options.wavelengthM;
        for (int o = 0; o < options.octaves; ++o) {
            const double n = noise(p.x / wavelength, p.y / wavelength, p.z / wavelength, options.seed + uint32_t(o) * 7919u);
            // Ridged in the large octaves (crests and valleys), smooth in the small ones.
            h += amplitude * (o < 2 ? (0.6 - std::abs(n)) * 1.6 : n);
            amplitude *= 0.5;
            wavelength *= 0.5;
        }
        return h;
    };
}

}  // namespace orbis::globe
