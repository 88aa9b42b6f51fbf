// The out-of-core build of a PointStore (PointStoreBuild.h), in bounded memory, into a cache
// file reused by later loads:
//   1. read the file, place the points, gather the statistics, spill the records to disk;
//   2. count the points per cell of a 128^3 grid over the root cube;
//   3. split the cube into chunks (the largest cells of at most chunkPoints points) and copy
//      each record into its chunk's range of a second temporary file;
//   4. the nodes above the chunks: only a chunk's first capacity x depth points in key order
//      can reach them (each ancestor takes at most `capacity`), so those candidates, inserted
//      in key order, fill them exactly as the in-memory build would;
//   5. each chunk's subtree, built in memory from its records less those taken above.
// The result is the tree PointOctree::build makes of the whole cloud, node for node.
#include "layers/points/PointStoreBuild.h"

#include "layers/points/OutOfCore.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace orbis::points::build {
namespace fs = std::filesystem;
namespace {

using store::Packing;

using ooc::Cell;
using ooc::Chunk;
using ooc::File;
using ooc::makeChunks;
constexpr uint32_t kGridLevels = 7;   // 128^3 counting cells

/// The cell of `levels` levels below the root a point descends to (the octree's own octant
/// tests, so the chunks agree with the tree to the last bit).
Cell cellOf(const glm::dvec3& p, Cube cube, uint32_t levels) {
    Cell c;
    for (uint32_t l = 0; l < levels; ++l) {
        const int o = cube.octant(p);
        c = c.child(o);
        cube = cube.child(o);
    }
    return c;
}

Cube cubeOf(const Cell& c, Cube cube) {
    for (uint32_t l = 0; l < c.level; ++l) cube = cube.child(c.octantAt(l));
    return cube;
}

/// The nodes above the chunks, filled with the candidates in key order as PointOctree would.
struct UpperTree {
    struct Node {
        Cube cube;
        Cell cell;
        int32_t parent = -1, chunk = -1;   // chunk: this node is that chunk's root (not filled here)
        int32_t children[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
        std::vector<uint32_t> taken;   // indices into the candidates
    };
    std::vector<Node> nodes;
    std::unordered_map<uint64_t, int32_t> chunkOfCell;

    int32_t child(int32_t i, int octant) {
        if (nodes[size_t(i)].children[octant] >= 0) return nodes[size_t(i)].children[octant];
        Node c;
        c.cube = nodes[size_t(i)].cube.child(octant);
        c.cell = nodes[size_t(i)].cell.child(octant);
        c.parent = i;
        auto it = chunkOfCell.find(c.cell.packed());
        c.chunk = it == chunkOfCell.end() ? -1 : it->second;
        nodes[size_t(i)].children[octant] = int32_t(nodes.size());
        nodes.push_back(std::move(c));
        return int32_t(nodes.size()) - 1;
    }
    /// The node of a chunk's root, made (with its path) if no candidate reached it.
    int32_t chunkRoot(const Chunk& chunk) {
        int32_t i = 0;
        for (uint32_t l = 0; l < chunk.cell.level; ++l) i = child(i, chunk.cell.octantAt(l));
        return i;
    }
};

/// The header's copy of `info`, field by field over zeroed bytes. CloudInfo has padding (after
/// intensityGain) that a plain copy carries over as the compiler finds it; zeroed, the cache
/// file's bytes depend on the cloud alone (as the node table's, which has its `reserved`).
void storeInfo(store::FileHeader& header, const CloudInfo& info) {
    static_assert(sizeof(CloudInfo) == 64, "CloudInfo changed: copy its new fields here");
    std::memset(static_cast<void*>(&header.info), 0, sizeof header.info);
    header.info.heightMin = info.heightMin, header.info.heightMax = info.heightMax;
    header.info.intensityGain = info.intensityGain;
    header.info.read = info.read, header.info.dropped = info.dropped, header.info.points = info.points;
    header.info.depth = info.depth, header.info.rgb = info.rgb, header.info.rgb16 = info.rgb16;
    header.info.tolerance = info.tolerance;
}

/// The out-of-core build, pass by pass (see the top of this file); each pass leaves in the
/// members what the next one reads. Temporary files are removed when it is destroyed.
class CacheBuilder {
public:
    CacheBuilder(const BuildContext& ctx, double tolerance)
        : ctx_(ctx), tree_(ctx.options.octree), capacity_(std::max(1u, tree_.capacity)), tolerance_(tolerance),
          // Temporary files carry the process id: two processes building one cache do not
          // collide (the last rename wins, and both results are the same).
          tmp_((fs::path(ctx.folder) / ctx.stem).string().append(".").append(std::to_string(::getpid()))) {}

    /// Builds the cache file `out`, which starts with `key`.
    Result<void> build(const std::string& out, const std::string& key) {
        if (auto r = spillRecords(); !r) return r;
        auto counts = countCells();
        if (!counts) return counts.error();
        ctx_.progress(0.35);
        if (auto r = distributeToChunks(std::move(counts).value()); !r) return r;
        ctx_.progress(0.45);
        if (auto r = gatherCandidates(); !r) return r;
        fillUpperTree();
        ctx_.progress(0.5);
        return writeCache(out, key);
    }

private:
    /// 1. Records to the spill file, statistics.
    Result<void> spillRecords() {
        if (auto r = spill_.create(tmp_ + ".spill.tmp"); !r) return r;
        ooc::RecordWriter<PointRecord> spillWriter(spill_);
        auto stats = readRecords(ctx_.file, ctx_.georef, ctx_.options, 0.3,
                                 [&](std::span<const PointRecord> r) { return spillWriter.add(r); });
        if (!stats) return stats.error();
        if (auto r = spillWriter.flush(); !r) return r;
        stats_ = std::move(stats).value();
        packing_ = packingFor(stats_, tolerance_, ctx_.options.mortonOrder);
        n_ = stats_.kept;
        root_ = n_ ? Cube::around(stats_.lo, stats_.hi) : Cube{};
        levels_ = std::min(kGridLevels, tree_.maxLevel);
        return {};
    }

    /// 2. Counts per grid cell.
    Result<std::vector<uint32_t>> countCells() const {
        const uint32_t side = 1u << levels_;
        std::vector<uint32_t> counts(size_t(side) * side * side, 0);
        if (auto r = ooc::forEachBlock<PointRecord>(spill_, n_, ctx_.options.cancel, [&](std::span<const PointRecord> block) {
                for (const PointRecord& p : block) ++counts[cellOf(p.ecef, root_, levels_).index()];
            });
            !r)
            return r.error();
        return counts;
    }

    /// 3. Chunks, and each record copied into its chunk's range of the chunk file.
    Result<void> distributeToChunks(std::vector<uint32_t> counts) {
        const uint64_t chunkPoints = std::max<uint64_t>(ctx_.options.chunkPoints, uint64_t(8) * capacity_);
        chunks_ = makeChunks(counts, levels_, chunkPoints);
        const std::vector<uint32_t> chunkOf = ooc::chunkOfCells(chunks_, levels_);
        std::vector<uint32_t>().swap(counts);
        if (auto r = chunkFile_.create(tmp_ + ".chunks.tmp"); !r) return r;
        if (auto r = ooc::distribute<PointRecord>(spill_, n_, ctx_.options.cancel,
                                [&](const PointRecord& p) { return chunkOf[cellOf(p.ecef, root_, levels_).index()]; }, chunks_,
                                chunkFile_);
            !r)
            return r;
        spill_.close(true);
        return {};
    }

    bool byKey(const PointRecord& a, const PointRecord& b) const {
        const uint64_t ka = pointKey(a.id, tree_.seed), kb = pointKey(b.id, tree_.seed);
        return ka != kb ? ka < kb : a.id < b.id;
    }

    /// 4a. The candidates for the nodes above the chunks, in key order: each chunk's first
    /// capacity x depth records.
    Result<void> gatherCandidates() {
        const auto byKey = [this](const PointRecord& a, const PointRecord& b) { return this->byKey(a, b); };
        for (const Chunk& c : chunks_) {
            if (ctx_.cancelled()) return cancelled(ctx_.file);
            const uint64_t m = std::min<uint64_t>(c.count, uint64_t(capacity_) * c.cell.level);
            if (m == 0) continue;
            records_.resize(c.count);
            if (auto r = chunkFile_.read(records_.data(), c.count * sizeof(PointRecord), c.first * sizeof(PointRecord)); !r) return r;
            std::nth_element(records_.begin(), records_.begin() + int64_t(m - 1), records_.end(), byKey);
            candidates_.insert(candidates_.end(), records_.begin(), records_.begin() + int64_t(m));
        }
        std::sort(candidates_.begin(), candidates_.end(), byKey);
        return {};
    }

    /// 4b. The nodes above the chunks, filled with the candidates as PointOctree would.
    void fillUpperTree() {
        for (uint32_t c = 0; c < chunks_.size(); ++c) upper_.chunkOfCell[chunks_[c].cell.packed()] = int32_t(c);
        upper_.nodes.push_back({});
        upper_.nodes[0].cube = root_;
        upper_.nodes[0].chunk = chunks_.size() == 1 && chunks_[0].cell.level == 0 ? 0 : -1;
        for (uint32_t k = 0; k < candidates_.size(); ++k) {
            int32_t i = 0;
            while (upper_.nodes[size_t(i)].chunk < 0) {
                UpperTree::Node& nd = upper_.nodes[size_t(i)];
                if (nd.taken.size() < capacity_ || nd.cube.level >= tree_.maxLevel) {
                    nd.taken.push_back(k);
                    taken_.insert(candidates_[k].id);
                    break;
                }
                i = upper_.child(i, nd.cube.octant(candidates_[k].ecef));
            }
        }
    }

    /// 5. The cache file: the header and key, the nodes above the chunks, each chunk's subtree,
    /// the node table; then renamed to `out`.
    Result<void> writeCache(const std::string& out, const std::string& key) {
        File cache;
        if (auto r = cache.create(tmp_ + ".tmp"); !r) return r;
        store::FileHeader header{};
        std::memcpy(header.magic, store::kMagic, sizeof header.magic);
        header.version = store::kVersion;
        header.headerBytes = sizeof header;
        header.keyBytes = key.size();
        header.dataOffset = sizeof header + key.size();
        if (auto r = cache.write(key.data(), key.size(), sizeof header); !r) return r;
        NodeWriter nodes{cache, header.dataOffset};
        if (auto r = writeUpperNodes(nodes); !r) return r;
        if (auto r = writeChunkTrees(nodes); !r) return r;
        chunkFile_.close(true);
        stats_.info.depth = 0;
        for (const StoredNode& s : nodes.nodes) stats_.info.depth = std::max(stats_.info.depth, s.level);
        stats_.info.tolerance = float(tolerance_);
        storeInfo(header, stats_.info);
        header.dataBytes = nodes.dataBytes;
        header.nodeTableOffset = header.dataOffset + nodes.dataBytes;
        header.nodeCount = nodes.nodes.size();
        if (auto r = cache.write(nodes.nodes.data(), nodes.nodes.size() * sizeof(StoredNode), header.nodeTableOffset); !r) return r;
        header.tableCrc = store::tableChecksum(header, key, nodes.nodes);
        if (auto r = cache.write(&header, sizeof header, 0); !r) return r;
        return moveInPlace(cache, out);
    }

    /// The node table as it grows, and the node data written through a buffer.
    struct NodeWriter {
        File& cache;
        uint64_t dataOffset;
        std::vector<StoredNode> nodes;
        std::vector<uint8_t> data;   // not written yet
        uint64_t dataBytes = 0;      // written

        Result<void> writeData() {
            auto r = cache.write(data.data(), data.size(), dataOffset + dataBytes);
            dataBytes += data.size();
            data.clear();
            return r;
        }
    };

    /// Upper nodes first (their indices in creation order), the chunks' roots patched in later.
    Result<void> writeUpperNodes(NodeWriter& w) {
        storedIndex_.assign(upper_.nodes.size(), -1);
        for (size_t i = 0; i < upper_.nodes.size(); ++i)
            if (upper_.nodes[i].chunk < 0) storedIndex_[i] = int32_t(w.nodes.size()), w.nodes.emplace_back();
        for (size_t i = 0; i < upper_.nodes.size(); ++i) {
            const UpperTree::Node& u = upper_.nodes[i];
            if (u.chunk >= 0) continue;
            StoredNode& s = w.nodes[size_t(storedIndex_[i])];
            s.centre = u.cube.centre, s.halfSize = u.cube.halfSize, s.level = u.cube.level;
            s.count = uint32_t(u.taken.size());
            s.parent = u.parent >= 0 ? storedIndex_[size_t(u.parent)] : -1;
            s.offset = w.dataBytes + w.data.size();
            const size_t at = w.data.size();
            s.step = store::encodeNode(candidates_, u.taken, u.cube, packing_, w.data);
            s.crc = store::checksum(w.data.data() + at, w.data.size() - at);
        }
        if (auto r = w.writeData(); !r) return r;
        std::vector<PointRecord>().swap(candidates_);
        for (size_t i = 0; i < upper_.nodes.size(); ++i)
            if (upper_.nodes[i].chunk < 0) linkChild(w, int32_t(i), storedIndex_[i]);
        return {};
    }

    /// Each chunk's subtree, built in memory from its records less those taken above.
    Result<void> writeChunkTrees(NodeWriter& w) {
        for (size_t c = 0; c < chunks_.size(); ++c) {
            if (ctx_.cancelled()) return cancelled(ctx_.file);
            records_.resize(chunks_[c].count);
            if (auto r = chunkFile_.read(records_.data(), records_.size() * sizeof(PointRecord), chunks_[c].first * sizeof(PointRecord)); !r)
                return r;
            if (!taken_.empty())
                std::erase_if(records_, [&](const PointRecord& p) { return taken_.count(p.id) != 0; });
            if (records_.empty()) continue;
            const int32_t at = upper_.chunkRoot(chunks_[c]);
            storedIndex_.resize(upper_.nodes.size(), -1);
            const int32_t parent = upper_.nodes[size_t(at)].parent >= 0 ? storedIndex_[size_t(upper_.nodes[size_t(at)].parent)] : -1;
            const PointOctree sub = PointOctree::build(records_, tree_, cubeOf(chunks_[c].cell, root_));
            storedIndex_[size_t(at)] = appendTree(sub, records_, packing_, parent, w.dataBytes, w.nodes, w.data);
            linkChild(w, at, storedIndex_[size_t(at)]);
            if (auto r = w.writeData(); !r) return r;
            ctx_.progress(0.5 + 0.5 * double(c + 1) / double(chunks_.size()));
        }
        return {};
    }

    /// Points the stored parent of upper node `upperIndex` at its stored node.
    void linkChild(NodeWriter& w, int32_t upperIndex, int32_t stored) {
        const UpperTree::Node& u = upper_.nodes[size_t(upperIndex)];
        if (u.parent < 0) return;
        const UpperTree::Node& p = upper_.nodes[size_t(u.parent)];
        for (int o = 0; o < 8; ++o)
            if (p.children[o] == upperIndex) w.nodes[size_t(storedIndex_[size_t(u.parent)])].children[o] = stored;
    }

    /// Renames the finished temporary file to `out`.
    static Result<void> moveInPlace(File& cache, const std::string& out) {
        const std::string written = cache.path();
        // On the disk before it gets its name: a crash leaves no cache that looks whole.
        if (auto r = cache.sync(); !r) return r;
        cache.close(false);
        std::error_code ec;
        fs::rename(written, out, ec);
        if (ec) {
            ::unlink(written.c_str());
            return makeError(std::string(out).append(": cannot write the point cache: ").append(ec.message()));
        }
        return {};
    }

    const BuildContext& ctx_;
    const PointOctree::Options& tree_;
    const uint32_t capacity_;
    const double tolerance_;
    const std::string tmp_;   // temporary files: tmp_.*.tmp
    File spill_, chunkFile_;
    Statistics stats_;
    Packing packing_;
    uint64_t n_ = 0;          // points kept
    Cube root_;
    uint32_t levels_ = 0;     // of the counting grid
    std::vector<Chunk> chunks_;
    UpperTree upper_;
    std::vector<PointRecord> candidates_, records_;
    std::unordered_set<uint64_t> taken_;   // ids of the candidates the upper nodes took
    std::vector<int32_t> storedIndex_;     // per upper node: its index in the node table, -1 none yet
};

}  // namespace

Result<void> buildCacheFile(const BuildContext& ctx, const std::string& out, const std::string& key, double tolerance) {
    return CacheBuilder(ctx, tolerance).build(out, key);
}

}  // namespace orbis::points::build
