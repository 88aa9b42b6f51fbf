#include "layers/points/NodeResidency.h"

#include <algorithm>

namespace orbis::points {
namespace {

uint64_t aligned(uint64_t bytes) { return (bytes + NodeResidency::kAlignment - 1) / NodeResidency::kAlignment * NodeResidency::kAlignment; }

}  // namespace

NodeResidency::NodeResidency(std::shared_ptr<const PointStore> store, uint64_t gpuBytes, uint32_t framesInFlight)
    : store_(std::move(store)), framesInFlight_(std::max(1u, framesInFlight)) {
    const auto& nodes = store_->nodes();
    uint64_t total = 0;
    for (const StoredNode& n : nodes) total += aligned(n.bytes());
    capacity_ = std::min(total, gpuBytes / kAlignment * kAlignment);
    if (capacity_ > 0) free_[0] = capacity_;
    offset_.assign(nodes.size(), -1);
    lastWanted_.assign(nodes.size(), 0);
    reading_.assign(nodes.size(), 0);
}

NodeResidency::~NodeResidency() {
    for (Read& r : reads_) r.job.cancel();
}

bool NodeResidency::allocate(uint64_t bytes, uint64_t& offset) {
    for (auto it = free_.begin(); it != free_.end(); ++it)
        if (it->second >= bytes) {
            offset = it->first;
            const uint64_t left = it->second - bytes;
            free_.erase(it);
            if (left > 0) free_[offset + bytes] = left;
            return true;
        }
    return false;
}

void NodeResidency::release(uint64_t offset, uint64_t bytes) {
    auto next = free_.lower_bound(offset);
    if (next != free_.end() && offset + bytes == next->first) {
        bytes += next->second;
        next = free_.erase(next);
    }
    if (next != free_.begin()) {
        auto prev = std::prev(next);
        if (prev->first + prev->second == offset) {
            prev->second += bytes;
            return;
        }
    }
    free_[offset] = bytes;
}

void NodeResidency::beginFrame(uint64_t frame) {
    frame_ = frame;
    // Ranges evicted framesInFlight frames ago: no frame that drew from them is still running.
    std::erase_if(freed_, [&](const auto& f) {
        if (f.first + framesInFlight_ > frame_) return false;
        release(f.second.first, f.second.second);
        return true;
    });
    std::erase_if(reads_, [&](Read& r) {
        if (!r.job.ready()) return false;
        readBytes_ -= r.bytes;
        reading_[size_t(r.node)] = 0;
        try {
            auto data = r.job.get();
            if (data) {
                readyBytes_ += data->size();
                ready_[r.node] = std::move(*data);
            } else if (error_.empty()) {
                error_ = "point cache " + store_->path() + ": cannot read node " + std::to_string(r.node);
            }
        } catch (const std::exception&) {   // cancelled
        }
        return true;
    });
}

void NodeResidency::want(std::span<const int32_t> nodes, jobs::ThreadPool* pool) {
    wanted_.assign(nodes.begin(), nodes.end());
    for (int32_t n : wanted_) lastWanted_[size_t(n)] = frame_;
    // Read data nobody wants any more is dropped (it is read again if wanted again).
    std::erase_if(ready_, [&](const auto& r) {
        if (lastWanted_[size_t(r.first)] == frame_) return false;
        readyBytes_ -= r.second.size();
        return true;
    });
    if (!store_->onDisk() || !pool || !error_.empty()) return;
    for (int32_t n : wanted_) {
        if (resident(n) || reading_[size_t(n)] || ready_.count(n)) continue;
        const uint64_t bytes = store_->nodes()[size_t(n)].bytes();
        if (!reads_.empty() && readBytes_ + bytes > kReadBytesInFlight) break;
        std::shared_ptr<const PointStore> store = store_;
        auto job = pool->submit(0.0, jobs::CancelToken::create(),
                                [store, n](const jobs::CancelToken&) -> std::optional<std::vector<uint8_t>> {
                                    std::vector<uint8_t> data;
                                    if (!store->read(size_t(n), data)) return std::nullopt;
                                    return data;
                                });
        reads_.push_back({n, bytes, std::move(job)});
        reading_[size_t(n)] = 1;
        readBytes_ += bytes;
    }
}

bool NodeResidency::evictFor(uint64_t bytes, uint64_t& offset) {
    if (allocate(bytes, offset)) return true;
    // Nodes not wanted this frame, the least recently wanted first, the deepest among equals.
    std::vector<int32_t> candidates;
    for (size_t i = 0; i < offset_.size(); ++i)
        if (offset_[i] >= 0 && lastWanted_[i] < frame_) candidates.push_back(int32_t(i));
    const auto& nodes = store_->nodes();
    std::sort(candidates.begin(), candidates.end(), [&](int32_t a, int32_t b) {
        if (lastWanted_[size_t(a)] != lastWanted_[size_t(b)]) return lastWanted_[size_t(a)] < lastWanted_[size_t(b)];
        return nodes[size_t(a)].level > nodes[size_t(b)].level;
    });
    // Ranges already evicted and not yet back count towards the room needed.
    uint64_t coming = 0;
    for (const auto& f : freed_) coming += f.second.second;
    for (int32_t c : candidates) {
        if (coming >= bytes) break;
        const uint64_t size = aligned(nodes[size_t(c)].bytes());
        freed_.push_back({frame_, {uint64_t(offset_[size_t(c)]), size}});
        offset_[size_t(c)] = -1;
        --residentNodes_;
        residentPoints_ -= nodes[size_t(c)].count;
        residentBytes_ -= size;
        ++evictions_;
        coming += size;
    }
    return false;
}

uint64_t NodeResidency::upload(uint64_t budget, const Copy& copy) {
    waiting_ = false;
    uint64_t& bytes = uploaded_;
    bytes = 0;
    const auto& nodes = store_->nodes();
    for (int32_t n : wanted_) {
        if (resident(n)) continue;
        std::span<const uint8_t> data = store_->view(size_t(n));
        auto ready = ready_.find(n);
        if (data.empty() && ready != ready_.end()) data = ready->second;
        if (data.empty() && nodes[size_t(n)].count > 0) continue;   // still being read
        const uint64_t size = aligned(data.size());
        if (bytes > 0 && bytes + size > budget) {
            waiting_ = true;   // the next frame's budget
            break;
        }
        uint64_t offset = 0;
        if (!evictFor(size, offset)) {
            // Room comes back once the frames in flight are done, if anything could be evicted.
            waiting_ = !freed_.empty();
            break;
        }
        if (!data.empty()) copy(n, data, offset);
        offset_[size_t(n)] = int64_t(offset);
        ++residentNodes_;
        residentPoints_ += nodes[size_t(n)].count;
        residentBytes_ += size;
        bytes += size;
        if (ready != ready_.end()) {
            readyBytes_ -= ready->second.size();
            ready_.erase(ready);
        }
    }
    return bytes;
}

bool NodeResidency::busy() const { return !reads_.empty() || waiting_ || uploaded_ > 0; }

}  // namespace orbis::points
