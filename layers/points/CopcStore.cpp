// A COPC file's own octree as a PointStore: its hierarchy becomes the node table (cubes placed
// in ECEF through the cloud's georeference), and a node's data is its LAZ chunk decoded and
// encoded for the GPU when the renderer first wants it. No pass over the points, no cache file:
// the first frame needs the hierarchy and the root node only.
#include "layers/points/PointCloud.h"
#include "layers/points/PointStoreFormat.h"

#include "base/Log.h"
#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>
#include <tuple>

namespace orbis::points {
namespace {

using KeyTuple = std::tuple<int32_t, int32_t, int32_t, int32_t>;
KeyTuple tupleOf(const copc::Key& k) { return {k.d, k.x, k.y, k.z}; }

/// Where a node's points are in the file (points 0: a node that only leads to others).
struct Chunk {
    uint64_t offset = 0;
    uint32_t bytes = 0, points = 0;
};

/// How colours are stored: 16-bit values, or 8-bit ones in the 16-bit fields.
uint32_t packColour(const LasPoint& p, bool rgb, bool rgb16) {
    if (!rgb) return 0xFFFFFFu;
    const auto channel = [&](uint16_t v) { return uint32_t(rgb16 ? v >> 8 : std::min<uint16_t>(v, 255)); };
    return channel(p.red) | channel(p.green) << 8 | channel(p.blue) << 16;
}

}  // namespace

Result<std::shared_ptr<PointStore>> loadCopcStore(std::shared_ptr<const LasFile> file, const PointGeoreference& georef,
                                                  const PointLoadOptions& options) {
    const copc::Info info = *file->copc();
    // A file on a server: the nodes it sends are kept on the disk, for the next view of them
    // and the next run (the cache folder's "remote" folder).
    if (file->remote())
        file->cacheRemoteReads((std::filesystem::path(options.cacheFolder.empty() ? defaultPointCacheDir() : options.cacheFolder) / "remote").string());
    auto hierarchy = copc::readHierarchy(*file, info);
    if (!hierarchy) return hierarchy.error();
    if (options.progress) options.progress(0.3);

    // Every node and its ancestors (a writer may leave out empty ones), numbered breadth first
    // from the root so that a parent comes before its children.
    std::map<KeyTuple, Chunk> chunks;
    for (const copc::Node& n : *hierarchy) {
        chunks[tupleOf(n.key)] = {n.offset, n.bytes, n.points};
        for (copc::Key k = n.key; k.d > 0;) {
            k = k.parent();
            chunks.try_emplace(tupleOf(k));
        }
    }
    chunks.try_emplace(KeyTuple{0, 0, 0, 0});
    std::vector<copc::Key> keys;
    std::vector<Chunk> where;
    std::map<KeyTuple, int32_t> index;
    std::vector<StoredNode> nodes;
    for (std::deque<std::pair<copc::Key, int32_t>> queue{{copc::Key{}, -1}}; !queue.empty(); queue.pop_front()) {
        const auto [key, parent] = queue.front();
        const int32_t i = int32_t(nodes.size());
        index[tupleOf(key)] = i;
        keys.push_back(key);
        where.push_back(chunks[tupleOf(key)]);
        StoredNode s;
        s.parent = parent;
        s.level = uint32_t(key.d);
        s.count = where.back().points;
        nodes.push_back(s);
        if (parent >= 0) {
            const copc::Key up = key.parent();
            const int octant = (key.x - 2 * up.x) | (key.y - 2 * up.y) << 1 | (key.z - 2 * up.z) << 2;
            nodes[size_t(parent)].children[octant] = i;
        }
        for (int c = 0; c < 8; ++c)
            if (chunks.count(tupleOf(key.child(c)))) queue.emplace_back(key.child(c), i);
    }

    // The cubes on the globe: each node's centre and corners through the georeference; the ECEF
    // cube around them (with room for the curvature of the cube's faces) holds its points.
    std::vector<glm::dvec3> xyz;
    xyz.reserve(keys.size() * 9);
    for (const copc::Key& k : keys) {
        glm::dvec3 c;
        double h;
        copc::cube(info, k, c, h);
        xyz.push_back(c);
        for (int corner = 0; corner < 8; ++corner)
            xyz.push_back(c + h * glm::dvec3((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1));
    }
    georef.toEcef(xyz);
    double tolerance = 0.5 * georef.resolutionMetres(*file);
    if (!std::isfinite(tolerance)) tolerance = 0.0005;
    tolerance = std::clamp(tolerance, 1e-6, 0.01);
    uint32_t depth = 0;
    for (size_t i = 0; i < nodes.size(); ++i) {
        const glm::dvec3 centre = xyz[9 * i];
        double half = 0.0;
        for (int corner = 1; corner <= 8; ++corner) {
            const glm::dvec3 d = glm::abs(xyz[9 * i + size_t(corner)] - centre);
            half = std::max({half, d.x, d.y, d.z});
        }
        if (!std::isfinite(half) || !std::isfinite(centre.x))
            return makeError(std::string(file->path()).append(": the COPC octree's cube at level ").append(std::to_string(keys[i].d))
                                 .append(" cannot be placed on the globe with ").append(georef.description()));
        nodes[i].centre = centre;
        nodes[i].halfSize = half * 1.01 + 1e-3;
        const double step = store::quantisationStep(nodes[i].halfSize);
        nodes[i].step = step <= tolerance ? step : 0.0;
        depth = std::max(depth, nodes[i].level);
    }

    // The root's points: the colours' depth and the intensities' range (the renderer's gain).
    const LasHeader& h = file->header();
    CloudInfo cloud;
    cloud.read = cloud.points = h.pointCount;
    cloud.depth = depth;
    cloud.rgb = h.hasRgb() ? 1 : 0;
    cloud.tolerance = float(tolerance);
    std::vector<LasPoint> sample;
    if (where[0].points > 0)
        if (auto r = file->readChunk(where[0].offset, where[0].bytes, where[0].points, sample); !r) return r.error();
    for (const LasPoint& p : sample) cloud.rgb16 |= std::max({p.red, p.green, p.blue}) > 255 ? 1 : 0;
    std::vector<uint16_t> intensities;
    for (const LasPoint& p : sample) intensities.push_back(p.intensity);
    if (!intensities.empty()) {
        auto p99 = intensities.begin() + ptrdiff_t(intensities.size() * 99 / 100);
        std::nth_element(intensities.begin(), p99, intensities.end());
        cloud.intensityGain = 1.0f / float(std::max<uint16_t>(*p99, 1));
    }
    // Heights: the header's box on the globe.
    std::vector<glm::dvec3> box;
    for (int c = 0; c < 8; ++c) box.push_back({(c & 1) ? h.max.x : h.min.x, (c & 2) ? h.max.y : h.min.y, (c & 4) ? h.max.z : h.min.z});
    georef.toEcef(box);
    cloud.heightMin = 1e300, cloud.heightMax = -1e300;
    for (const glm::dvec3& b : box)
        if (std::isfinite(b.x)) {
            const double height = globe::Ellipsoid::wgs84().toGeodetic(b).height;
            cloud.heightMin = std::min(cloud.heightMin, height), cloud.heightMax = std::max(cloud.heightMax, height);
        }
    if (cloud.heightMin > cloud.heightMax) cloud.heightMin = cloud.heightMax = 0.0;
    store::Packing packing;
    packing.heightMin = cloud.heightMin;
    packing.heightSpan = cloud.heightMax > cloud.heightMin ? cloud.heightMax - cloud.heightMin : 1.0;
    packing.tolerance = tolerance;
    packing.morton = options.mortonOrder;

    // A node's data: its chunk decoded, placed, and encoded as the cache would hold it.
    const bool rgb = cloud.rgb != 0, rgb16 = cloud.rgb16 != 0;
    auto table = std::make_shared<const std::vector<StoredNode>>(nodes);
    auto source = [file, georef, table, where, packing, rgb, rgb16](size_t node) -> Result<std::vector<uint8_t>> {
        const Chunk& c = where[node];
        const StoredNode& s = (*table)[node];
        std::vector<uint8_t> out;
        if (c.points == 0) return out;
        std::vector<LasPoint> pts;
        if (auto r = file->readChunk(c.offset, c.bytes, c.points, pts); !r) return r.error();
        std::vector<glm::dvec3> ecef(pts.size());
        for (size_t k = 0; k < pts.size(); ++k) ecef[k] = pts[k].position;
        georef.toEcef(ecef);
        std::vector<PointRecord> records(pts.size());
        std::vector<uint32_t> order(pts.size());
        for (size_t k = 0; k < pts.size(); ++k) {
            // A point the transformation cannot place stays in the node's data (its size is
            // fixed by the table) at the centre, where it is at least not far off.
            const bool placed = std::isfinite(ecef[k].x) && std::isfinite(ecef[k].y) && std::isfinite(ecef[k].z);
            records[k] = {placed ? ecef[k] : s.centre, packColour(pts[k], rgb, rgb16) | uint32_t(pts[k].classification) << 24,
                          pts[k].intensity, c.offset + k};
            order[k] = uint32_t(k);
        }
        store::encodeNode(records, order, Cube{s.centre, s.halfSize, s.level}, packing, out);
        return out;
    };
    log::info(file->path(), ": COPC octree of ", nodes.size(), " nodes, depth ", depth, ", read from the file (no cache built)");
    if (options.progress) options.progress(1.0);
    return PointStore::streamed(std::move(nodes), cloud, std::move(source));
}

}  // namespace orbis::points
