#include "layers/earth/EarthMesh.h"

#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>

namespace orbis::layers {

EarthMesh EarthMesh::build(double patchDeg, int segments) {
    const auto& ell = globe::Ellipsoid::wgs84();
    EarthMesh mesh;
    mesh.patchDeg = patchDeg;
    mesh.segments = segments;
    const int nLon = static_cast<int>(std::lround(360.0 / patchDeg));
    const int nLat = static_cast<int>(std::lround(180.0 / patchDeg));
    const int n = segments + 1;
    mesh.vertices.reserve(size_t(nLon) * nLat * n * n);
    for (int j = 0; j < nLat; ++j) {
        for (int i = 0; i < nLon; ++i) {
            EarthPatch patch;
            patch.lonMinDeg = -180.0 + i * patchDeg;
            patch.latMinDeg = -90.0 + j * patchDeg;
            patch.origin = ell.toEcef(patch.lonMinDeg + 0.5 * patchDeg, patch.latMinDeg + 0.5 * patchDeg, 0.0);
            double radius = 0.0;
            for (int y = 0; y < n; ++y) {
                // Exact grid values at patch edges, so neighbours share bit-identical vertices.
                const double lat = y == segments ? patch.latMinDeg + patchDeg : patch.latMinDeg + patchDeg * y / segments;
                for (int x = 0; x < n; ++x) {
                    const double lon = x == segments ? patch.lonMinDeg + patchDeg : patch.lonMinDeg + patchDeg * x / segments;
                    const glm::dvec3 p = ell.toEcef(lon, lat, 0.0) - patch.origin;
                    radius = std::max(radius, glm::length(p));
                    mesh.vertices.push_back({glm::vec3(p), glm::vec3(ell.surfaceNormal(lon, lat)),
                                             glm::vec2(float(lon), float(lat))});
                }
            }
            patch.radius = radius * 1.001 + 1.0;   // float rounding of the vertices
            mesh.patches.push_back(patch);
        }
    }
    for (int y = 0; y < segments; ++y) {
        for (int x = 0; x < segments; ++x) {
            const uint32_t a = uint32_t(y * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
            // east x north = up: (a, b, d) and (a, d, c) wind counter-clockwise from outside.
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    }
    return mesh;
}

}  // namespace orbis::layers
