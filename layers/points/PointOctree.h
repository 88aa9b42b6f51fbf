#pragma once
// A point cloud organised for drawing within a point budget (CPU only, no Vulkan).
//
// An octree over an ECEF-aligned cube around the cloud. Points are inserted in a shuffled
// order; a node keeps the first `capacity` points that reach it and passes the rest to its
// children. So every node holds a uniform random subsample of its cube, a node and its
// ancestors together are a denser sample, and each point lives in exactly one node: drawing a
// node and its ancestors draws each of their points once. A renderer draws the nodes with the
// largest screen size first until the budget is spent; with no budget it draws every node.
//
// Points are stored node by node, as floats relative to the node's centre (double): a node
// 2 km across keeps 0.1 mm, a node 1 m across 0.1 um.

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::points {

/// A point's packed attributes, as the shaders read them (shaders/points/PointColor.glsl):
/// rgbClass = sRGB r | g << 8 | b << 16 | classification << 24;
/// intensityHeight = intensity | height << 16 (0..65535 over the cloud's height range).
struct PackedAttributes {
    uint32_t rgbClass = 0;
    uint32_t intensityHeight = 0;
};

struct OctreeNode {
    glm::dvec3 centre{0.0};   ///< ECEF, metres: the centre of the node's cube
    double halfSize = 0.0;    ///< half the cube's edge (m)
    uint64_t first = 0;       ///< its points: [first, first + count) of the octree's arrays
    uint32_t count = 0;
    int32_t parent = -1;
    int32_t children[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    uint8_t level = 0;
    /// Radius of the sphere around the centre that holds the node's points and every
    /// descendant's (for culling and screen size).
    double radius() const { return halfSize * 1.7320508075688772; }
};

class PointOctree {
public:
    struct Options {
        uint32_t capacity = 16384;   ///< points a node keeps before passing points to its children
        uint32_t maxLevel = 20;      ///< the deepest level keeps every point that reaches it
        uint64_t seed = 1;           ///< the shuffle (the result depends on nothing else)
    };

    /// Builds over `ecef` (NaN positions are left out) with one PackedAttributes per point.
    static PointOctree build(std::span<const glm::dvec3> ecef, std::span<const PackedAttributes> attributes,
                             const Options& options);
    static PointOctree build(std::span<const glm::dvec3> ecef, std::span<const PackedAttributes> attributes) {
        return build(ecef, attributes, Options{});
    }

    const std::vector<OctreeNode>& nodes() const { return nodes_; }
    /// Node by node: 3 floats a point relative to its node's centre.
    const std::vector<float>& positions() const { return positions_; }
    const std::vector<PackedAttributes>& attributes() const { return attributes_; }
    uint64_t points() const { return attributes_.size(); }
    /// The ECEF position of point i (double; for tests).
    glm::dvec3 position(uint64_t i) const;
    uint32_t depth() const { return depth_; }

private:
    std::vector<OctreeNode> nodes_;
    std::vector<float> positions_;
    std::vector<PackedAttributes> attributes_;
    uint32_t depth_ = 0;
};

}  // namespace orbis::points
