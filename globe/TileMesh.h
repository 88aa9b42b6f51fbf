#pragma once
// The vertex grid of one terrain tile: N x N vertices on the ellipsoid over the tile's extent,
// positions relative to the tile's centre (computed in double, stored as float: the GPU never
// sees ECEF), plus a skirt hanging from each edge to hide cracks between tiles of different
// levels. Heights come later, on the GPU, from the elevation texture along the stored normal.
// The same index list serves every tile. No Vulkan.

#include "globe/Ellipsoid.h"
#include "globe/TileKey.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace orbis::globe {

/// 32 bytes. Matches the vertex attributes of shaders/terrain/terrain.vert.
struct TileVertex {
    float position[3];      ///< on the ellipsoid, relative to TileMesh::center, metres
    int16_t normal[4];      ///< snorm: geodetic up (xyz); w = 32767 on skirt vertices, else 0
    uint16_t uv[2];         ///< unorm: u east, v south over the tile (0..1)
    float cellMetres[2];    ///< east and north size of one grid cell here (for slopes)
};
static_assert(sizeof(TileVertex) == 32);

struct TileMesh {
    glm::dvec3 center{0.0};           ///< ECEF of the tile centre at height 0
    std::vector<TileVertex> vertices; ///< grid rows north to south, then the 4 skirts
};

/// Vertices in the mesh of a grid of `n` x `n` (n >= 2): n*n + 4*n.
inline uint32_t tileVertexCount(int n) { return uint32_t(n * n + 4 * n); }

/// Builds the vertices of `key`'s mesh (closed-form geodetic -> ECEF in double, with the
/// per-row and per-column trigonometry computed once: ~10 us for 65 x 65).
TileMesh buildTileMesh(const TileKey& key, int n, const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

/// Triangle list for any tile mesh of grid size `n` (grid plus skirts).
std::vector<uint32_t> buildTileIndices(int n);

}  // namespace orbis::globe
