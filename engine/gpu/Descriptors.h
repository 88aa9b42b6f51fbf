#pragma once
// Descriptor sets, samplers and descriptor writes: the one place that spells out
// vkCreateDescriptorSetLayout / vkCreateDescriptorPool / vkAllocateDescriptorSets,
// vkCreateSampler and vkUpdateDescriptorSets for the layers.

#include "engine/gpu/Handle.h"
#include "shared/Common.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace orbis::gpu {

class Buffer;
class Device;

struct DescriptorSets {
    DescriptorSetLayout layout;
    DescriptorPool pool;
    std::vector<VkDescriptorSet> sets;
};

/// `count` sets of the layout made of `bindings` (a shared header's table); the pool holds
/// exactly what they need.
DescriptorSets createDescriptorSets(Device& device, std::span<const shader::DescriptorBinding> bindings, uint32_t count);
/// The same from Vulkan's own binding descriptions.
DescriptorSets createDescriptorSets(Device& device, std::span<const VkDescriptorSetLayoutBinding> bindings, uint32_t count);

VkDescriptorType toVulkan(shader::DescriptorKind kind);

struct SamplerDesc {
    VkFilter filter = VK_FILTER_LINEAR;   ///< magnification and minification
    VkSamplerAddressMode address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;   ///< u, v and w
    std::optional<VkSamplerAddressMode> addressV;                           ///< v's, when not `address`
    /// Linear between mip levels, all levels; else level 0 only (render targets, lookup tables).
    bool mipmaps = false;
    /// Above 1: anisotropic filtering up to this, where the device supports it and is not a CPU
    /// device (lavapipe's, Mesa 22, speckles the image).
    float maxAnisotropy = 0.0f;
};

Sampler createSampler(Device& device, const SamplerDesc& desc);

/// The writes of one descriptor set, binding by binding, applied in one vkUpdateDescriptorSets:
///
///     gpu::DescriptorWriter(set)
///         .uniformBuffer(kVolumeBindingUniforms, uniforms)
///         .sampledImage(kVolumeBindingField, sampler, fieldImage.view())
///         .update(device);
///
/// Sampled images are in SHADER_READ_ONLY_OPTIMAL, storage images in GENERAL.
class DescriptorWriter {
public:
    explicit DescriptorWriter(VkDescriptorSet set) : set_(set) {}

    DescriptorWriter& uniformBuffer(uint32_t binding, const Buffer& buffer, VkDeviceSize offset = 0,
                                    VkDeviceSize range = VK_WHOLE_SIZE);
    DescriptorWriter& storageBuffer(uint32_t binding, const Buffer& buffer, VkDeviceSize offset = 0,
                                    VkDeviceSize range = VK_WHOLE_SIZE);
    /// A dynamic storage buffer: `range` bytes from an offset given when the set is bound.
    DescriptorWriter& storageBufferDynamic(uint32_t binding, const Buffer& buffer, VkDeviceSize range);
    DescriptorWriter& sampledImage(uint32_t binding, VkSampler sampler, VkImageView view);
    /// An array of combined image samplers, element i from views[i].
    DescriptorWriter& sampledImages(uint32_t binding, VkSampler sampler, std::span<const VkImageView> views);
    DescriptorWriter& storageImage(uint32_t binding, VkImageView view);

    void update(Device& device);

private:
    DescriptorWriter& buffer(uint32_t binding, VkDescriptorType type, VkDescriptorBufferInfo info);
    DescriptorWriter& images(uint32_t binding, VkDescriptorType type, std::vector<VkDescriptorImageInfo> infos);

    struct Write {
        uint32_t binding;
        VkDescriptorType type;
        size_t first, count;   // into buffers_ or images_
        bool isBuffer;
    };
    VkDescriptorSet set_;
    std::vector<Write> writes_;
    std::vector<VkDescriptorBufferInfo> buffers_;
    std::vector<VkDescriptorImageInfo> images_;
};

}  // namespace orbis::gpu
