#include "layers/points/NodeResidency.h"

#include "base/Log.h"

#include <algorithm>

namespace orbis::points {
namespace {

uint64_t aligned(uint64_t bytes) { return (bytes + NodeResidency::kAlignment - 1) / NodeResidency::kAlignment * NodeResidency::kAlignment; }

}  // namespace

NodeResidency::NodeResidency(std::shared_ptr<const PointStore> store, uint64_t gpuBytes, uint64_t pageBytes,
                             uint32_t framesInFlight)
    : store_(std::move(store)), framesInFlight_(std::max(1u, framesInFlight)) {
    const auto& nodes = store_->nodes();
    uint64_t total = 0;
    for (const StoredNode& n : nodes) total += aligned(n.bytes());
    const uint64_t budget = gpuBytes / kAlignment * kAlignment;
    capacity_ = std::min(total, budget);
    pageBytes_ = pageBytes == 0 ? capacity_ : std::max(pageBytes / kAlignment * kAlignment, kAlignment);
    if (capacity_ <= pageBytes_) {
        pageBytes_ = std::max<uint64_t>(capacity_, kAlignment);   // one page: the whole buffer
    } else {
        // Whole pages (every page is bound with the same range). When the whole cloud fits the
        // budget, every node gets its place now (largest first, each in the first page with
        // room): pages leave gaps that nodes arriving in any order might not fill.
        if (total <= budget) {
            std::vector<int32_t> bySize(nodes.size());
            for (size_t i = 0; i < nodes.size(); ++i) bySize[i] = int32_t(i);
            std::stable_sort(bySize.begin(), bySize.end(),
                             [&](int32_t a, int32_t b) { return nodes[size_t(a)].bytes() > nodes[size_t(b)].bytes(); });
            std::vector<uint64_t> used;   // per page
            reserved_.assign(nodes.size(), -1);
            for (int32_t n : bySize) {
                const uint64_t size = aligned(nodes[size_t(n)].bytes());
                if (size > pageBytes_) continue;
                size_t p = 0;
                while (p < used.size() && used[p] + size > pageBytes_) ++p;
                if (p == used.size()) used.push_back(0);
                reserved_[size_t(n)] = int64_t(p * pageBytes_ + used[p]);
                used[p] += size;
            }
            if (used.size() * pageBytes_ <= budget) {
                capacity_ = used.size() * pageBytes_;
            } else {
                reserved_.clear();   // packing needs more pages than the budget: as below
            }
        }
        if (reserved_.empty()) capacity_ = capacity_ / pageBytes_ * pageBytes_;
    }
    for (uint64_t at = 0; reserved_.empty() && at < capacity_; at += pageBytes_) free_[at] = pageBytes_;
    for (const StoredNode& n : nodes)
        if (aligned(n.bytes()) > pageBytes_) ++oversized_;
    offset_.assign(nodes.size(), -1);
    lastWanted_.assign(nodes.size(), 0);
    reading_.assign(nodes.size(), 0);
    failed_.assign(nodes.size(), 0);
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
    // Coalesced with its neighbours within its page, never across a page's start.
    auto next = free_.lower_bound(offset);
    if (next != free_.end() && offset + bytes == next->first && next->first % pageBytes_ != 0) {
        bytes += next->second;
        next = free_.erase(next);
    }
    if (next != free_.begin() && offset % pageBytes_ != 0) {
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
            if (data.ok) {
                readyBytes_ += data.data.size();
                ready_[r.node] = std::move(data.data);
            } else if (store_->streamed()) {
                // A damaged node of a COPC file: said once, skipped, the others still load.
                failed_[size_t(r.node)] = 1;
                if (failures_++ == 0) log::warn("points: ", data.error, " (the node is skipped)");
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
        if (resident(n) || reading_[size_t(n)] || failed_[size_t(n)] || ready_.count(n)) continue;
        const uint64_t bytes = store_->nodes()[size_t(n)].bytes();
        if (!reads_.empty() && readBytes_ + bytes > kReadBytesInFlight) break;
        std::shared_ptr<const PointStore> store = store_;
        auto job = pool->submit(0.0, jobs::CancelToken::create(),
                                [store, n](const jobs::CancelToken&) {
                                    NodeRead read;
                                    read.ok = store->read(size_t(n), read.data, &read.error);
                                    return read;
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
        if (size > pageBytes_) continue;   // never fits (its subtree is not drawn either)
        if (bytes > 0 && bytes + size > budget) {
            waiting_ = true;   // the next frame's budget
            break;
        }
        uint64_t offset = reserved_.empty() ? 0 : uint64_t(reserved_[size_t(n)]);
        if (reserved_.empty() && !evictFor(size, offset)) {
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
