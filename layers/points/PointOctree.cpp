#include "layers/points/PointOctree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace orbis::points {
namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

uint64_t pointKey(uint64_t id, uint64_t seed) {
    // splitmix64's finaliser over the index offset by the seed: distinct indices, distinct keys.
    uint64_t z = id + (seed + 1) * 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

Cube Cube::around(const glm::dvec3& lo, const glm::dvec3& hi) {
    Cube c;
    c.centre = 0.5 * (lo + hi);
    const glm::dvec3 extent = hi - lo;
    c.halfSize = std::max(0.5 * std::max({extent.x, extent.y, extent.z}) * (1.0 + 1e-9), 1e-3);
    return c;
}

Cube Cube::child(int octant) const {
    Cube c;
    c.halfSize = 0.5 * halfSize;
    c.centre = centre + c.halfSize * glm::dvec3((octant & 1) ? 1 : -1, (octant & 2) ? 1 : -1, (octant & 4) ? 1 : -1);
    c.level = level + 1;
    return c;
}

PointOctree PointOctree::build(std::span<const PointRecord> points, const Options& options, std::optional<Cube> root) {
    PointOctree tree;
    // The finite points in key order (ties, which need equal keys, broken by id).
    struct Keyed {
        uint64_t key;
        uint64_t id;
        uint32_t index;
    };
    std::vector<Keyed> keyed;
    keyed.reserve(points.size());
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (size_t i = 0; i < points.size(); ++i)
        if (finite(points[i].ecef)) {
            keyed.push_back({pointKey(points[i].id, options.seed), points[i].id, uint32_t(i)});
            lo = glm::min(lo, points[i].ecef);
            hi = glm::max(hi, points[i].ecef);
        }
    if (keyed.empty()) return tree;
    std::sort(keyed.begin(), keyed.end(),
              [](const Keyed& a, const Keyed& b) { return a.key != b.key ? a.key < b.key : a.id < b.id; });

    const Cube rootCube = root ? *root : Cube::around(lo, hi);
    OctreeNode first;
    first.centre = rootCube.centre;
    first.halfSize = rootCube.halfSize;
    first.level = uint8_t(rootCube.level);
    tree.nodes_.push_back(first);
    tree.depth_ = rootCube.level;
    const uint32_t capacity = std::max(1u, options.capacity);

    // Each point goes to the first node on its path that has room (the deepest keeps all).
    std::vector<uint32_t> nodeOf(keyed.size());
    for (size_t k = 0; k < keyed.size(); ++k) {
        const glm::dvec3& p = points[keyed[k].index].ecef;
        int32_t node = 0;
        for (;;) {
            OctreeNode& nd = tree.nodes_[size_t(node)];
            if (nd.count < capacity || nd.level >= options.maxLevel) {
                ++nd.count;
                nodeOf[k] = uint32_t(node);
                break;
            }
            const int octant = nd.cube().octant(p);
            int32_t child = nd.children[octant];
            if (child < 0) {
                const Cube cc = nd.cube().child(octant);
                OctreeNode c;
                c.centre = cc.centre;
                c.halfSize = cc.halfSize;
                c.parent = node;
                c.level = uint8_t(cc.level);
                child = int32_t(tree.nodes_.size());
                nd.children[octant] = child;
                tree.nodes_.push_back(c);   // (nd is not used after this)
                tree.depth_ = std::max<uint32_t>(tree.depth_, c.level);
            }
            node = child;
        }
    }
    // Node by node, each node's points in key order (a prefix of a node is a uniform sample
    // of it too).
    uint64_t offset = 0;
    for (OctreeNode& nd : tree.nodes_) {
        nd.first = offset;
        offset += nd.count;
    }
    std::vector<uint64_t> cursor(tree.nodes_.size());
    for (size_t i = 0; i < tree.nodes_.size(); ++i) cursor[i] = tree.nodes_[i].first;
    tree.order_.resize(keyed.size());
    for (size_t k = 0; k < keyed.size(); ++k) tree.order_[cursor[nodeOf[k]]++] = keyed[k].index;
    return tree;
}

}  // namespace orbis::points
