#pragma once
// Which octree nodes are on the GPU (CPU side, no Vulkan): each frame the layer names the nodes
// it wants, most important first; nodes of a store on disk are read on worker threads (at most
// kReadBytesInFlight at a time), then uploaded in that order within a per-frame byte budget into
// one GPU buffer of fixed size. When the buffer is full, the nodes wanted least recently (the
// deepest first among equals) are evicted; a node wanted this frame never is. A freed range is
// reused only once the frames that may still read it are done.
//
// The buffer is split into pages that no node straddles: a shader sees one page at a time
// (a device's maxStorageBufferRange can be smaller than the buffer: 128 MB on lavapipe). When
// the whole cloud fits, every node's place is fixed from the start (packed largest first).

#include "base/ThreadPool.h"
#include "layers/points/PointStore.h"

#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace orbis::points {

class NodeResidency {
public:
    static constexpr uint64_t kReadBytesInFlight = uint64_t(64) << 20;
    static constexpr uint64_t kAlignment = 16;

    /// `gpuBytes`: the buffer's size at most (it is the cloud's size when that is smaller);
    /// `pageBytes`: the pages' size (a multiple of kAlignment; 0: one page); `framesInFlight`:
    /// frames that may read it at once.
    NodeResidency(std::shared_ptr<const PointStore> store, uint64_t gpuBytes, uint64_t pageBytes, uint32_t framesInFlight);
    ~NodeResidency();
    NodeResidency(const NodeResidency&) = delete;
    NodeResidency& operator=(const NodeResidency&) = delete;

    uint64_t capacity() const { return capacity_; }
    uint64_t pageBytes() const { return pageBytes_; }
    uint32_t pages() const { return uint32_t((capacity_ + pageBytes_ - 1) / pageBytes_); }
    /// Nodes larger than a page: never resident (nor their subtrees drawn).
    uint64_t oversizedNodes() const { return oversized_; }
    bool resident(int32_t node) const { return offset_[size_t(node)] >= 0; }
    /// Where a resident node's data start in the buffer (bytes); all in page offset / pageBytes.
    uint64_t offset(int32_t node) const { return uint64_t(offset_[size_t(node)]); }

    /// Starts frame `frame` (increasing): collects finished reads, takes back ranges no frame in
    /// flight can read any more.
    void beginFrame(uint64_t frame);
    /// The frame's wanted nodes, most important first; reads of those not resident are queued
    /// on `pool` (stores on disk). Call once a frame, after beginFrame.
    void want(std::span<const int32_t> nodes, jobs::ThreadPool* pool);
    /// Uploads wanted nodes whose data are at hand, in order, within `budget` bytes (the first
    /// always goes): copy(node, data, offset) records each copy. Returns the bytes uploaded.
    using Copy = std::function<void(int32_t node, std::span<const uint8_t> data, uint64_t offset)>;
    uint64_t upload(uint64_t budget, const Copy& copy);

    /// Reads in flight, wanted nodes waiting for an upload that has room for them, or nodes
    /// uploaded by the last upload() (the frame's selection did not have them yet).
    bool busy() const;
    uint64_t residentNodes() const { return residentNodes_; }
    uint64_t residentPoints() const { return residentPoints_; }
    uint64_t residentBytes() const { return residentBytes_; }
    uint64_t evictions() const { return evictions_; }
    uint64_t readsInFlight() const { return reads_.size(); }
    /// Bytes read and waiting for their upload.
    uint64_t readyBytes() const { return readyBytes_; }
    /// The first read error (a cache file gone or damaged), or empty.
    const std::string& error() const { return error_; }

private:
    bool allocate(uint64_t bytes, uint64_t& offset);
    void release(uint64_t offset, uint64_t bytes);
    bool evictFor(uint64_t bytes, uint64_t& offset);

    std::shared_ptr<const PointStore> store_;
    uint64_t capacity_ = 0, pageBytes_ = 1;
    uint64_t oversized_ = 0;
    uint32_t framesInFlight_ = 2;
    uint64_t frame_ = 0;
    std::vector<int64_t> offset_;       // per node: bytes into the buffer, or -1
    std::vector<int64_t> reserved_;     // per node, when the whole cloud fits in pages: its place
    std::vector<uint64_t> lastWanted_;  // per node: the last frame that wanted it (0: never)
    std::vector<int32_t> wanted_;       // this frame's
    std::map<uint64_t, uint64_t> free_;                         // offset -> bytes, coalesced
    std::vector<std::pair<uint64_t, std::pair<uint64_t, uint64_t>>> freed_;   // (frame, (offset, bytes))
    /// A node's data, or why it could not be read.
    struct NodeRead {
        std::vector<uint8_t> data;
        std::string error;
        bool ok = false;
    };
    struct Read {
        int32_t node;
        uint64_t bytes;
        jobs::Job<NodeRead> job;
    };
    std::vector<Read> reads_;
    std::vector<uint8_t> reading_;   // per node: a read is in flight
    std::vector<uint8_t> failed_;    // per node: its read failed (a streamed store's: skipped from then on)
    uint64_t readBytes_ = 0;
    std::unordered_map<int32_t, std::vector<uint8_t>> ready_;
    uint64_t readyBytes_ = 0;
    uint64_t uploaded_ = 0;  // by the last upload()
    bool waiting_ = false;   // wanted nodes with data left un-uploaded last call (not for lack of room)
    uint64_t residentNodes_ = 0, residentPoints_ = 0, residentBytes_ = 0, evictions_ = 0;
    std::string error_;
    uint64_t failures_ = 0;   // failed reads of a streamed store
};

}  // namespace orbis::points
