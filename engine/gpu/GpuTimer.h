#pragma once
// GPU timestamps per pass. Each frame slot owns a range of queries; results are read once the
// slot's submit has completed (FrameRing guarantees it before the slot is reused).

#include "engine/gpu/Handle.h"

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

namespace orbis::gpu {

struct PassTime {
    std::string name;
    double ms = 0.0;
};

class GpuTimer {
public:
    GpuTimer(Device& device, uint32_t frameSlots, uint32_t maxScopesPerFrame = 32);

    bool enabled() const { return static_cast<bool>(pool_); }

    /// Reads the slot's previous results (its submit must be complete), then resets its queries.
    /// Called while recording, before any scope.
    void beginFrame(VkCommandBuffer cmd, uint32_t slot);
    /// Returns the scope index to pass to end(). Called while recording, outside rendering.
    int begin(VkCommandBuffer cmd, const std::string& name);
    void end(VkCommandBuffer cmd, int scope);

    /// Results of the last completed use of `slot` (after beginFrame read them), or of the
    /// current frame once its submit has completed (see resolve()).
    const std::vector<PassTime>& results(uint32_t slot) const { return slots_[slot].results; }
    /// Reads the results of `slot` now; its submit must have completed.
    const std::vector<PassTime>& resolve(uint32_t slot);

private:
    struct Slot {
        std::vector<std::string> names;
        std::vector<PassTime> results;
        bool pending = false;
    };
    Device& device_;
    QueryPool pool_;
    uint32_t maxScopes_;
    uint32_t current_ = 0;
    double periodNs_ = 1.0;
    std::vector<Slot> slots_;
};

}  // namespace orbis::gpu
