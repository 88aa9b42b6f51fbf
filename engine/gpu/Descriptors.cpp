#include "engine/gpu/Descriptors.h"

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/VkCheck.h"

#include <map>

namespace orbis::gpu {

static_assert(shader::kStageVertex == uint32_t(VK_SHADER_STAGE_VERTEX_BIT));
static_assert(shader::kStageFragment == uint32_t(VK_SHADER_STAGE_FRAGMENT_BIT));
static_assert(shader::kStageCompute == uint32_t(VK_SHADER_STAGE_COMPUTE_BIT));

VkDescriptorType toVulkan(shader::DescriptorKind kind) {
    switch (kind) {
        case shader::DescriptorKind::UniformBuffer: return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        case shader::DescriptorKind::StorageBuffer: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        case shader::DescriptorKind::StorageBufferDynamic: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC;
        case shader::DescriptorKind::CombinedImageSampler: return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        case shader::DescriptorKind::StorageImage: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    }
    return VK_DESCRIPTOR_TYPE_MAX_ENUM;
}

Sampler createSampler(Device& device, const SamplerDesc& desc) {
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    si.magFilter = si.minFilter = desc.filter;
    si.addressModeU = si.addressModeV = si.addressModeW = desc.address;
    if (desc.addressV) si.addressModeV = *desc.addressV;
    si.mipmapMode = desc.mipmaps ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.maxLod = desc.mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
    if (desc.maxAnisotropy > 1.0f && device.features().samplerAnisotropy && device.info().type != "cpu") {
        si.anisotropyEnable = VK_TRUE;
        si.maxAnisotropy = desc.maxAnisotropy;
    }
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(device.vk(), &si, nullptr, &sampler));
    return Sampler(device, sampler);
}

DescriptorSets createDescriptorSets(Device& device, std::span<const shader::DescriptorBinding> bindings, uint32_t count) {
    std::vector<VkDescriptorSetLayoutBinding> vk;
    for (const shader::DescriptorBinding& b : bindings)
        vk.push_back({b.binding, toVulkan(b.kind), b.count, VkShaderStageFlags(b.stages), nullptr});
    return createDescriptorSets(device, std::span<const VkDescriptorSetLayoutBinding>(vk), count);
}

DescriptorSets createDescriptorSets(Device& device, std::span<const VkDescriptorSetLayoutBinding> bindings, uint32_t count) {
    DescriptorSets out;
    VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    li.bindingCount = uint32_t(bindings.size());
    li.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorSetLayout(device.vk(), &li, nullptr, &layout));
    out.layout = DescriptorSetLayout(device, layout);

    std::map<VkDescriptorType, uint32_t> perType;
    for (const VkDescriptorSetLayoutBinding& b : bindings) perType[b.descriptorType] += b.descriptorCount * count;
    std::vector<VkDescriptorPoolSize> sizes;
    for (const auto& [type, n] : perType) sizes.push_back({type, n});
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = count;
    pi.poolSizeCount = uint32_t(sizes.size());
    pi.pPoolSizes = sizes.data();
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VK_CHECK(vkCreateDescriptorPool(device.vk(), &pi, nullptr, &pool));
    out.pool = DescriptorPool(device, pool);

    const std::vector<VkDescriptorSetLayout> layouts(count, layout);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = count;
    ai.pSetLayouts = layouts.data();
    out.sets.resize(count);
    VK_CHECK(vkAllocateDescriptorSets(device.vk(), &ai, out.sets.data()));
    return out;
}

DescriptorWriter& DescriptorWriter::buffer(uint32_t binding, VkDescriptorType type, VkDescriptorBufferInfo info) {
    writes_.push_back({binding, type, buffers_.size(), 1, true});
    buffers_.push_back(info);
    return *this;
}

DescriptorWriter& DescriptorWriter::images(uint32_t binding, VkDescriptorType type, std::vector<VkDescriptorImageInfo> infos) {
    writes_.push_back({binding, type, images_.size(), infos.size(), false});
    images_.insert(images_.end(), infos.begin(), infos.end());
    return *this;
}

DescriptorWriter& DescriptorWriter::uniformBuffer(uint32_t binding, const Buffer& b, VkDeviceSize offset, VkDeviceSize range) {
    return buffer(binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, {b.vk(), offset, range});
}

DescriptorWriter& DescriptorWriter::storageBuffer(uint32_t binding, const Buffer& b, VkDeviceSize offset, VkDeviceSize range) {
    return buffer(binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, {b.vk(), offset, range});
}

DescriptorWriter& DescriptorWriter::storageBufferDynamic(uint32_t binding, const Buffer& b, VkDeviceSize range) {
    return buffer(binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC, {b.vk(), 0, range});
}

DescriptorWriter& DescriptorWriter::sampledImage(uint32_t binding, VkSampler sampler, VkImageView view) {
    return images(binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, {{sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}});
}

DescriptorWriter& DescriptorWriter::sampledImages(uint32_t binding, VkSampler sampler, std::span<const VkImageView> views) {
    std::vector<VkDescriptorImageInfo> infos;
    for (VkImageView v : views) infos.push_back({sampler, v, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
    return images(binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, std::move(infos));
}

DescriptorWriter& DescriptorWriter::storageImage(uint32_t binding, VkImageView view) {
    return images(binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, {{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL}});
}

void DescriptorWriter::update(Device& device) {
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(writes_.size());
    for (const Write& w : writes_) {
        VkWriteDescriptorSet v{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        v.dstSet = set_;
        v.dstBinding = w.binding;
        v.descriptorCount = uint32_t(w.count);
        v.descriptorType = w.type;
        if (w.isBuffer) v.pBufferInfo = &buffers_[w.first];
        else v.pImageInfo = &images_[w.first];
        writes.push_back(v);
    }
    vkUpdateDescriptorSets(device.vk(), uint32_t(writes.size()), writes.data(), 0, nullptr);
    writes_.clear();
    buffers_.clear();
    images_.clear();
}

}  // namespace orbis::gpu
