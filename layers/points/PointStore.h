#pragma once
// A point cloud's octree, ready for drawing (CPU only, no Vulkan): the node table, always in
// memory, and each node's points, in memory for small clouds or in a cache file on disk,
// read node by node on demand (so a cloud larger than memory costs its node table only).
//
// A node's data is what the GPU reads, byte for byte:
//   count x 8 bytes   attributes: uvec2(sRGB r | g << 8 | b << 16 | class << 24,
//                                       intensity | height << 16)
//   count x 8 bytes   positions quantised: 3 x 21 bits in a uvec2 (x | y << 21, y >> 11 | z << 10),
//                     p = centre + (q - 2^20) * step                                   if step > 0
//   count x 12 bytes  positions as floats relative to the node's centre               if step == 0
// A node is quantised when its step (edge / 2^21) is within the cloud's tolerance (half the
// file's coordinate resolution, at most 1 cm), else stored as floats: a 10 km node keeps 5 mm
// quantised, a 2 km node 1 mm; floats keep 0.1 mm at 2 km.
//
// The cache file ("ORBISPTS", little-endian): a 256-byte header, the key text (what the cache
// was built from: file, size, time, CRS, options; a different key means a rebuild), then the
// nodes' data, then the node table (StoredNode records).

#include "base/Result.h"
#include "layers/points/PointOctree.h"

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace orbis::points {

class LasFile;
class PointGeoreference;

/// A node as stored (the cache file's node table, 96 bytes).
struct StoredNode {
    glm::dvec3 centre{0.0};   ///< ECEF (m)
    double halfSize = 0.0;
    double step = 0.0;        ///< quantisation step (m); 0: float positions
    uint64_t offset = 0;      ///< its data: bytes from the start of the store's data
    uint32_t count = 0;
    int32_t parent = -1;
    int32_t children[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    uint32_t level = 0;
    uint32_t crc = 0;         ///< CRC-32 of its data, checked when read from a cache file
    double radius() const { return halfSize * 1.7320508075688772; }   ///< holds the node and its subtree
    uint64_t bytes() const { return uint64_t(count) * (step > 0.0 ? 16 : 20); }
    uint64_t positionOffset() const { return uint64_t(count) * 8; }   ///< within its data
};
static_assert(sizeof(StoredNode) == 96);

/// What a cloud's loading found out about it.
struct CloudInfo {
    double heightMin = 0.0, heightMax = 0.0;   ///< metres above the ellipsoid
    float intensityGain = 1.0f;                ///< 1 / the 99th percentile of the intensities
    uint64_t read = 0;                         ///< points in the file
    uint64_t dropped = 0;                      ///< points that could not be placed
    uint64_t points = 0;                       ///< points in the octree
    uint32_t depth = 0;                        ///< the octree's deepest level
    uint32_t rgb = 0;                          ///< the format carries colour
    uint32_t rgb16 = 0;                        ///< colours use 16 bits (else 8 bits in 16-bit fields)
    float tolerance = 0.0f;                    ///< quantisation's largest step (m)
};

class PointStore {
public:
    /// Makes a node's data on demand (a COPC node decoded): any thread; an error names the node.
    using NodeSource = std::function<Result<std::vector<uint8_t>>(size_t node)>;
    /// A cloud whose nodes come from `source` (a COPC file's own octree): nothing is built.
    static std::shared_ptr<PointStore> streamed(std::vector<StoredNode> nodes, const CloudInfo& info, NodeSource source);
    /// Small clouds: everything in memory.
    static std::shared_ptr<PointStore> inMemory(std::vector<StoredNode> nodes, std::vector<uint8_t> data,
                                                const CloudInfo& info);
    /// Opens a cache file, checking it whole (version, sizes, offsets, links, the checksum of its
    /// header and node table) and that it was built from `key`; errors name the file and the
    /// problem. Each node's data is checked against its checksum when read.
    static Result<std::shared_ptr<PointStore>> open(const std::string& path, const std::string& key);
    ~PointStore();
    PointStore(const PointStore&) = delete;
    PointStore& operator=(const PointStore&) = delete;

    const std::vector<StoredNode>& nodes() const { return nodes_; }
    const CloudInfo& info() const { return info_; }
    /// The cache file, or empty for a store in memory.
    const std::string& path() const { return path_; }
    /// Nodes are read (from the cache file or the source), not viewed in memory.
    bool onDisk() const { return fd_ >= 0 || source_ != nullptr; }
    /// Nodes come from a source (COPC): one that fails is skipped, the others still load.
    bool streamed() const { return source_ != nullptr; }
    /// Node i's data into `out` (resized). Any thread; false (and a message) on a read error or
    /// when the data fails its checksum: then the corrupted file is removed (once, logged), so
    /// that the next load builds it again.
    bool read(size_t node, std::vector<uint8_t>& out, std::string* error = nullptr) const;
    /// The node's data in place, for a store in memory (empty for one on disk).
    std::span<const uint8_t> view(size_t node) const;
    /// Bytes held in memory: the node table, and the data of a store in memory.
    uint64_t memoryBytes() const { return nodes_.size() * sizeof(StoredNode) + data_.size(); }

    /// The ECEF position of point k of a node's data (tests, tools).
    static glm::dvec3 position(const StoredNode& node, std::span<const uint8_t> data, uint32_t k);

private:
    PointStore() = default;
    std::vector<StoredNode> nodes_;
    std::vector<uint8_t> data_;   // in memory
    int fd_ = -1;                 // on disk
    uint64_t dataOffset_ = 0;     // where the nodes' data start in the file
    std::string path_;
    NodeSource source_;
    CloudInfo info_;
    mutable std::once_flag corruptOnce_;
};

struct PointLoadOptions {
    PointOctree::Options octree;
    /// A node's points in Z order of their positions (neighbours in memory are neighbours on
    /// screen: the splat's writes stay together); else in the octree's random key order.
    bool mortonOrder = true;
    uint64_t pointsPerRead = 1u << 20;   ///< points decoded at a time
    /// Clouds up to this many points are built in memory (about 70 bytes a point while building,
    /// 16-20 bytes kept); larger ones go through the cache file.
    uint64_t inMemoryPoints = 8'000'000;
    /// When the cache cannot be written (a read-only or full folder), clouds up to this many
    /// points are built in memory instead, with a warning; larger ones fail with the reason.
    uint64_t fallbackInMemoryPoints = 40'000'000;
    /// The out-of-core build's chunks: subtrees built in memory, up to about this many points
    /// each (raised to 8 x the capacity).
    uint64_t chunkPoints = 8'000'000;
    /// Where the cache file goes. Empty: next to the LAS file when that folder is writable,
    /// else the user's cache folder (defaultPointCacheDir()).
    std::string cacheFolder;
    const std::atomic<bool>* cancel = nullptr;   ///< stop early (an error "cancelled")
    std::function<void(double)> progress;        ///< 0..1, from the loading thread
};

/// $ORBIS_CACHE_DIR/points, else $XDG_CACHE_HOME/orbis/points, else ~/.cache/orbis/points.
std::string defaultPointCacheDir();

/// Builds the octree of `file` placed by `georef` (in memory for small clouds; else reusing a
/// valid cache file, or building one chunk by chunk in bounded memory). Any thread.
Result<std::shared_ptr<PointStore>> loadPointStore(const LasFile& file, const PointGeoreference& georef,
                                                   const PointLoadOptions& options);
/// A COPC file's own octree as a store (CopcStore.cpp): the hierarchy is read, the root node
/// decoded (for the colours' depth and the intensities' range), and every other node is decoded
/// when the renderer wants it. Nothing is built or cached. Any thread.
Result<std::shared_ptr<PointStore>> loadCopcStore(std::shared_ptr<const LasFile> file, const PointGeoreference& georef,
                                                  const PointLoadOptions& options);

}  // namespace orbis::points
