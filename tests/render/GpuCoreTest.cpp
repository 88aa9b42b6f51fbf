// The Vulkan layer: deferred deletion, the sub-allocator, uploads and readback, timestamps.
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/FrameRing.h"
#include "engine/gpu/GpuTimer.h"
#include "engine/gpu/Image.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/Renderer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/support/GpuTest.h"

#include <numeric>

namespace orbis::test {
namespace {

class GpuCore : public GpuTest {};

TEST_F(GpuCore, ValidationLayerReportsMisuse) {
    // Proves the harness can fail: a fill at an unaligned offset (VUID-vkCmdFillBuffer-dstOffset-00025)
    // recorded into a command buffer that is never submitted.
    ASSERT_TRUE(instance().validationEnabled());
    gpu::Buffer b(device(), 256, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly);
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = device().queueFamily();
    VkCommandPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateCommandPool(device().vk(), &poolInfo, nullptr, &pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    ASSERT_EQ(vkAllocateCommandBuffers(device().vk(), &alloc, &cmd), VK_SUCCESS);
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(cmd, &begin);
    const int before = instance().validationMessages();
    vkCmdFillBuffer(cmd, b.vk(), 3, 16, 0);
    vkEndCommandBuffer(cmd);
    vkDestroyCommandPool(device().vk(), pool, nullptr);
    EXPECT_GT(instance().validationMessages(), before);
    acknowledgeValidationMessages();
}

TEST_F(GpuCore, DestroyedBufferIsFreedOnlyAfterItsSubmitCompletes) {
    auto& alloc = device().allocator();
    const auto before = alloc.stats().bytesInUse;
    gpu::FrameRing ring(device(), 2);
    auto& frame = ring.begin();
    {
        gpu::Buffer b(device(), 4096, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly);
        vkCmdFillBuffer(frame.cmd, b.vk(), 0, VK_WHOLE_SIZE, 7);
    }   // destroyed while the command buffer that uses it is not even submitted
    EXPECT_GE(alloc.stats().bytesInUse, before + 4096) << "freed before the GPU used it";
    const uint64_t value = ring.submit(frame);
    device().wait(value);
    device().collectRetired();
    EXPECT_EQ(alloc.stats().bytesInUse, before);
}

TEST_F(GpuCore, SmallResourcesShareDriverAllocations) {
    auto& alloc = device().allocator();
    const auto blocksBefore = alloc.stats().driverAllocations;
    std::vector<gpu::Buffer> buffers;
    for (int i = 0; i < 200; ++i)
        buffers.emplace_back(device(), 64 * 1024, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::GpuOnly);
    // 200 x 64 KiB = 12.5 MiB fits in one 64 MiB block (two if one was partly used).
    EXPECT_LE(alloc.stats().driverAllocations - blocksBefore, 2u);
    buffers.clear();
    device().waitIdle();
}

TEST_F(GpuCore, UploadThenReadbackRoundTrips) {
    std::vector<uint32_t> data(1000);
    std::iota(data.begin(), data.end(), 12345u);
    gpu::Uploader uploader(device());
    gpu::Buffer gpuBuffer(device(), data.size() * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                          gpu::MemoryUsage::GpuOnly);
    gpu::Buffer readback(device(), data.size() * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback);
    device().runOnce([&](VkCommandBuffer cmd) {
        uploader.toBuffer(cmd, gpuBuffer, data.data(), data.size() * 4);
        gpu::bufferBarrier(cmd, gpuBuffer, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferCopy region{0, 0, data.size() * 4};
        vkCmdCopyBuffer(cmd, gpuBuffer.vk(), readback.vk(), 1, &region);
        gpu::bufferBarrier(cmd, readback, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    readback.invalidate();
    const auto* out = static_cast<const uint32_t*>(readback.mapped());
    EXPECT_TRUE(std::equal(data.begin(), data.end(), out));
    EXPECT_EQ(uploader.bytesUploaded(), data.size() * 4);
}

TEST_F(GpuCore, ImageUploadAndTransitionsAreValid) {
    gpu::ImageDesc desc;
    desc.format = VK_FORMAT_R32_SFLOAT;
    desc.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    desc.extent = {16, 16, 1};
    desc.layers = 4;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    gpu::Image image(device(), desc);
    std::vector<float> texels(16 * 16, 1.5f);
    gpu::Uploader uploader(device());
    device().runOnce([&](VkCommandBuffer cmd) {
        for (uint32_t layer = 0; layer < 4; ++layer) uploader.toImage(cmd, image, texels.data(), texels.size() * 4, layer);
        gpu::transition(cmd, image, gpu::ImageUse::SampledFragment);
    });
    EXPECT_EQ(image.currentUse(), gpu::ImageUse::SampledFragment);
}

TEST_F(GpuCore, RendererReportsGpuTimePerPass) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto scene = buildScene(globeScene(R"({"lon": 0, "lat": 0, "range": 20000000})"), registry);
    ASSERT_TRUE(scene);
    render::Renderer renderer(device(), 128, 96);
    scene->time().advance(0.0);
    const auto frame = renderer.render(*scene, false);
    const auto times = renderer.gpuTimes(frame);
    ASSERT_FALSE(times.empty());
    EXPECT_EQ(times[0].name, "opaque");
    EXPECT_GT(times[0].ms, 0.0);
    EXPECT_LT(times[0].ms, 10000.0);
}

TEST_F(GpuCore, FramesInFlightReuseSlots) {
    scene::LayerRegistry registry;
    layers::registerBuiltinLayers(registry);
    auto scene = buildScene(globeScene(R"({"lon": 0, "lat": 0, "range": 20000000})"), registry);
    ASSERT_TRUE(scene);
    render::Renderer renderer(device(), 64, 64);
    std::vector<uint32_t> slots;
    for (int i = 0; i < 5; ++i) {
        scene->time().advance(1.0 / 60.0);
        slots.push_back(renderer.render(*scene, false).slot);
    }
    EXPECT_EQ(slots, (std::vector<uint32_t>{0, 1, 0, 1, 0}));
}

}  // namespace
}  // namespace orbis::test
