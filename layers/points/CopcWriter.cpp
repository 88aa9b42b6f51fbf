// COPC 1.0 writing (see CopcWriter.h), out of core, in the passes PointCacheBuild.cpp makes:
//   1. read the input once: every point packed as the output's record (with its index) into a
//      spill file; the bounds, GPS times and returns counted; the root cube placed;
//   2. count the points per cell of a 128^3 grid over the root cube (the tree's own octant tests);
//   3. split the cube into chunks (the largest cells of at most `batchPoints` points) and copy each
//      record into its chunk's range of a second file;
//   4. the nodes above the chunks: only a chunk's first capacity x level points in key order can
//      reach them (each ancestor takes at most `capacity`), so those candidates, merged in key
//      order over all chunks, fill them exactly as one pass over the whole cloud would; and the
//      points of a chunk they take are its first ones in key order (once one of its points passes
//      every ancestor, all of them are full), so a count per chunk says which;
//   5. chunk by chunk: the points taken above are set aside (by node, in a fourth file), the rest
//      fill the chunk's subtree in key order; each node's LAZ chunk is encoded on worker threads
//      and written in order;
//   6. the nodes above the chunks, then the chunk table, the hierarchy EVLR and finally the header
//      and VLRs (their bytes: CopcLayout.h).
// The tree is the one the whole cloud inserted in key order would make, whatever the batch size.
#include "layers/points/CopcWriter.h"

#include "layers/points/CopcLayout.h"
#include "layers/points/LasBytes.h"

#include "layers/points/Copc.h"
#include "layers/points/LasReader.h"
#include "layers/points/LazChunks.h"
#include "layers/points/OutOfCore.h"
#include "layers/points/PointOctree.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <tuple>
#include <queue>
#include <unordered_map>
#include <vector>

namespace orbis::points {
namespace {

constexpr int32_t kDeepest = 30;        // keys hold 2^d cells per axis in an int32 (as Copc.cpp reads)
constexpr uint64_t kSeed = 1;           // the points' keys (as PointOctree's default)

/// A point on its way: its index in the input and its output record (30-38 bytes).
struct Spilled {
    uint64_t index;
    uint8_t record[40];
};
static_assert(sizeof(Spilled) == 48);

/// A candidate for the nodes above the chunks: its place in key order (the index in the low bits)
/// and its position's integers.
struct Candidate {
    uint64_t order;
    int32_t xyz[3];
    uint32_t pad = 0;   // (written to the candidates file: zero, not stray bytes)
};
static_assert(sizeof(Candidate) == 24);

/// An octree node while the tree is built.
struct Node {
    copc::Key key;
    glm::dvec3 centre{0.0};   // its cube's, as copc::cube gives it (the reader's arithmetic)
    uint32_t count = 0;
    uint32_t children[8] = {};   // 0: none (the first node is no one's child)
    int32_t chunk = -1;          // above the chunks: the chunk whose root this node is, if any
    uint64_t first = 0;          // its points: in the permutation (a chunk's subtree) or the upper file
};

std::string name(const copc::Key& k) {
    return std::to_string(k.d) + "-" + std::to_string(k.x) + "-" + std::to_string(k.y) + "-" + std::to_string(k.z);
}


/// The output file; removed unless committed (when it is a file: never a device or a pipe).
struct Output {
    std::string path;
    std::FILE* file = nullptr;
    bool failed = false;
    bool committed = false;
    ~Output() {
        if (file) std::fclose(file);
        std::error_code ec;
        if (!committed && std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
    }
    void write(const void* data, size_t n) {
        if (n > 0 && std::fwrite(data, 1, n, file) != n) failed = true;
    }
};

constexpr uint32_t kGridLevels = 7;   // 128^3 counting cells

class CopcBuilder {
public:
    CopcBuilder(const LasFile& in, const std::string& path, const CopcWriteOptions& options)
        : in_(in), path_(path), options_(options), n_(in.points()), capacity_(options.maxNodePoints),
          maxLevel_(std::min<uint32_t>(options.maxLevel, kDeepest)),
          tmp_(path + "." + std::to_string(::getpid())) {}

    Result<CopcWriteStats> write() {
        const LasHeader& ih = in_.header();
        if (in_.crs().wkt.empty())
            return makeError(path_ + ": COPC needs a CRS: " + in_.path() +
                             " has none (no WKT or GeoTIFF VLR, no .wkt or .prj sidecar); give it one (a sidecar next to it, or convert it with a CRS)");
        if (capacity_ == 0) return makeError(path_ + ": a COPC node must hold at least one point (maxNodePoints 0)");
        wkt_ = wkt1(in_.crs().wkt);
        if (wkt_.size() + 1 > 65535) return makeError(path_ + ": the CRS's WKT is too long for a VLR (65 534 bytes at most)");
        format_ = ih.hasNir() ? 8 : ih.hasRgb() ? 7 : 6;
        recordLength_ = format_ == 8 ? 38 : format_ == 7 ? 36 : 30;
        scale_ = ih.scale, offset_ = ih.offset;
        indexBits_ = std::max(1, int(std::bit_width(n_ > 0 ? n_ - 1 : 0)));
        indexMask_ = indexBits_ >= 64 ? ~uint64_t(0) : (uint64_t(1) << indexBits_) - 1;

        if (auto r = readInput(); !r) return r.error();
        placeRoot();
        if (auto r = makeChunks(); !r) return r.error();
        progress(0.4);
        if (auto r = gatherCandidates(); !r) return r.error();
        if (auto r = fillUpperTree(); !r) return r.error();
        progress(0.45);
        if (auto r = openOutput(); !r) return r.error();
        if (auto r = writeChunkTrees(); !r) return r.error();
        if (auto r = writeUpperNodes(); !r) return r.error();
        return finish();
    }

private:
    void progress(double f) const {
        if (options_.progress) options_.progress(std::clamp(f, 0.0, 1.0));
    }
    Error fail(const std::string& what) const { return makeError(path_ + ": " + what); }
    uint64_t order(uint64_t index) const { return (pointKey(index, kSeed) & ~indexMask_) | index; }
    glm::dvec3 position(const int32_t xyz[3]) const { return glm::dvec3(xyz[0], xyz[1], xyz[2]) * scale_ + offset_; }
    glm::dvec3 position(const Spilled& s) const {
        int32_t xyz[3];
        std::memcpy(xyz, s.record, 12);
        return position(xyz);
    }
    static int octant(const glm::dvec3& p, const glm::dvec3& centre) {
        return (p.x >= centre.x ? 1 : 0) | (p.y >= centre.y ? 2 : 0) | (p.z >= centre.z ? 4 : 0);
    }
    Node makeNode(const copc::Key& key) const {
        Node nd;
        nd.key = key;
        double half = 0.0;
        copc::cube(info_, key, nd.centre, half);
        return nd;
    }

    uint64_t batchPoints() const { return std::max<uint64_t>(options_.batchPoints, uint64_t(8) * capacity_); }

    /// 1. Every point packed into the spill file (kept in memory when the cloud is one batch);
    /// bounds, GPS times, returns.
    Result<void> readInput() {
        inMemory_ = n_ <= batchPoints();
        if (inMemory_) {
            try {
                memory_.reserve(size_t(n_));
            } catch (const std::bad_alloc&) {
                return fail("not enough memory for the " + std::to_string(n_) + " points of " + in_.path() + "; convert it in smaller batches");
            }
        } else if (auto r = spill_.create(tmp_ + ".spill.tmp"); !r) {
            return fail(r.message());
        }
        ooc::RecordWriter<Spilled> writer(spill_);
        constexpr uint64_t kBatch = 1u << 19;
        std::vector<LasPoint> batch;
        Spilled s{};
        for (uint64_t first = 0; first < n_; first += kBatch) {
            const uint64_t count = std::min(kBatch, n_ - first);
            if (auto r = in_.read(first, count, batch); !r) return fail(r.message());
            if (batch.size() != count)
                return fail(in_.path() + " gave " + std::to_string(batch.size()) + " points where " + std::to_string(count) +
                            " were asked (points " + std::to_string(first) + " on; damaged chunks skipped?)");
            for (uint64_t i = 0; i < count; ++i) {
                const LasPoint& p = batch[i];
                const glm::dvec3 q = glm::round((p.position - offset_) / scale_);
                if (!glm::all(glm::lessThanEqual(glm::abs(q), glm::dvec3(2147483647.0))))
                    return fail("point " + std::to_string(first + i) + " of " + in_.path() + " does not fit in 32 bits with the file's scale and offset");
                const int32_t xyz[3] = {int32_t(q.x), int32_t(q.y), int32_t(q.z)};
                s.index = first + i;
                packLasRecord(p, xyz, format_, s.record);
                if (inMemory_)
                    memory_.push_back(s);
                else if (auto w = writer.add(s); !w)
                    return fail(w.message());
                // As a reader computes it (LasFile::decodeRecords): the bounds are the written points'.
                const glm::dvec3 at = position(xyz);
                lo_ = glm::min(lo_, at);
                hi_ = glm::max(hi_, at);
                gpsMin_ = std::min(gpsMin_, p.gpsTime);
                gpsMax_ = std::max(gpsMax_, p.gpsTime);
                if (p.returnNumber >= 1 && p.returnNumber <= 15) ++byReturn_[size_t(p.returnNumber - 1)];
            }
            progress(0.3 * double(first + count) / double(n_));
        }
        if (!inMemory_)
            if (auto w = writer.flush(); !w) return fail(w.message());
        if (n_ == 0) lo_ = hi_ = glm::dvec3(0.0), gpsMin_ = gpsMax_ = 0.0;
        return {};
    }

    /// The root cube: centred on the bounds, its half size half the largest extent, snapped so
    /// that a reader's arithmetic is exact: the half size rounded up to 11 significant bits (0.1 %
    /// more at most), the centre to a multiple of the deepest cells' half size. Every cube's
    /// bounds, as copc::cube computes them, are then exact doubles, and the cube a point is sent
    /// to (by comparing it with its parent's centre) contains it exactly. That needs the centre's
    /// coordinates below 2^(41 - maxLevel) times the half size, so a cloud smaller than that
    /// (about 25 cm across at 4000 km from the origin, for maxLevel 16; one point, or all in one
    /// place) gets a root of that size.
    void placeRoot() {
        const glm::dvec3 extent = hi_ - lo_, middle = 0.5 * (lo_ + hi_);
        const double far = std::max({std::abs(middle.x), std::abs(middle.y), std::abs(middle.z)});
        const double half = std::max({0.5 * std::max({extent.x, extent.y, extent.z}) * (1.0 + 1e-9), std::max({scale_.x, scale_.y, scale_.z}),
                                      std::ldexp(far, int(maxLevel_) - 41)});
        const int s = std::ilogb(half) - 10;                     // the half size's last significant bit
        const double q = std::ldexp(1.0, s - int(maxLevel_));   // the deepest cells' half size is a multiple of it
        info_.centre = glm::round(middle / q) * q;
        info_.halfSize = std::ceil((half + q) / std::ldexp(1.0, s)) * std::ldexp(1.0, s);
        info_.spacing = 2.0 * info_.halfSize / std::sqrt(double(capacity_));
        info_.gpsTimeMin = gpsMin_;
        info_.gpsTimeMax = gpsMax_;
        // The grid's cells' centres per level and axis, as copc::cube computes the nodes' (so a
        // point's cell is the one the tree sends it to, to the last bit).
        levels_ = std::min(kGridLevels, maxLevel_);
        for (uint32_t l = 0; l < levels_; ++l) {
            const int32_t side = int32_t(1) << l;
            for (int a = 0; a < 3; ++a) gridCentres_[a][l].resize(size_t(side));
            for (int32_t i = 0; i < side; ++i) {
                glm::dvec3 c;
                double h;
                copc::cube(info_, copc::Key{int32_t(l), i, i, i}, c, h);
                for (int a = 0; a < 3; ++a) gridCentres_[a][l][size_t(i)] = c[a];
            }
        }
    }

    ooc::Cell cellOf(const glm::dvec3& p) const {
        ooc::Cell c;
        for (uint32_t l = 0; l < levels_; ++l)
            c = c.child((p.x >= gridCentres_[0][l][c.x] ? 1 : 0) | (p.y >= gridCentres_[1][l][c.y] ? 2 : 0) |
                        (p.z >= gridCentres_[2][l][c.z] ? 4 : 0));
        return c;
    }

    /// 2-3. Counts per grid cell, the chunks, each record copied into its chunk's range (when
    /// there is more than one chunk: one chunk reads the spill file as it is).
    Result<void> makeChunks() {
        if (inMemory_) {   // one batch: the root's
            if (n_ > 0) chunks_.push_back({ooc::Cell{}, n_, 0});
            return {};
        }
        const size_t side = size_t(1) << levels_;
        std::vector<uint32_t> counts(side * side * side, 0);
        if (auto r = ooc::forEachBlock<Spilled>(spill_, n_, nullptr,
                                                [&](std::span<const Spilled> block) {
                                                    for (const Spilled& s : block) ++counts[cellOf(position(s)).index()];
                                                });
            !r)
            return fail(r.message());
        progress(0.33);
        chunks_ = ooc::makeChunks(counts, levels_, batchPoints());
        if (chunks_.size() <= 1) {
            records_ = &spill_;
            return {};
        }
        const std::vector<uint32_t> chunkOf = ooc::chunkOfCells(chunks_, levels_);
        std::vector<uint32_t>().swap(counts);
        if (auto r = chunkFile_.create(tmp_ + ".chunks.tmp"); !r) return fail(r.message());
        if (auto r = ooc::distribute<Spilled>(spill_, n_, nullptr, [&](const Spilled& s) { return chunkOf[cellOf(position(s)).index()]; },
                                              chunks_, chunkFile_);
            !r)
            return fail(r.message());
        spill_.close(true);
        records_ = &chunkFile_;
        return {};
    }

    /// A chunk's records.
    Result<void> readChunk(const ooc::Chunk& c, std::vector<Spilled>& out) {
        if (inMemory_) {   // the one batch, read once
            out.swap(memory_);
            return {};
        }
        try {
            out.resize(size_t(c.count));
        } catch (const std::bad_alloc&) {
            return fail("not enough memory for the " + std::to_string(c.count) + " points of cell " + std::to_string(c.cell.level) + "-" +
                        std::to_string(c.cell.x) + "-" + std::to_string(c.cell.y) + "-" + std::to_string(c.cell.z) +
                        " (they lie closer together than the counting grid tells apart)");
        }
        if (auto r = records_->read(out.data(), c.count * sizeof(Spilled), c.first * sizeof(Spilled)); !r) return fail(r.message());
        return {};
    }

    /// 4a. Each chunk's first capacity x level points in key order, into the candidates file.
    Result<void> gatherCandidates() {
        taken_.assign(chunks_.size(), {});
        candidateFirst_.assign(chunks_.size(), 0);
        candidateCount_.assign(chunks_.size(), 0);
        uint64_t at = 0;
        std::vector<Spilled> records;
        std::vector<Candidate> candidates;
        for (size_t c = 0; c < chunks_.size(); ++c) {
            const uint64_t m = std::min<uint64_t>(chunks_[c].count, uint64_t(capacity_) * chunks_[c].cell.level);
            if (m == 0) continue;
            if (at == 0)
                if (auto r = candidateFile_.create(tmp_ + ".candidates.tmp"); !r) return fail(r.message());
            if (auto r = readChunk(chunks_[c], records); !r) return r;
            candidates.resize(records.size());
            for (size_t i = 0; i < records.size(); ++i) {
                candidates[i].order = order(records[i].index);
                std::memcpy(candidates[i].xyz, records[i].record, 12);
            }
            const auto byOrder = [](const Candidate& a, const Candidate& b) { return a.order < b.order; };
            std::nth_element(candidates.begin(), candidates.begin() + int64_t(m - 1), candidates.end(), byOrder);
            std::sort(candidates.begin(), candidates.begin() + int64_t(m), byOrder);
            if (auto r = candidateFile_.write(candidates.data(), m * sizeof(Candidate), at * sizeof(Candidate)); !r) return fail(r.message());
            candidateFirst_[c] = at, candidateCount_[c] = m;
            at += m;
        }
        return {};
    }

    /// 4b. The nodes above the chunks, filled with the candidates of all chunks in key order.
    Result<void> fillUpperTree() {
        upper_.clear();
        if (chunks_.empty()) return {};
        std::unordered_map<uint64_t, int32_t> chunkOfCell;
        for (size_t c = 0; c < chunks_.size(); ++c) chunkOfCell[chunks_[c].cell.packed()] = int32_t(c);
        upper_.push_back(makeNode({}));
        upper_[0].chunk = chunks_[0].cell.level == 0 ? 0 : -1;
        // One stream per chunk, read a block at a time, merged by a heap on the key order.
        struct Stream {
            std::vector<Candidate> block;
            size_t next = 0;
            uint64_t read = 0;   // candidates read from the file
        };
        constexpr uint64_t kBlock = 2048;
        std::vector<Stream> streams(chunks_.size());
        using Head = std::pair<uint64_t, uint32_t>;   // order, chunk
        std::priority_queue<Head, std::vector<Head>, std::greater<>> heap;
        const auto refill = [&](uint32_t c) -> Result<void> {
            Stream& s = streams[c];
            if (s.next < s.block.size()) return {};
            const uint64_t left = candidateCount_[c] - s.read;
            s.block.resize(size_t(std::min(kBlock, left)));
            s.next = 0;
            if (s.block.empty()) return {};
            if (auto r = candidateFile_.read(s.block.data(), s.block.size() * sizeof(Candidate), (candidateFirst_[c] + s.read) * sizeof(Candidate));
                !r)
                return fail(r.message());
            s.read += s.block.size();
            return {};
        };
        for (uint32_t c = 0; c < chunks_.size(); ++c) {
            if (auto r = refill(c); !r) return r;
            if (!streams[c].block.empty()) heap.push({streams[c].block[0].order, c});
        }
        while (!heap.empty()) {
            const uint32_t c = heap.top().second;
            heap.pop();
            Stream& s = streams[c];
            const Candidate k = s.block[s.next++];
            const glm::dvec3 p = position(k.xyz);
            uint32_t i = 0;
            bool taken = false;
            while (upper_[i].chunk < 0) {
                if (upper_[i].count < capacity_) {
                    ++upper_[i].count;
                    taken_[c].push_back(i);
                    taken = true;
                    break;
                }
                const int o = octant(p, upper_[i].centre);
                uint32_t child = upper_[i].children[o];
                if (child == 0) {
                    Node nd = makeNode(upper_[i].key.child(o));
                    const copc::Key& key = nd.key;
                    auto it = chunkOfCell.find(ooc::Cell{uint32_t(key.d), uint32_t(key.x), uint32_t(key.y), uint32_t(key.z)}.packed());
                    nd.chunk = it == chunkOfCell.end() ? -1 : it->second;
                    child = uint32_t(upper_.size());
                    upper_[i].children[o] = child;
                    upper_.push_back(nd);
                }
                i = child;
            }
            // A point that passes every node above its chunk finds them all full: none of the
            // chunk's later points is taken either.
            if (!taken) continue;
            if (auto r = refill(c); !r) return r;
            if (s.next < s.block.size()) heap.push({s.block[s.next].order, c});
        }
        candidateFile_.close(true);
        // Each node's range in the upper file.
        uint64_t at = 0;
        for (Node& nd : upper_)
            if (nd.chunk < 0) nd.first = at, at += nd.count;
        if (at > 0)
            if (auto r = upperFile_.create(tmp_ + ".upper.tmp"); !r) return fail(r.message());
        upperCursor_.assign(upper_.size(), 0);
        return {};
    }

    Result<void> openOutput() {
        z_ = copcLaszip(format_);
        head_ = copcHead(z_, wkt_);
        pointOffset_ = head_.size() - 8;
        out_.path = path_;
        out_.file = std::fopen(path_.c_str(), "wb");
        if (!out_.file) return fail(std::string("cannot create the file: ") + std::strerror(errno));
        out_.write(head_.data(), head_.size());   // rewritten at the end
        dataAt_ = pointOffset_ + 8;
        return {};
    }

    /// Encodes nodes (gather(i, records) fills node i's records, in the input's order) on worker
    /// threads and writes their chunks in order.
    using Gather = std::function<Result<void>(size_t, std::vector<uint8_t>&)>;
    Result<void> encodeNodes(const std::vector<copc::Key>& keys, const std::vector<uint32_t>& counts, const Gather& gather) {
        const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u, 8u);
        const size_t window = 2 * size_t(threads);   // chunks encoded ahead of the writing at most
        std::vector<std::vector<uint8_t>> encoded(keys.size());
        std::vector<char> ready(keys.size(), 0);
        std::string error;
        size_t next = 0, done = 0;
        bool stop = false;
        std::mutex mutex;
        std::condition_variable cv;
        const auto work = [&] {
            std::vector<uint8_t> gathered, bytes;
            for (;;) {
                size_t i;
                {
                    std::unique_lock lock(mutex);
                    cv.wait(lock, [&] { return stop || next >= keys.size() || next < done + window; });
                    if (stop || next >= keys.size()) return;
                    i = next++;
                }
                Result<void> r;
                try {
                    r = gather(i, gathered);
                    bytes.clear();
                    if (r) r = laz::encodeChunk(z_, gathered.data(), counts[i], bytes);
                } catch (const std::bad_alloc&) {
                    r = makeError("not enough memory to encode the " + std::to_string(counts[i]) + " points of node " + name(keys[i]));
                }
                std::lock_guard lock(mutex);
                if (!r) {
                    if (error.empty()) error = r.message();
                    stop = true;
                } else {
                    encoded[i].swap(bytes);
                    ready[i] = 1;
                }
                cv.notify_all();
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < std::min<size_t>(threads, keys.size()); ++t) pool.emplace_back(work);
        for (size_t i = 0; i < keys.size(); ++i) {
            std::vector<uint8_t> bytes;
            {
                std::unique_lock lock(mutex);
                cv.wait(lock, [&] { return stop || ready[i]; });
                if (stop) break;
                bytes.swap(encoded[i]);
            }
            out_.write(bytes.data(), bytes.size());
            if (bytes.size() > uint64_t(std::numeric_limits<int32_t>::max())) {
                std::lock_guard lock(mutex);
                error = "node " + name(keys[i]) + "'s chunk is " + std::to_string(bytes.size()) + " bytes, more than a COPC entry holds";
                stop = true;
                break;
            }
            chunkTable_.push_back({dataAt_, bytes.size(), counts[i], pointsWritten_});
            entries_.push_back({keys[i], dataAt_, uint32_t(bytes.size()), counts[i]});
            dataAt_ += bytes.size();
            pointsWritten_ += counts[i];
            {
                std::lock_guard lock(mutex);
                ++done;
                if (out_.failed) stop = true;
            }
            cv.notify_all();
            progress(0.45 + 0.5 * double(pointsWritten_) / double(std::max<uint64_t>(n_, 1)));
        }
        {
            std::lock_guard lock(mutex);
            stop = true;
        }
        cv.notify_all();
        for (std::thread& t : pool) t.join();
        if (!error.empty()) return fail(error);
        if (out_.failed) return fail("write failed (disk full?)");
        return {};
    }

    /// A batch ready to encode: its records, its subtree's nodes with points (in the order they
    /// are written) and, node after node, their records' indices.
    struct Batch {
        std::vector<Spilled> records;
        std::vector<Node> nodes;
        std::vector<uint32_t> permutation, written;
        std::vector<copc::Key> keys;
        std::vector<uint32_t> counts;
    };

    /// 5a. A batch: its records read, the points taken above written to their nodes' ranges of
    /// the upper file, the rest, in key order, into the subtree (each to the first node on its
    /// path with room).
    Result<void> prepareBatch(size_t c, Batch& b) {
        if (auto r = readChunk(chunks_[c], b.records); !r) return r;
        const std::vector<Spilled>& records = b.records;
        // The key order with the record's place in the batch in the low bits: the records are in
        // the input's order, so this is the order of the input's indices among equal keys.
        std::vector<uint64_t> byOrder(records.size());
        for (uint32_t i = 0; i < records.size(); ++i) byOrder[i] = (order(records[i].index) & ~indexMask_) | i;
        std::sort(byOrder.begin(), byOrder.end());
        const auto recordAt = [&](size_t k) { return uint32_t(byOrder[k] & indexMask_); };
        // The points taken above: the first ones in key order.
        const std::vector<uint32_t>& taken = taken_[c];
        {
            std::vector<std::pair<uint32_t, uint32_t>> toNode(taken.size());   // node, record (the input's order in a node)
            for (size_t k = 0; k < taken.size(); ++k) toNode[k] = {taken[k], recordAt(k)};
            std::sort(toNode.begin(), toNode.end());
            std::vector<Spilled> run;
            for (size_t k = 0; k < toNode.size();) {
                const uint32_t node = toNode[k].first;
                run.clear();
                for (; k < toNode.size() && toNode[k].first == node; ++k) run.push_back(records[toNode[k].second]);
                const uint64_t at = upper_[node].first + upperCursor_[node];
                if (auto r = upperFile_.write(run.data(), run.size() * sizeof(Spilled), at * sizeof(Spilled)); !r) return fail(r.message());
                upperCursor_[node] += run.size();
            }
        }
        const ooc::Cell& cell = chunks_[c].cell;
        std::vector<Node>& nodes = b.nodes;
        nodes.assign(1, makeNode({int32_t(cell.level), int32_t(cell.x), int32_t(cell.y), int32_t(cell.z)}));
        std::vector<uint32_t> nodeOf(records.size(), UINT32_MAX);
        for (size_t k = taken.size(); k < byOrder.size(); ++k) {
            const uint32_t index = recordAt(k);
            const glm::dvec3 p = position(records[index]);
            uint32_t node = 0;
            for (;;) {
                Node& nd = nodes[node];
                if (nd.count < capacity_ || uint32_t(nd.key.d) >= maxLevel_) {
                    ++nd.count;
                    break;
                }
                const int o = octant(p, nd.centre);
                uint32_t child = nd.children[o];
                if (child == 0) {
                    child = uint32_t(nodes.size());
                    nd.children[o] = child;
                    nodes.push_back(makeNode(nd.key.child(o)));   // (nd is not used after this)
                }
                node = child;
            }
            nodeOf[index] = node;
        }
        std::vector<uint64_t>().swap(byOrder);
        // Inside a node, the input's order (LAZ predicts each point from the one before); the
        // batch's records are in that order already.
        uint64_t at = 0;
        for (Node& nd : nodes) nd.first = at, at += nd.count;
        std::vector<uint64_t> cursor(nodes.size());
        for (size_t i = 0; i < nodes.size(); ++i) cursor[i] = nodes[i].first;
        b.permutation.resize(size_t(at));
        for (uint32_t i = 0; i < records.size(); ++i)
            if (nodeOf[i] != UINT32_MAX) b.permutation[cursor[nodeOf[i]]++] = i;
        for (uint32_t i = 0; i < nodes.size(); ++i)
            if (nodes[i].count > 0) b.written.push_back(i);
        std::sort(b.written.begin(), b.written.end(), [&](uint32_t x, uint32_t y) { return levelOrder(nodes[x].key, nodes[y].key); });
        for (uint32_t i : b.written) {
            if (nodes[i].count > uint32_t(std::numeric_limits<int32_t>::max()))
                return fail("node " + name(nodes[i].key) + " would hold " + std::to_string(nodes[i].count) +
                            " points, more than a COPC entry counts; allow a deeper tree (maxLevel)");
            b.keys.push_back(nodes[i].key);
            b.counts.push_back(nodes[i].count);
        }
        return {};
    }

    /// 5. Batch by batch, the next one prepared on another thread while one is encoded: each
    /// node of its subtree encoded and written.
    Result<void> writeChunkTrees() {
        if (chunks_.empty()) return {};
        const auto prepare = [this](size_t c) {
            auto b = std::make_unique<Batch>();
            Result<void> r;
            try {
                r = prepareBatch(c, *b);
            } catch (const std::bad_alloc&) {
                r = fail("not enough memory for a batch of " + std::to_string(chunks_[c].count) + " points; convert it in smaller batches");
            }
            return std::make_pair(std::move(r), std::move(b));
        };
        auto next = std::async(std::launch::deferred, prepare, size_t(0));
        for (size_t c = 0; c < chunks_.size(); ++c) {
            auto [ready, batch] = next.get();
            if (!ready) return ready;
            if (c + 1 < chunks_.size()) next = std::async(std::launch::async, prepare, c + 1);
            const Batch& b = *batch;
            const auto gather = [&](size_t i, std::vector<uint8_t>& out) -> Result<void> {
                const Node& nd = b.nodes[b.written[i]];
                out.resize(size_t(nd.count) * recordLength_);
                for (uint32_t k = 0; k < nd.count; ++k)
                    std::memcpy(out.data() + size_t(k) * recordLength_, b.records[b.permutation[nd.first + k]].record, recordLength_);
                return {};
            };
            if (auto r = encodeNodes(b.keys, b.counts, gather); !r) {
                if (next.valid()) next.wait();   // (it uses this builder's files)
                return r;
            }
        }
        return {};
    }

    /// 6a. The nodes above the chunks, their points read back from the upper file.
    Result<void> writeUpperNodes() {
        std::vector<uint32_t> written;
        for (uint32_t i = 0; i < upper_.size(); ++i)
            if (upper_[i].chunk < 0 && upper_[i].count > 0) written.push_back(i);
        std::sort(written.begin(), written.end(), [&](uint32_t a, uint32_t b) { return levelOrder(upper_[a].key, upper_[b].key); });
        std::vector<copc::Key> keys;
        std::vector<uint32_t> counts;
        for (uint32_t i : written) keys.push_back(upper_[i].key), counts.push_back(upper_[i].count);
        const auto gather = [&](size_t i, std::vector<uint8_t>& out) -> Result<void> {
            const Node& nd = upper_[written[i]];
            std::vector<Spilled> points(nd.count);
            if (auto r = upperFile_.read(points.data(), points.size() * sizeof(Spilled), nd.first * sizeof(Spilled)); !r) return r;
            std::sort(points.begin(), points.end(), [](const Spilled& a, const Spilled& b) { return a.index < b.index; });
            out.resize(size_t(nd.count) * recordLength_);
            for (uint32_t k = 0; k < nd.count; ++k) std::memcpy(out.data() + size_t(k) * recordLength_, points[k].record, recordLength_);
            return {};
        };
        return encodeNodes(keys, counts, gather);
    }

    /// 6b. The chunk table, the hierarchy (one page, in an EVLR), the header and the info VLR.
    Result<CopcWriteStats> finish() {
        spill_.close(true);
        chunkFile_.close(true);
        upperFile_.close(true);
        const uint64_t tableAt = dataAt_;
        std::vector<uint8_t> table;
        laz::encodeChunkTable(z_, chunkTable_, table);
        out_.write(table.data(), table.size());
        const uint64_t evlrAt = tableAt + table.size();
        const std::vector<uint8_t> evlr = hierarchyEvlr(entries_);
        const uint64_t pageBytes = evlr.size() - 60;
        out_.write(evlr.data(), evlr.size());
        info_.rootPageOffset = evlrAt + 60;
        info_.rootPageBytes = pageBytes;

        CopcHeadFields fields;
        fields.globalEncoding = in_.header().globalEncoding;
        fields.format = format_;
        fields.recordLength = recordLength_;
        fields.scale = scale_, fields.offset = offset_, fields.lo = lo_, fields.hi = hi_;
        fields.points = n_;
        fields.byReturn = byReturn_;
        fields.evlrAt = evlrAt, fields.chunkTableAt = tableAt;
        fillCopcHead(head_, fields, info_);
        if (std::fseek(out_.file, 0, SEEK_SET) != 0) out_.failed = true;
        out_.write(head_.data(), head_.size());
        const bool closed = std::fclose(out_.file) == 0;
        out_.file = nullptr;
        if (out_.failed || !closed) return fail("write failed (disk full?)");
        out_.committed = true;
        progress(1.0);

        CopcWriteStats stats;
        stats.points = n_;
        stats.nodes = uint32_t(entries_.size());
        for (const copc::Node& nd : entries_) stats.depth = std::max(stats.depth, uint32_t(nd.key.d));
        stats.bytes = evlrAt + evlr.size();
        stats.batches = uint32_t(chunks_.size());
        return stats;
    }

    const LasFile& in_;
    const std::string path_;
    const CopcWriteOptions& options_;
    const uint64_t n_;
    const uint32_t capacity_, maxLevel_;
    const std::string tmp_;   // temporary files: tmp_.*.tmp
    std::string wkt_;
    uint8_t format_ = 6;
    uint16_t recordLength_ = 30;
    glm::dvec3 scale_{1.0}, offset_{0.0};
    int indexBits_ = 1;
    uint64_t indexMask_ = 1;
    glm::dvec3 lo_{std::numeric_limits<double>::max()}, hi_{-std::numeric_limits<double>::max()};
    double gpsMin_ = std::numeric_limits<double>::max(), gpsMax_ = -std::numeric_limits<double>::max();
    std::array<uint64_t, 15> byReturn_{};
    copc::Info info_;
    uint32_t levels_ = 0;                              // of the counting grid
    std::array<std::array<std::vector<double>, kGridLevels>, 3> gridCentres_;   // [axis][level][cell]
    bool inMemory_ = false;                            // the cloud is one batch: memory_ holds it
    std::vector<Spilled> memory_;
    ooc::File spill_, chunkFile_, candidateFile_, upperFile_;
    const ooc::File* records_ = nullptr;               // where the chunks' records are
    std::vector<ooc::Chunk> chunks_;
    std::vector<uint64_t> candidateFirst_, candidateCount_;
    std::vector<std::vector<uint32_t>> taken_;         // per chunk: the upper node of each of its first points in key order
    std::vector<Node> upper_;                          // the nodes above the chunks
    std::vector<uint64_t> upperCursor_;
    laz::LaszipVlr z_;
    std::vector<uint8_t> head_;
    uint64_t pointOffset_ = 0, dataAt_ = 0, pointsWritten_ = 0;
    Output out_;
    std::vector<laz::Chunk> chunkTable_;
    std::vector<copc::Node> entries_;
};

}  // namespace

Result<CopcWriteStats> writeCopc(const LasFile& in, const std::string& path, const CopcWriteOptions& options) {
    return CopcBuilder(in, path, options).write();
}

}  // namespace orbis::points
