#include "engine/gpu/GpuTimer.h"

#include "engine/gpu/VkCheck.h"

namespace orbis::gpu {

GpuTimer::GpuTimer(Device& device, uint32_t frameSlots, uint32_t maxScopesPerFrame)
    : device_(device), maxScopes_(maxScopesPerFrame), slots_(frameSlots) {
    if (!device.features().timestamps) return;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = frameSlots * maxScopesPerFrame * 2;
    VkQueryPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateQueryPool(device.vk(), &info, nullptr, &pool));
    pool_ = QueryPool(device, pool);
    periodNs_ = device.timestampPeriodNs();
}

const std::vector<PassTime>& GpuTimer::resolve(uint32_t slot) {
    Slot& s = slots_[slot];
    if (!s.pending || !pool_) return s.results;
    s.pending = false;
    s.results.clear();
    if (s.names.empty()) return s.results;
    std::vector<uint64_t> stamps(s.names.size() * 2);
    const VkResult r = vkGetQueryPoolResults(device_.vk(), pool_.vk(), slot * maxScopes_ * 2,
                                             static_cast<uint32_t>(stamps.size()), stamps.size() * sizeof(uint64_t),
                                             stamps.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) return s.results;   // not ready: report nothing rather than garbage
    for (size_t i = 0; i < s.names.size(); ++i) {
        const double ns = static_cast<double>(stamps[2 * i + 1] - stamps[2 * i]) * periodNs_;
        s.results.push_back({s.names[i], ns * 1e-6});
    }
    return s.results;
}

void GpuTimer::beginFrame(VkCommandBuffer cmd, uint32_t slot) {
    current_ = slot;
    if (!pool_) return;
    resolve(slot);
    slots_[slot].names.clear();
    vkCmdResetQueryPool(cmd, pool_.vk(), slot * maxScopes_ * 2, maxScopes_ * 2);
}

int GpuTimer::begin(VkCommandBuffer cmd, const std::string& name) {
    Slot& s = slots_[current_];
    if (!pool_ || s.names.size() >= maxScopes_) return -1;
    const int scope = static_cast<int>(s.names.size());
    s.names.push_back(name);
    s.pending = true;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, pool_.vk(), current_ * maxScopes_ * 2 + scope * 2);
    return scope;
}

void GpuTimer::end(VkCommandBuffer cmd, int scope) {
    if (!pool_ || scope < 0) return;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_.vk(),
                         current_ * maxScopes_ * 2 + scope * 2 + 1);
}

}  // namespace orbis::gpu
