#pragma once
// Frames in flight: each slot has its own command pool and buffer and remembers the timeline
// value of its last submit. Beginning a slot waits only for that slot's previous use, so the
// CPU records frame N+1 while the GPU renders frame N.

#include "engine/gpu/Handle.h"

#include <vulkan/vulkan.h>

#include <vector>

namespace orbis::gpu {

class FrameRing {
public:
    struct Frame {
        uint32_t slot = 0;
        uint64_t number = 0;            ///< frames begun so far, including this one
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        uint64_t submitted = 0;         ///< timeline value of this slot's last submit
    };

    explicit FrameRing(Device& device, uint32_t framesInFlight = 2);
    ~FrameRing();
    FrameRing(const FrameRing&) = delete;
    FrameRing& operator=(const FrameRing&) = delete;

    /// Waits until the next slot's previous submit is done, resets it and begins recording.
    /// Also frees retired objects whose submits have completed. Main thread only.
    Frame& begin();
    /// Ends recording and submits. Returns the timeline value the GPU signals when done.
    uint64_t submit(Frame& frame, std::span<const VkSemaphoreSubmitInfo> waits = {},
                    std::span<const VkSemaphoreSubmitInfo> signals = {});

    uint32_t framesInFlight() const { return static_cast<uint32_t>(slots_.size()); }

private:
    struct Slot {
        CommandPool pool;
        Frame frame;
    };
    Device& device_;
    std::vector<Slot> slots_;
    uint64_t frameNumber_ = 0;
};

}  // namespace orbis::gpu
