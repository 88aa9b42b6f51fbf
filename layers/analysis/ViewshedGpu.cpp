#include "layers/analysis/ViewshedGpu.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "shared/ViewshedTypes.h"
#include "spv/analysis/viewshed.comp.h"
#include "spv/analysis/viewshed_cpu.comp.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace orbis::layers {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

ViewshedGpu::ViewshedGpu(gpu::Device& device, Workgroup workgroup) : device_(device), timer_(device, 1, 2) {
    descriptors_ = gpu::createDescriptorSets(device, shader::kViewshedBindings, 1);
    const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(shader::ViewshedPush)};
    const VkDescriptorSetLayout sets[] = {descriptors_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, sets, {&push, 1});
    // A CPU device, or one whose workgroups cannot hold kViewshedGroupSize: the small workgroup.
    const auto& limits = device.properties().limits;
    const bool fits = limits.maxComputeWorkGroupSize[0] >= shader::kViewshedGroupSize &&
                      limits.maxComputeWorkGroupInvocations >= shader::kViewshedGroupSize;
    const bool small = !fits || workgroup == Workgroup::Narrow || (workgroup == Workgroup::Auto && device.info().type == "cpu");
    pipeline_ = small ? gpu::createComputePipeline(device, layout_.vk(), kSpv_analysis_viewshed_cpu_comp, nullptr, "viewshed (CPU device)")
                      : gpu::createComputePipeline(device, layout_.vk(), kSpv_analysis_viewshed_comp, nullptr, "viewshed");
}

ViewshedGpu::~ViewshedGpu() = default;

Result<void> ViewshedGpu::setGrid(const globe::ViewshedGrid& grid) {
    const size_t cells = size_t(grid.side()) * size_t(grid.side());
    if (grid.radiusCells < 1 || grid.heights.size() != cells) return makeError("the viewshed grid is empty or inconsistent");
    const VkDeviceSize bytes = VkDeviceSize(cells) * 4;
    if (bytes > device_.properties().limits.maxStorageBufferRange)
        return makeError("a viewshed grid of " + std::to_string(grid.side()) + " cells a side is more than this device's storage buffers hold");
    if (cells > capacity_) {
        heights_ = gpu::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly,
                               "viewshed heights");
        horizon_ = gpu::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::GpuOnly, "viewshed horizon");
        sights_ = gpu::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                                  VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              gpu::MemoryUsage::GpuOnly, "viewshed sights");
        readback_ = gpu::Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "viewshed readback");
        capacity_ = cells;
        gpu::DescriptorWriter(descriptors_.sets[0])
            .storageBuffer(shader::kViewshedBindingHeights, heights_)
            .storageBuffer(shader::kViewshedBindingHorizon, horizon_)
            .storageBuffer(shader::kViewshedBindingSight, sights_)
            .update(device_);
    }
    gpu::Uploader uploader(device_);
    device_.runOnce([&](VkCommandBuffer cmd) {
        uploader.toBuffer(cmd, heights_, grid.heights.data(), bytes);
        gpu::bufferBarrier(cmd, heights_, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    });
    grid_ = grid;
    return {};
}

Result<void> ViewshedGpu::record(VkCommandBuffer cmd, const globe::ViewshedOptions& options) {
    if (!grid_) return makeError("the viewshed has no grid yet");
    auto eye = globe::viewshedEyeHeight(*grid_, options);
    if (!eye) return eye.error();
    if (!std::isfinite(options.targetHeight) || !std::isfinite(options.curvature) || options.curvature < 0.0 || options.curvature > 2.0 ||
        !std::isfinite(options.radiusM) || options.radiusM < 0.0)
        return makeError("the viewshed's target height, curvature or radius is out of range");
    const globe::ViewshedGrid& g = *grid_;
    const int side = g.side();
    const VkDeviceSize bytes = VkDeviceSize(side) * VkDeviceSize(side) * 4;
    shader::ViewshedPush push{};
    push.observerCol = options.observerCol;
    push.observerRow = options.observerRow;
    push.side = side;
    push.eye = float(*eye);
    push.dropPerCell2 = float(options.curvature / globe::kViewshedEarthDiameter * g.cellM * g.cellM);
    const double radiusCells = options.radiusM / g.cellM;
    push.radius2Cells = float(radiusCells * radiusCells);
    push.targetHeight = float(options.targetHeight);
    push.observerHeight = float(options.observerHeight);
    int rings = std::max({options.observerCol, options.observerRow, side - 1 - options.observerCol, side - 1 - options.observerRow});
    if (options.radiusM > 0.0) rings = std::min(rings, int(std::ceil(radiusCells)));

    vkCmdFillBuffer(cmd, sights_.vk(), 0, bytes, shader::kSightOutOfRange);
    gpu::bufferBarrier(cmd, sights_, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.vk());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.vk(), shader::kViewshedSet, 1, &descriptors_.sets[0], 0, nullptr);
    push.ring = rings;
    vkCmdPushConstants(cmd, layout_.vk(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    vkCmdDispatch(cmd, shader::kViewshedGroups, 1, 1);
    lastRings_ = rings + 1;
    return {};
}

Result<globe::Viewshed> ViewshedGpu::run(const globe::ViewshedOptions& options, ViewshedTiming* timing) {
    if (!grid_) return makeError("the viewshed has no grid yet");
    const int side = grid_->side();
    const VkDeviceSize bytes = VkDeviceSize(side) * VkDeviceSize(side) * 4;
    Result<void> recorded;
    const auto t0 = std::chrono::steady_clock::now();
    device_.runOnce([&](VkCommandBuffer cmd) {
        if (timer_.enabled()) timer_.beginFrame(cmd, 0);
        const int scope = timer_.enabled() ? timer_.begin(cmd, "viewshed") : -1;
        recorded = record(cmd, options);
        if (scope >= 0) timer_.end(cmd, scope);
        if (!recorded) return;
        gpu::bufferBarrier(cmd, sights_, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                       VK_ACCESS_2_TRANSFER_READ_BIT);
        const VkBufferCopy copy{0, 0, bytes};
        vkCmdCopyBuffer(cmd, sights_.vk(), readback_.vk(), 1, &copy);
        gpu::bufferBarrier(cmd, readback_, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                       VK_ACCESS_2_HOST_READ_BIT);
    });
    if (!recorded) return recorded.error();
    const double submitMs = msSince(t0);
    const auto t1 = std::chrono::steady_clock::now();
    readback_.invalidate();
    globe::Viewshed out;
    out.side = side;
    out.cells.resize(size_t(side) * size_t(side));
    const auto* codes = static_cast<const uint32_t*>(readback_.mapped());
    for (size_t i = 0; i < out.cells.size(); ++i) out.cells[i] = globe::Sight(std::min<uint32_t>(codes[i], shader::kSightNoData));
    if (timing) {
        timing->submitMs = submitMs;
        timing->readbackMs = msSince(t1);
        timing->rings = lastRings_;
        timing->gpuMs = 0.0;
        if (timer_.enabled())
            for (const auto& p : timer_.resolve(0)) timing->gpuMs += p.ms;
    }
    return out;
}

}  // namespace orbis::layers
