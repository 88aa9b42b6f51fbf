#pragma once
// Descriptor sets for a fixed layout: the layout, a pool sized from its bindings for `count`
// sets, and the sets (one per frame in flight, typically). The one place that spells out
// vkCreateDescriptorSetLayout / vkCreateDescriptorPool / vkAllocateDescriptorSets.

#include "engine/gpu/Handle.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::gpu {

class Device;

struct DescriptorSets {
    DescriptorSetLayout layout;
    DescriptorPool pool;
    std::vector<VkDescriptorSet> sets;
};

/// `count` sets of the layout made of `bindings`; the pool holds exactly what they need.
/// A sampler of single-level images, clamped to the edge: `filter` for magnification and
/// minification (compute and full-screen passes read render targets and lookup tables this way).
Sampler createClampSampler(Device& device, VkFilter filter);

DescriptorSets createDescriptorSets(Device& device, std::span<const VkDescriptorSetLayoutBinding> bindings, uint32_t count);

}  // namespace orbis::gpu
