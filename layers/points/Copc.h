#pragma once
// COPC (Cloud Optimized Point Cloud, COPC 1.0): a LAZ 1.4 file whose chunks are the nodes of an
// octree, described by the `copc` info VLR (the first VLR: the root cube, the spacing, where the
// hierarchy starts) and hierarchy pages (one entry per node: its key, where its chunk is, how many
// points; an entry of -1 points is another page). CPU only; the bytes come through LasFile, so a
// local file and a remote one read the same.
//
// Every page and chunk an entry names is checked to lie inside the file, keys to lie inside their
// level, each page to be read once (a page that refers back to one already read is an error, not
// a loop), and the node and page counts to be bounded by the file's size.

#include "base/Result.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::points {

class LasFile;

namespace copc {

/// The `copc` info VLR (user "copc", record 1, 160 bytes).
struct Info {
    glm::dvec3 centre{0.0};   ///< the root cube's centre (the file's CRS units)
    double halfSize = 0.0;
    double spacing = 0.0;     ///< the root's point spacing; level d's is spacing / 2^d
    uint64_t rootPageOffset = 0, rootPageBytes = 0;
    double gpsTimeMin = 0.0, gpsTimeMax = 0.0;
};

/// An octree cell: level d and its index (x, y, z) in [0, 2^d) on each axis.
struct Key {
    int32_t d = 0, x = 0, y = 0, z = 0;
    bool operator==(const Key&) const = default;
    Key child(int octant) const { return {d + 1, 2 * x + (octant & 1), 2 * y + ((octant >> 1) & 1), 2 * z + ((octant >> 2) & 1)}; }
    Key parent() const { return {d - 1, x >> 1, y >> 1, z >> 1}; }
};

/// A node with points: its key and its chunk.
struct Node {
    Key key;
    uint64_t offset = 0;   ///< the chunk's first byte in the file
    uint32_t bytes = 0;
    uint32_t points = 0;
};

Result<Info> parseInfo(std::span<const uint8_t> payload);

/// Reads every hierarchy page from the root page, through `file`. Errors name the page or entry.
Result<std::vector<Node>> readHierarchy(const LasFile& file, const Info& info);

/// A node's cube in the file's CRS: its centre and half its edge.
inline void cube(const Info& info, const Key& k, glm::dvec3& centre, double& halfSize) {
    const double size = 2.0 * info.halfSize / double(int64_t(1) << k.d);
    halfSize = 0.5 * size;
    centre = info.centre - glm::dvec3(info.halfSize) + (glm::dvec3(k.x, k.y, k.z) + 0.5) * size;
}

}  // namespace copc
}  // namespace orbis::points
