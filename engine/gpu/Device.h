#pragma once
// The logical device: one queue (graphics + compute + transfer, + present when a surface is
// given), the sub-allocator, a timeline semaphore that orders every submit, and the retire
// list: a destroyed object is freed only once the GPU has finished every submit that may use it.

#include "engine/gpu/Instance.h"
#include "engine/gpu/MemoryAllocator.h"

#include <vulkan/vulkan.h>

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace orbis::gpu {

struct DeviceOptions {
    /// "" = first discrete GPU, else the CPU device (lavapipe), else anything;
    /// "discrete" | "integrated" | "cpu" | "virtual" = first of that type;
    /// a number = index in enumeration order; anything else = case-insensitive name substring.
    std::string select;
    VkSurfaceKHR surface = VK_NULL_HANDLE;   ///< when set: the queue must present to it
    /// Fault injection (tests of the device-lost path): after this many submits, the next
    /// submit acts as if the driver had reported VK_ERROR_DEVICE_LOST. 0: the value of
    /// $ORBIS_FAULT_DEVICE_LOST_AFTER when set, else never.
    uint64_t loseAfterSubmits = 0;
};

/// Optional features the device was created with (renderers choose their paths from these).
struct DeviceFeatures {
    bool shaderInt64 = false;
    bool shaderFloat64 = false;
    bool bufferInt64Atomics = false;
    bool samplerAnisotropy = false;
    bool fillModeNonSolid = false;
    bool wideLines = false;
    bool timestamps = false;
};

/// Live object counts: tests use them to prove that unused layers build nothing.
struct DeviceCounters {
    std::atomic<int> pipelines{0};
    std::atomic<int> images{0};
    std::atomic<int> buffers{0};
    std::atomic<int> pipelinesEverCreated{0};
};

struct PhysicalDeviceInfo {
    VkPhysicalDevice handle = VK_NULL_HANDLE;
    std::string name;
    std::string type;           ///< "discrete", "integrated", "cpu", "virtual", "other"
    uint32_t apiVersion = 0;
    std::string driverInfo;
};

class Device {
public:
    Device(Instance& instance, const DeviceOptions& options);
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    static std::vector<PhysicalDeviceInfo> enumerate(const Instance& instance);

    VkDevice vk() const { return device_; }
    VkPhysicalDevice physical() const { return physical_; }
    VkInstance instance() const { return instance_.vk(); }
    Instance& instanceObject() { return instance_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    const PhysicalDeviceInfo& info() const { return info_; }
    const DeviceFeatures& features() const { return features_; }
    MemoryAllocator& allocator() { return *allocator_; }
    DeviceCounters& counters() { return counters_; }
    float timestampPeriodNs() const { return properties_.limits.timestampPeriod; }

    /// Submits one command buffer; signals the timeline with a new value and returns it.
    /// Main thread only (the single queue is not shared with loader threads).
    ///
    /// Device loss: when a submit or a wait reports VK_ERROR_DEVICE_LOST it throws GpuError
    /// with that result, and the device is lost() for good: later submits throw at once, waits
    /// return at once (nothing will ever complete), waitIdle() and the destructor only destroy
    /// what was retired, so that the app can save its state and close cleanly.
    uint64_t submit(VkCommandBuffer cmd, std::span<const VkSemaphoreSubmitInfo> waits = {},
                    std::span<const VkSemaphoreSubmitInfo> signals = {});
    /// Blocks until the GPU has finished the submit that signalled `value`.
    void wait(uint64_t value);
    uint64_t completedValue() const;
    uint64_t lastSubmitted() const { return lastSubmitted_; }
    /// The device reported VK_ERROR_DEVICE_LOST (or the fault was injected).
    bool lost() const { return lost_; }

    /// Records `record` into a one-shot command buffer, submits it and waits. For set-up work
    /// (initial uploads), never per frame, and never while a frame is being recorded: objects
    /// retired during a frame are keyed to the next submit, which must be that frame's.
    /// Main thread only.
    void runOnce(const std::function<void(VkCommandBuffer)>& record);

    /// Queues `destroy` to run once the GPU has finished the next submit (which may still
    /// reference the object). Any thread.
    void retire(std::function<void()> destroy);
    /// Runs the destroy functions whose submits have completed. Called once per frame.
    void collectRetired();
    /// Waits for the GPU and destroys everything retired. Shutdown and tests only.
    void waitIdle();

    /// FrameRing marks the span between begin() and submit(). Main thread only.
    void setRecordingFrame(bool recording) { recordingFrame_ = recording; }
    bool recordingFrame() const { return recordingFrame_; }

    void setDebugName(uint64_t handle, VkObjectType type, const char* name);

private:
    void pickPhysicalDevice(const std::string& select, VkSurfaceKHR surface);

    Instance& instance_;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    PhysicalDeviceInfo info_;
    VkPhysicalDeviceProperties properties_{};
    DeviceFeatures features_;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    VkSemaphore timeline_ = VK_NULL_HANDLE;
    std::atomic<uint64_t> lastSubmitted_{0};
    mutable std::atomic<bool> lost_{false};
    uint64_t loseAfterSubmits_ = 0;
    /// Throws GpuError for a failed `result`, marking the device lost on VK_ERROR_DEVICE_LOST.
    void check(VkResult result, const char* what) const;
    VkCommandPool oneShotPool_ = VK_NULL_HANDLE;
    bool recordingFrame_ = false;
    std::unique_ptr<MemoryAllocator> allocator_;
    DeviceCounters counters_;
    PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;

    struct Retired {
        uint64_t value;
        std::function<void()> destroy;
    };
    std::mutex retireMutex_;
    std::deque<Retired> retired_;
};

}  // namespace orbis::gpu
