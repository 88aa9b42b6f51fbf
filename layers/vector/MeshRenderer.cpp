#include "layers/vector/MeshRenderer.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "globe/Culling.h"
#include "shared/FrameUniforms.h"

#include "spv/vector/marker.frag.h"
#include "spv/vector/marker.vert.h"
#include "spv/vector/mesh.frag.h"
#include "spv/vector/mesh.vert.h"
#include "spv/vector/segment.frag.h"
#include "spv/vector/segment.vert.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace orbis::layers {
namespace {

constexpr VkShaderStageFlags kPushStages = VK_SHADER_STAGE_VERTEX_BIT;

/// Concatenates one member vector of every chunk into `buffer` (made to fit).
template <typename T, typename Member>
void upload(const render::RecordContext& rc, gpu::Device& device, const vector::FeatureMesh& mesh, Member member,
            VkBufferUsageFlags usage, VkPipelineStageFlags2 stage, VkAccessFlags2 access, const char* name, gpu::Buffer& buffer) {
    size_t count = 0;
    for (const vector::MeshChunk& c : mesh.chunks) count += (c.*member).size();
    buffer = {};
    if (count == 0) return;
    // Room for kSlack more elements, never read: the synchronization validation of the Debian
    // layers (1.3.239) takes an instanced draw of 6 vertices as reading 6 elements of an
    // instance-rate buffer, past the end of a buffer of fewer, and reports the neighbouring
    // allocation's next use as a hazard.
    constexpr size_t kSlack = 6;
    buffer = gpu::Buffer(device, (count + kSlack) * sizeof(T), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly,
                         name);
    VkDeviceSize offset = 0;
    for (const vector::MeshChunk& c : mesh.chunks) {
        const auto& items = c.*member;
        if (items.empty()) continue;
        rc.uploader->toBuffer(rc.cmd, buffer, items.data(), items.size() * sizeof(T), offset);
        offset += items.size() * sizeof(T);
    }
    gpu::bufferBarrier(rc.cmd, buffer, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, stage, access);
}

}  // namespace

static_assert(shader::kMeshSet == shader::kFrameSet + 1, "a layer's own set follows the frame's");

MeshRenderer::MeshRenderer(const render::RenderServices& services, std::shared_ptr<vector::IconCache> icons)
    : services_(services), icons_(std::move(icons)) {
    const VkPushConstantRange push{kPushStages, 0, sizeof(shader::VectorMeshPush)};
    // The markers' icon atlas is the layout's second set (the other kinds do not read it).
    sets_ = gpu::createDescriptorSets(*services.device, shader::kMeshBindings, 1);
    const VkDescriptorSetLayout setLayouts[] = {services.frameSetLayout, sets_.layout.vk()};
    layout_ = gpu::createPipelineLayout(*services.device, setLayouts, {&push, 1});
}

void MeshRenderer::refreshAtlas() {
    if (!atlas_) {
        gpu::ImageDesc image;
        image.format = VK_FORMAT_R8G8B8A8_SRGB;
        image.extent = {kAtlasPx, kAtlasPx, 1};
        image.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        image.name = "vector marker icons";
        atlas_ = gpu::Image(*services_.device, image);
        sampler_ = gpu::createSampler(*services_.device, {.filter = VK_FILTER_LINEAR});
        gpu::DescriptorWriter(sets_.sets[0]).sampledImage(shader::kMeshBindingIcons, sampler_.vk(), atlas_.view()).update(*services_.device);
        atlasPixels_.assign(size_t(kAtlasPx) * kAtlasPx * 4, 0);   // the image starts undefined: clear it
    }
    const auto icons = icons_ ? icons_->byIndex() : std::vector<std::shared_ptr<const ImageRgba8>>{};
    if (icons.size() <= atlasIcons_ && atlasIcons_ > 0) return;
    atlasPixels_.assign(size_t(kAtlasPx) * kAtlasPx * 4, 0);
    constexpr uint32_t cell = shader::kMeshIconCellPx, cells = shader::kMeshIconCells;
    for (size_t i = 0; i < icons.size() && i < size_t(cells) * cells; ++i) {
        const ImageRgba8* icon = icons[i].get();
        if (!icon || icon->width == 0 || icon->height == 0) continue;
        // Fitted into the cell and centred (the marker shader finds it so), sampled bilinearly
        // from the icon, over a box of its pixels when it shrinks.
        const double scale = double(cell) / std::max(icon->width, icon->height);
        const uint32_t w = std::max(1u, uint32_t(std::lround(icon->width * scale))), h = std::max(1u, uint32_t(std::lround(icon->height * scale)));
        const uint32_t x0 = uint32_t(i % cells) * cell + (cell - w) / 2, y0 = uint32_t(i / cells) * cell + (cell - h) / 2;
        const int box = std::max(1, int(std::ceil(1.0 / scale)));
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                uint32_t sum[4] = {0, 0, 0, 0}, n = 0;
                const int sx = int((x + 0.5) / scale - 0.5 * box), sy = int((y + 0.5) / scale - 0.5 * box);
                for (int dy = 0; dy < box; ++dy)
                    for (int dx = 0; dx < box; ++dx) {
                        const int px = std::clamp(sx + dx, 0, int(icon->width) - 1), py = std::clamp(sy + dy, 0, int(icon->height) - 1);
                        const uint8_t* p = &icon->pixels[(size_t(py) * icon->width + size_t(px)) * 4];
                        for (int c = 0; c < 4; ++c) sum[c] += p[c];
                        ++n;
                    }
                uint8_t* out = &atlasPixels_[(size_t(y0 + y) * kAtlasPx + x0 + x) * 4];
                for (int c = 0; c < 4; ++c) out[c] = uint8_t(sum[c] / n);
            }
    }
    atlasIcons_ = std::max<size_t>(icons.size(), 1);
}

void MeshRenderer::setMesh(std::shared_ptr<const vector::FeatureMesh> mesh) {
    gpu::GraphicsPipelineDesc d;
    d.layout = layout_.vk();
    d.colorFormat = services_.colorFormat;
    d.depthFormat = services_.depthFormat;
    bool triangles = false, translucent = false, segments = false, markers = false;
    for (const vector::MeshChunk& c : mesh->chunks) {
        triangles = triangles || !c.indices.empty();
        translucent = translucent || !c.translucent.empty();
        segments = segments || !c.segments.empty();
        markers = markers || !c.markers.empty();
    }
    using shader::VectorMeshVertex;
    if ((triangles && !meshPipeline_) || (translucent && !translucentPipeline_)) {
        d.vertexSpirv = kSpv_vector_mesh_vert;
        d.fragmentSpirv = kSpv_vector_mesh_frag;
        d.bindings = {{0, sizeof(VectorMeshVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
        d.attributes = {
            {shader::kMeshInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorMeshVertex, position)},
            {shader::kMeshInputNormal, 0, VK_FORMAT_R8G8B8A8_SNORM, offsetof(VectorMeshVertex, normal)},
            {shader::kMeshInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(VectorMeshVertex, color)},
            {shader::kMeshInputFeature, 0, VK_FORMAT_R32_UINT, offsetof(VectorMeshVertex, feature)},
        };
        // Solids are closed and wound outwards; a surface at altitude has both faces (FeatureMesh).
        d.cullMode = VK_CULL_MODE_BACK_BIT;
        d.name = "vector meshes";
        if (triangles && !meshPipeline_) meshPipeline_ = gpu::createGraphicsPipeline(*services_.device, d);
        // Translucent surfaces: one face each, seen from either side, blended over what is drawn.
        d.cullMode = VK_CULL_MODE_NONE;
        d.alphaBlend = true;
        d.depthWrite = false;
        d.name = "vector translucent surfaces";
        if (translucent && !translucentPipeline_) translucentPipeline_ = gpu::createGraphicsPipeline(*services_.device, d);
    }
    // Segments and markers: screen quads, blended over what is drawn, hidden by what is nearer.
    d.cullMode = VK_CULL_MODE_NONE;
    d.alphaBlend = true;
    d.depthWrite = false;
    if (segments && !segmentPipeline_) {
        using shader::VectorSegment;
        d.vertexSpirv = kSpv_vector_segment_vert;
        d.fragmentSpirv = kSpv_vector_segment_frag;
        d.bindings = {{0, sizeof(VectorSegment), VK_VERTEX_INPUT_RATE_INSTANCE}};
        d.attributes = {
            {shader::kSegmentInputA, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorSegment, a)},
            {shader::kSegmentInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(VectorSegment, color)},
            {shader::kSegmentInputB, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorSegment, b)},
            {shader::kSegmentInputWidth, 0, VK_FORMAT_R32_SFLOAT, offsetof(VectorSegment, widthPx)},
            {shader::kSegmentInputFeature, 0, VK_FORMAT_R32_UINT, offsetof(VectorSegment, feature)},
            {shader::kSegmentInputStart, 0, VK_FORMAT_R32_SFLOAT, offsetof(VectorSegment, startM)},
            {shader::kSegmentInputDash, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(VectorSegment, dashPx)},
        };
        d.name = "vector segments";
        segmentPipeline_ = gpu::createGraphicsPipeline(*services_.device, d);
    }
    if (markers && !markerPipeline_) {
        using shader::VectorMarker;
        d.vertexSpirv = kSpv_vector_marker_vert;
        d.fragmentSpirv = kSpv_vector_marker_frag;
        d.bindings = {{0, sizeof(VectorMarker), VK_VERTEX_INPUT_RATE_INSTANCE}};
        d.attributes = {
            {shader::kMarkerInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorMarker, position)},
            {shader::kMarkerInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(VectorMarker, color)},
            {shader::kMarkerInputSize, 0, VK_FORMAT_R32_SFLOAT, offsetof(VectorMarker, sizePx)},
            {shader::kMarkerInputFeature, 0, VK_FORMAT_R32_UINT, offsetof(VectorMarker, feature)},
        };
        d.attributes.push_back({shader::kMarkerInputIcon, 0, VK_FORMAT_R32_UINT, offsetof(VectorMarker, icon)});
        d.attributes.push_back({shader::kMarkerInputAspect, 0, VK_FORMAT_R32_SFLOAT, offsetof(VectorMarker, aspect)});
        d.attributes.push_back({shader::kMarkerInputScale, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorMarker, scale)});
        d.attributes.push_back({shader::kMarkerInputFrom, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorMarker, from)});
        d.attributes.push_back({shader::kMarkerInputGlide, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(VectorMarker, glide)});
        d.name = "vector markers";
        markerPipeline_ = gpu::createGraphicsPipeline(*services_.device, d);
    }
    if (markers) refreshAtlas();
    pending_ = std::move(mesh);
}

void MeshRenderer::recordTransfers(const render::RecordContext& rc) {
    if (!atlasPixels_.empty()) {
        rc.uploader->toImage(rc.cmd, atlas_, atlasPixels_.data(), atlasPixels_.size(), 0, {0, 0, 0}, {kAtlasPx, kAtlasPx, 1});
        gpu::transition(rc.cmd, atlas_, gpu::ImageUse::SampledFragment);
        atlasPixels_.clear();
    }
    if (!pending_) return;
    mesh_ = std::move(pending_);
    pending_.reset();
    ranges_.clear();
    Range next;
    for (const vector::MeshChunk& c : mesh_->chunks) {
        Range r{next.firstIndex, uint32_t(c.indices.size()), next.firstTranslucent, uint32_t(c.translucent.size()), next.vertexOffset,
                next.firstSegment, uint32_t(c.segments.size()), next.firstMarker, uint32_t(c.markers.size())};
        ranges_.push_back(r);
        next.firstIndex += r.indexCount;
        next.firstTranslucent += r.translucentCount;
        next.vertexOffset += int32_t(c.vertices.size());
        next.firstSegment += r.segmentCount;
        next.firstMarker += r.markerCount;
    }
    // New buffers each time (the old ones are retired once the frames using them are done).
    gpu::Device& device = *services_.device;
    using vector::MeshChunk;
    upload<shader::VectorMeshVertex>(rc, device, *mesh_, &MeshChunk::vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                     VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT,
                                     "vector mesh vertices", vertices_);
    upload<uint32_t>(rc, device, *mesh_, &MeshChunk::indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT,
                     VK_ACCESS_2_INDEX_READ_BIT, "vector mesh indices", indices_);
    upload<uint32_t>(rc, device, *mesh_, &MeshChunk::translucent, VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                     VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT, "vector translucent indices", translucent_);
    upload<shader::VectorSegment>(rc, device, *mesh_, &MeshChunk::segments, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                  VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT,
                                  "vector segments", segments_);
    upload<shader::VectorMarker>(rc, device, *mesh_, &MeshChunk::markers, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                 VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT, "vector markers",
                                 markers_);
}

void MeshRenderer::record(const render::RecordContext& rc) {
    chunksDrawn_ = 0;
    if (!mesh_ || !rc.frame || !rc.frame->camera) return;
    const scene::Camera& camera = *rc.frame->camera;
    const auto frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), rc.frame->aspect(), camera.nearPlane());
    const glm::dmat3 view(camera.viewRotation());
    const glm::dvec3 eye = camera.position();
    visible_.clear();
    for (size_t i = 0; i < mesh_->chunks.size(); ++i) {
        const vector::MeshChunk& c = mesh_->chunks[i];
        const double range = glm::length(c.center - eye);
        // The style's camera range, taken from the chunk's nearest and farthest points.
        if (range + c.radius < c.minRangeM || range - c.radius > c.maxRangeM) continue;
        if (globe::sphereBelowHorizon(eye, c.center, c.radius)) continue;
        if (!frustum.intersectsSphere(view * (c.center - eye), c.radius)) continue;
        visible_.push_back(uint32_t(i));
    }
    chunksDrawn_ = uint32_t(visible_.size());
    if (visible_.empty()) return;

    const VkCommandBuffer cmd = rc.cmd;
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);
    shader::VectorMeshPush push{};
    push.highlight = highlight_;
    const VkDeviceSize zero = 0;
    // One kind at a time over the visible chunks: the triangles, then the segments, then the markers.
    const auto each = [&](const gpu::Pipeline& pipeline, const gpu::Buffer& buffer, auto draw) {
        if (!pipeline || !buffer) return;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.vk());
        const VkBuffer vb = buffer.vk();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
        for (const uint32_t i : visible_) {
            const Range& r = ranges_[i];
            push.originFromEye = glm::vec3(mesh_->chunks[i].origin - eye);   // double: large minus large
            const double epoch = mesh_->chunks[i].glideEpoch;
            push.glideNow = epoch > 0.0 ? float(glideClock_ - epoch) : 0.0f;
            if (!draw(r, /*check*/ true)) continue;
            vkCmdPushConstants(cmd, layout_.vk(), kPushStages, 0, sizeof(push), &push);
            draw(r, false);
        }
    };
    if (indices_) {
        vkCmdBindIndexBuffer(cmd, indices_.vk(), 0, VK_INDEX_TYPE_UINT32);
        each(meshPipeline_, vertices_, [&](const Range& r, bool check) {
            if (check) return r.indexCount > 0;
            vkCmdDrawIndexed(cmd, r.indexCount, 1, r.firstIndex, r.vertexOffset, 0);
            return true;
        });
    }
    if (translucent_) {
        vkCmdBindIndexBuffer(cmd, translucent_.vk(), 0, VK_INDEX_TYPE_UINT32);
        each(translucentPipeline_, vertices_, [&](const Range& r, bool check) {
            if (check) return r.translucentCount > 0;
            vkCmdDrawIndexed(cmd, r.translucentCount, 1, r.firstTranslucent, r.vertexOffset, 0);
            return true;
        });
    }
    each(segmentPipeline_, segments_, [&](const Range& r, bool check) {
        if (check) return r.segmentCount > 0;
        vkCmdDraw(cmd, 6, r.segmentCount, 0, r.firstSegment);
        return true;
    });
    if (markerPipeline_ && markers_) vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kMeshSet, 1, &sets_.sets[0], 0, nullptr);
    each(markerPipeline_, markers_, [&](const Range& r, bool check) {
        if (check) return r.markerCount > 0;
        vkCmdDraw(cmd, 6, r.markerCount, 0, r.firstMarker);
        return true;
    });
}

}  // namespace orbis::layers
