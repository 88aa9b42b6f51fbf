#include "layers/vector/LabelRenderer.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "layers/vector/GlyphAtlas.h"
#include "shared/FrameUniforms.h"

#include "spv/vector/label.frag.h"
#include "spv/vector/label.vert.h"

#include <algorithm>
#include <cstddef>

namespace orbis::layers {
namespace {

/// The first instance buffer holds this many glyphs (some 400 labels); it doubles as needed.
constexpr VkDeviceSize kFirstGlyphs = 4096;
static_assert(shader::kLabelSet == shader::kFrameSet + 1, "a layer's own set follows the frame's");

}  // namespace

LabelRenderer::LabelRenderer(const render::RenderServices& services, int atlasWidth, int atlasHeight)
    : device_(services.device) {
    gpu::Device& device = *services.device;
    gpu::ImageDesc image;
    image.format = VK_FORMAT_R8_UNORM;
    image.extent = {uint32_t(atlasWidth), uint32_t(atlasHeight), 1};
    image.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    image.name = "vector label glyph atlas";
    atlas_ = gpu::Image(device, image);
    sampler_ = gpu::createSampler(device, {.filter = VK_FILTER_LINEAR});
    // One set: the atlas image never changes (a cleared atlas is uploaded again in place).
    sets_ = gpu::createDescriptorSets(device, shader::kLabelBindings, 1);
    gpu::DescriptorWriter(sets_.sets[0]).sampledImage(shader::kLabelBindingAtlas, sampler_.vk(), atlas_.view()).update(device);
    for (uint32_t i = 0; i < services.framesInFlight; ++i)
        instances_.emplace_back(device, kFirstGlyphs * sizeof(shader::LabelGlyph), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                gpu::MemoryUsage::Upload, "vector label glyphs");

    const VkDescriptorSetLayout setLayouts[] = {services.frameSetLayout, sets_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, setLayouts, {});
    gpu::GraphicsPipelineDesc d;
    d.vertexSpirv = kSpv_vector_label_vert;
    d.fragmentSpirv = kSpv_vector_label_frag;
    d.layout = layout_.vk();
    d.bindings = {{0, sizeof(shader::LabelGlyph), VK_VERTEX_INPUT_RATE_INSTANCE}};
    using shader::LabelGlyph;
    d.attributes = {
        {shader::kLabelInputOrigin, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(LabelGlyph, origin)},
        {shader::kLabelInputAxisX, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(LabelGlyph, axisX)},
        {shader::kLabelInputAxisY, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(LabelGlyph, axisY)},
        {shader::kLabelInputUv, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(LabelGlyph, uv)},
        {shader::kLabelInputEdges, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(LabelGlyph, edges)},
        {shader::kLabelInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(LabelGlyph, color)},
        {shader::kLabelInputHalo, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(LabelGlyph, halo)},
    };
    d.cullMode = VK_CULL_MODE_NONE;   // the quads wind as the pixel axes (y down) make them
    d.alphaBlend = true;
    d.depthTest = false;
    d.depthWrite = false;
    d.colorFormat = services.colorFormat;
    d.depthFormat = services.depthFormat;
    for (const bool halo : {true, false}) {
        gpu::Specialization spec;
        spec.set<VkBool32>(shader::kLabelSpecHalo, halo ? VK_TRUE : VK_FALSE);
        d.specialization = &spec;
        d.name = halo ? "vector label halos" : "vector label text";
        (halo ? halos_ : text_) = gpu::createGraphicsPipeline(device, d);
    }
}

void LabelRenderer::recordTransfers(const render::RecordContext& rc, vector::GlyphAtlas& atlas,
                                    std::span<const shader::LabelGlyph> glyphs) {
    vector::AtlasRect dirty = atlas.dirty();
    if (!atlasUploaded_) dirty = {0, 0, atlas.width(), atlas.height()};   // the image starts undefined
    if (!dirty.empty()) {
        // The rectangle's rows, packed: the staging copy takes a tight region.
        staging_.resize(size_t(dirty.width) * size_t(dirty.height));
        const auto pixels = atlas.pixels();
        for (int y = 0; y < dirty.height; ++y)
            std::copy_n(pixels.begin() + ptrdiff_t(size_t(dirty.y + y) * size_t(atlas.width()) + size_t(dirty.x)), dirty.width,
                        staging_.begin() + ptrdiff_t(size_t(y) * size_t(dirty.width)));
        rc.uploader->toImage(rc.cmd, atlas_, staging_.data(), staging_.size(), 0, {dirty.x, dirty.y, 0},
                             {uint32_t(dirty.width), uint32_t(dirty.height), 1});
        gpu::transition(rc.cmd, atlas_, gpu::ImageUse::SampledFragment);
        atlas.clearDirty();
        atlasUploaded_ = true;
    }
    glyphCount_ = uint32_t(glyphs.size());
    if (glyphs.empty()) return;
    gpu::Buffer& buffer = instances_[rc.slot];
    const VkDeviceSize bytes = glyphs.size_bytes();
    if (buffer.size() < bytes) {
        VkDeviceSize size = buffer.size();
        while (size < bytes) size *= 2;
        buffer = gpu::Buffer(*device_, size, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::Upload, "vector label glyphs");
    }
    buffer.write(glyphs.data(), bytes);
}

void LabelRenderer::record(const render::RecordContext& rc) {
    if (glyphCount_ == 0 || !atlasUploaded_) return;
    const VkDescriptorSet sets[] = {rc.frameSet, sets_.sets[0]};
    vkCmdBindDescriptorSets(rc.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 0, nullptr);
    const VkBuffer buffer = instances_[rc.slot].vk();
    const VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(rc.cmd, 0, 1, &buffer, &zero);
    // Every halo before any text: a glyph's halo must not cover its neighbour's stroke.
    for (const gpu::Pipeline* pipeline : {&halos_, &text_}) {
        vkCmdBindPipeline(rc.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline->vk());
        vkCmdDraw(rc.cmd, 6, glyphCount_, 0, 0);
    }
}

uint64_t LabelRenderer::gpuBytes() const {
    uint64_t bytes = uint64_t(atlas_.extent().width) * atlas_.extent().height;
    for (const gpu::Buffer& b : instances_) bytes += b.size();
    return bytes;
}

}  // namespace orbis::layers
