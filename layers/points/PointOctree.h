#pragma once
// A point cloud organised for drawing within a point budget (CPU only, no Vulkan).
//
// An octree over an ECEF-aligned cube around the cloud. Every point has a pseudo-random key
// (a hash of its index in the file and the seed); points are inserted in key order, and a
// node keeps the first `capacity` points that reach it and passes the rest to its children. So
// every node holds a uniform random subsample of its cube, a node and its ancestors together
// are a denser sample, and each point lives in exactly one node: drawing a node and its
// ancestors draws each of their points once. A renderer draws the nodes with the largest
// screen size first until the budget is spent; with no budget it draws every node.
//
// Because the order is a function of each point's index, a subtree can be built on its own
// from the points in its cube (less those its ancestors took), which is how clouds larger than
// memory are built chunk by chunk (PointStore) into exactly the tree built here in one go.

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace orbis::points {

/// A point on its way into the octree: ECEF position and what the shaders need of it. The
/// record of the out-of-core build's temporary files too (40 bytes).
struct PointRecord {
    glm::dvec3 ecef{0.0};
    uint32_t rgbClass = 0;    ///< sRGB r | g << 8 | b << 16 | classification << 24
    uint32_t intensity = 0;   ///< 16 bits
    uint64_t id = 0;          ///< the point's index in the file: its key comes from it
};
static_assert(sizeof(PointRecord) == 40);

/// The insertion order: a 64-bit hash of a point's index and the seed.
uint64_t pointKey(uint64_t id, uint64_t seed);

/// An octree cell: its cube in ECEF and its level (0: the root).
struct Cube {
    glm::dvec3 centre{0.0};
    double halfSize = 0.0;
    uint32_t level = 0;
    /// The cube around [lo, hi] the root of a cloud with those bounds gets.
    static Cube around(const glm::dvec3& lo, const glm::dvec3& hi);
    /// Which child a point descends to (bit 0: x >= centre, 1: y, 2: z).
    int octant(const glm::dvec3& p) const {
        return (p.x >= centre.x ? 1 : 0) | (p.y >= centre.y ? 2 : 0) | (p.z >= centre.z ? 4 : 0);
    }
    Cube child(int octant) const;
};

struct OctreeNode {
    glm::dvec3 centre{0.0};   ///< ECEF, metres: the centre of the node's cube
    double halfSize = 0.0;    ///< half the cube's edge (m)
    uint64_t first = 0;       ///< its points: [first, first + count) of order()
    uint32_t count = 0;
    int32_t parent = -1;
    int32_t children[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    uint8_t level = 0;
    Cube cube() const { return {centre, halfSize, level}; }
};

class PointOctree {
public:
    struct Options {
        uint32_t capacity = 16384;   ///< points a node keeps before passing points to its children
        uint32_t maxLevel = 20;      ///< the deepest level keeps every point that reaches it
        uint64_t seed = 1;           ///< the keys (the result depends on nothing else)
    };

    /// Builds over `points` (non-finite positions are left out). The root is the cube around
    /// the points, or `root` (a subtree of a larger tree: its points must lie in it).
    static PointOctree build(std::span<const PointRecord> points, const Options& options,
                             std::optional<Cube> root = std::nullopt);

    const std::vector<OctreeNode>& nodes() const { return nodes_; }
    /// Node by node, each node's points in key order: indices into the points built over.
    const std::vector<uint32_t>& order() const { return order_; }
    uint64_t points() const { return order_.size(); }
    uint32_t depth() const { return depth_; }

private:
    std::vector<OctreeNode> nodes_;
    std::vector<uint32_t> order_;
    uint32_t depth_ = 0;
};

}  // namespace orbis::points
