#include "globe/TileMesh.h"

#include <algorithm>
#include <cmath>

namespace orbis::globe {
namespace {

int16_t snorm(double v) { return int16_t(std::lround(std::clamp(v, -1.0, 1.0) * 32767.0)); }
uint16_t unorm(double v) { return uint16_t(std::lround(std::clamp(v, 0.0, 1.0) * 65535.0)); }

}  // namespace

TileMesh buildTileMesh(const TileKey& key, int n, const Ellipsoid& ellipsoid) {
    const GeoExtent e = key.extent();
    const double a = ellipsoid.equatorialRadius(), f = ellipsoid.flattening();
    const double e2 = f * (2.0 - f);
    constexpr double kDeg = 3.14159265358979323846 / 180.0;

    // Exact extent edges at the first and last row/column, so neighbours share positions.
    const size_t count = size_t(n);
    std::vector<double> cosLon(count), sinLon(count), cosLat(count), sinLat(count), radiusN(count);
    for (int i = 0; i < n; ++i) {
        const double t = double(i) / double(n - 1);
        const double lon = i == n - 1 ? e.east : e.west + t * e.width();
        const double lat = i == n - 1 ? e.south : e.north - t * e.height();
        cosLon[size_t(i)] = std::cos(lon * kDeg);
        sinLon[size_t(i)] = std::sin(lon * kDeg);
        // Exact zeros at the poles: cos(90 deg) in double is 6e-17, which would put the pole
        // vertices of neighbouring tiles a few nanometres apart.
        cosLat[size_t(i)] = std::abs(lat) == 90.0 ? 0.0 : std::cos(lat * kDeg);
        sinLat[size_t(i)] = lat == 90.0 ? 1.0 : lat == -90.0 ? -1.0 : std::sin(lat * kDeg);
        radiusN[size_t(i)] = a / std::sqrt(1.0 - e2 * sinLat[size_t(i)] * sinLat[size_t(i)]);
    }

    TileMesh mesh;
    mesh.center = ellipsoid.toEcef(e.centerLon(), e.centerLat(), 0.0);
    mesh.vertices.resize(tileVertexCount(n));
    const double dLon = e.width() * kDeg / double(n - 1), dLat = e.height() * kDeg / double(n - 1);
    for (int j = 0; j < n; ++j) {
        const double cl = cosLat[size_t(j)], sl = sinLat[size_t(j)], N = radiusN[size_t(j)];
        // Meridional radius of curvature M = N (1 - e^2) / (1 - e^2 sin^2).
        const double M = N * (1.0 - e2) / (1.0 - e2 * sl * sl);
        const float cellEast = float(N * cl * dLon), cellNorth = float(M * dLat);
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 p(N * cl * cosLon[size_t(i)], N * cl * sinLon[size_t(i)], N * (1.0 - e2) * sl);
            const glm::dvec3 up(cl * cosLon[size_t(i)], cl * sinLon[size_t(i)], sl);
            const glm::dvec3 r = p - mesh.center;
            TileVertex& v = mesh.vertices[size_t(j * n + i)];
            v.position[0] = float(r.x);
            v.position[1] = float(r.y);
            v.position[2] = float(r.z);
            v.normal[0] = snorm(up.x);
            v.normal[1] = snorm(up.y);
            v.normal[2] = snorm(up.z);
            v.normal[3] = 0;
            v.uv[0] = unorm(double(i) / double(n - 1));
            v.uv[1] = unorm(double(j) / double(n - 1));
            v.cellMetres[0] = cellEast;
            v.cellMetres[1] = cellNorth;
        }
    }
    // Skirts: copies of the edge vertices flagged so the vertex shader lowers them.
    size_t s = size_t(n) * size_t(n);
    const auto skirt = [&](int i, int j) {
        TileVertex v = mesh.vertices[size_t(j * n + i)];
        v.normal[3] = 32767;
        mesh.vertices[s++] = v;
    };
    for (int i = 0; i < n; ++i) skirt(i, 0);          // north edge
    for (int i = 0; i < n; ++i) skirt(i, n - 1);      // south edge
    for (int j = 0; j < n; ++j) skirt(0, j);          // west edge
    for (int j = 0; j < n; ++j) skirt(n - 1, j);      // east edge
    return mesh;
}

std::vector<uint32_t> buildTileIndices(int n) {
    std::vector<uint32_t> idx;
    idx.reserve(size_t(n - 1) * size_t(n - 1) * 6 + size_t(n - 1) * 24);
    const auto at = [n](int i, int j) { return uint32_t(j * n + i); };
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const uint32_t nw = at(i, j), ne = at(i + 1, j), sw = at(i, j + 1), se = at(i + 1, j + 1);
            // Counter-clockwise seen from above (east x north = up).
            idx.insert(idx.end(), {sw, se, ne, sw, ne, nw});
        }
    const uint32_t base = uint32_t(n * n);
    const auto strip = [&](uint32_t skirtStart, auto edgeVertex) {
        for (int k = 0; k + 1 < n; ++k) {
            const uint32_t t0 = edgeVertex(k), t1 = edgeVertex(k + 1);
            const uint32_t b0 = skirtStart + uint32_t(k), b1 = b0 + 1;
            idx.insert(idx.end(), {t0, b0, b1, t0, b1, t1});   // drawn without culling
        }
    };
    strip(base, [&](int k) { return at(k, 0); });
    strip(base + uint32_t(n), [&](int k) { return at(k, n - 1); });
    strip(base + 2 * uint32_t(n), [&](int k) { return at(0, k); });
    strip(base + 3 * uint32_t(n), [&](int k) { return at(n - 1, k); });
    return idx;
}

}  // namespace orbis::globe
