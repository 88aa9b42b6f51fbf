#include "layers/points/PointOctree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace orbis::points {
namespace {

uint64_t splitmix(uint64_t& state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

PointOctree PointOctree::build(std::span<const glm::dvec3> ecef, std::span<const PackedAttributes> attributes,
                               const Options& options) {
    PointOctree tree;
    const size_t n = std::min(ecef.size(), attributes.size());
    // The shuffled order of the finite points.
    std::vector<uint32_t> order;
    order.reserve(n);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (size_t i = 0; i < n; ++i)
        if (finite(ecef[i])) {
            order.push_back(uint32_t(i));
            lo = glm::min(lo, ecef[i]);
            hi = glm::max(hi, ecef[i]);
        }
    if (order.empty()) return tree;
    uint64_t state = options.seed;
    for (size_t i = order.size() - 1; i > 0; --i) std::swap(order[i], order[splitmix(state) % (i + 1)]);

    OctreeNode root;
    root.centre = 0.5 * (lo + hi);
    const glm::dvec3 extent = hi - lo;
    root.halfSize = std::max(0.5 * std::max({extent.x, extent.y, extent.z}) * (1.0 + 1e-9), 1e-3);
    tree.nodes_.push_back(root);
    const uint32_t capacity = std::max(1u, options.capacity);

    // Each point goes to the first node on its path that has room (the deepest keeps all).
    std::vector<uint32_t> nodeOf(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        const glm::dvec3& p = ecef[order[k]];
        int32_t node = 0;
        for (;;) {
            OctreeNode& nd = tree.nodes_[size_t(node)];
            if (nd.count < capacity || nd.level >= options.maxLevel) {
                ++nd.count;
                nodeOf[k] = uint32_t(node);
                break;
            }
            const int octant = (p.x >= nd.centre.x ? 1 : 0) | (p.y >= nd.centre.y ? 2 : 0) | (p.z >= nd.centre.z ? 4 : 0);
            int32_t child = nd.children[octant];
            if (child < 0) {
                OctreeNode c;
                c.halfSize = 0.5 * nd.halfSize;
                c.centre = nd.centre + c.halfSize * glm::dvec3((octant & 1) ? 1 : -1, (octant & 2) ? 1 : -1, (octant & 4) ? 1 : -1);
                c.parent = node;
                c.level = uint8_t(nd.level + 1);
                child = int32_t(tree.nodes_.size());
                tree.nodes_[size_t(node)].children[octant] = child;   // (nd may move below)
                tree.nodes_.push_back(c);
                tree.depth_ = std::max<uint32_t>(tree.depth_, c.level);
            }
            node = child;
        }
    }
    // Node by node, each node's points in the shuffled order (a prefix of a node is a uniform
    // sample of it too).
    uint64_t offset = 0;
    for (OctreeNode& nd : tree.nodes_) {
        nd.first = offset;
        offset += nd.count;
    }
    std::vector<uint64_t> cursor(tree.nodes_.size());
    for (size_t i = 0; i < tree.nodes_.size(); ++i) cursor[i] = tree.nodes_[i].first;
    tree.positions_.resize(3 * order.size());
    tree.attributes_.resize(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        const OctreeNode& nd = tree.nodes_[nodeOf[k]];
        const uint64_t at = cursor[nodeOf[k]]++;
        const glm::dvec3 rel = ecef[order[k]] - nd.centre;
        tree.positions_[3 * at] = float(rel.x);
        tree.positions_[3 * at + 1] = float(rel.y);
        tree.positions_[3 * at + 2] = float(rel.z);
        tree.attributes_[at] = attributes[order[k]];
    }
    return tree;
}

glm::dvec3 PointOctree::position(uint64_t i) const {
    // Nodes are stored in the order of their points: the last node starting at or before i.
    auto it = std::upper_bound(nodes_.begin(), nodes_.end(), i,
                               [](uint64_t v, const OctreeNode& nd) { return v < nd.first; });
    const OctreeNode& nd = *(it - 1);
    return nd.centre + glm::dvec3(positions_[3 * i], positions_[3 * i + 1], positions_[3 * i + 2]);
}

}  // namespace orbis::points
