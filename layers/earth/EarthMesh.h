#pragma once
// The tessellated WGS84 ellipsoid, cut into lon/lat patches. Each patch has a double-precision
// origin (its centre on the ellipsoid) and float vertices relative to it, so the GPU never sees
// ECEF coordinates. Patches never cross the antimeridian; polar rows close at the poles.
// No Vulkan: built and tested on the CPU.

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace orbis::layers {

struct EarthVertex {
    glm::vec3 position;   ///< relative to the patch origin, metres
    glm::vec3 normal;     ///< geodetic surface normal
    glm::vec2 lonLatDeg;
};
static_assert(sizeof(EarthVertex) == 32, "vertex layout is declared to Vulkan in EarthLayer.cpp");

struct EarthPatch {
    glm::dvec3 origin;       ///< ECEF
    double radius = 0.0;     ///< bounding sphere around origin
    double lonMinDeg = 0.0, latMinDeg = 0.0;
};

struct EarthMesh {
    double patchDeg = 10.0;
    int segments = 16;                   ///< quads per patch side
    std::vector<EarthPatch> patches;
    std::vector<EarthVertex> vertices;   ///< verticesPerPatch() per patch, patch after patch
    std::vector<uint32_t> indices;       ///< one patch's triangles (shared; counter-clockwise seen from outside)

    uint32_t verticesPerPatch() const { return uint32_t((segments + 1) * (segments + 1)); }

    /// patchDeg must divide 180; segments in [1, 256].
    static EarthMesh build(double patchDeg, int segments);
};

}  // namespace orbis::layers
