#include "engine/gpu/Descriptors.h"

#include "engine/gpu/Device.h"
#include "engine/gpu/VkCheck.h"

#include <map>

namespace orbis::gpu {

Sampler createClampSampler(Device& device, VkFilter filter) {
    VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    si.magFilter = si.minFilter = filter;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    si.maxLod = 0.0f;
    VkSampler sampler = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSampler(device.vk(), &si, nullptr, &sampler));
    return Sampler(device, sampler);
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

}  // namespace orbis::gpu
