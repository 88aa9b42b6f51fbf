#include "layers/vector/MeshRenderer.h"

#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "globe/Culling.h"
#include "shared/FrameUniforms.h"

#include "spv/vector/mesh.frag.h"
#include "spv/vector/mesh.vert.h"

#include <cstddef>

namespace orbis::layers {

MeshRenderer::MeshRenderer(const render::RenderServices& services) : device_(services.device) {
    gpu::Device& device = *services.device;
    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(shader::VectorMeshPush)};
    const VkDescriptorSetLayout setLayouts[] = {services.frameSetLayout};
    layout_ = gpu::createPipelineLayout(device, setLayouts, {&push, 1});
    gpu::GraphicsPipelineDesc d;
    d.vertexSpirv = kSpv_vector_mesh_vert;
    d.fragmentSpirv = kSpv_vector_mesh_frag;
    d.layout = layout_.vk();
    using shader::VectorMeshVertex;
    d.bindings = {{0, sizeof(VectorMeshVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.attributes = {
        {shader::kMeshInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(VectorMeshVertex, position)},
        {shader::kMeshInputNormal, 0, VK_FORMAT_R8G8B8A8_SNORM, offsetof(VectorMeshVertex, normal)},
        {shader::kMeshInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(VectorMeshVertex, color)},
        {shader::kMeshInputFeature, 0, VK_FORMAT_R32_UINT, offsetof(VectorMeshVertex, feature)},
    };
    // Solids are closed and wound outwards; a surface at altitude has both faces (FeatureMesh).
    d.cullMode = VK_CULL_MODE_BACK_BIT;
    d.colorFormat = services.colorFormat;
    d.depthFormat = services.depthFormat;
    d.name = "vector meshes";
    pipeline_ = gpu::createGraphicsPipeline(device, d);
}

void MeshRenderer::setMesh(std::shared_ptr<const vector::FeatureMesh> mesh) { pending_ = std::move(mesh); }

void MeshRenderer::recordTransfers(const render::RecordContext& rc) {
    if (!pending_) return;
    mesh_ = std::move(pending_);
    pending_.reset();
    ranges_.clear();
    size_t vertexCount = 0, indexCount = 0;
    for (const vector::MeshChunk& c : mesh_->chunks) {
        ranges_.push_back({uint32_t(indexCount), uint32_t(c.indices.size()), int32_t(vertexCount)});
        vertexCount += c.vertices.size();
        indexCount += c.indices.size();
    }
    const VkDeviceSize vbytes = vertexCount * sizeof(shader::VectorMeshVertex), ibytes = indexCount * sizeof(uint32_t);
    if (vbytes == 0 || ibytes == 0) return;
    // New buffers each time (the old ones are retired once the frames using them are done).
    vertices_ = gpu::Buffer(*device_, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            gpu::MemoryUsage::GpuOnly, "vector mesh vertices");
    indices_ = gpu::Buffer(*device_, ibytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           gpu::MemoryUsage::GpuOnly, "vector mesh indices");
    for (size_t i = 0; i < mesh_->chunks.size(); ++i) {
        const vector::MeshChunk& c = mesh_->chunks[i];
        rc.uploader->toBuffer(rc.cmd, vertices_, c.vertices.data(), c.vertices.size() * sizeof(shader::VectorMeshVertex),
                              VkDeviceSize(ranges_[i].vertexOffset) * sizeof(shader::VectorMeshVertex));
        rc.uploader->toBuffer(rc.cmd, indices_, c.indices.data(), c.indices.size() * sizeof(uint32_t),
                              VkDeviceSize(ranges_[i].firstIndex) * sizeof(uint32_t));
    }
    gpu::bufferBarrier(rc.cmd, vertices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
    gpu::bufferBarrier(rc.cmd, indices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT);
}

void MeshRenderer::record(const render::RecordContext& rc) {
    chunksDrawn_ = 0;
    if (!mesh_ || !vertices_ || !rc.frame || !rc.frame->camera) return;
    const scene::Camera& camera = *rc.frame->camera;
    const VkCommandBuffer cmd = rc.cmd;
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.vk());
    const VkDeviceSize zero = 0;
    const VkBuffer vb = vertices_.vk();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
    vkCmdBindIndexBuffer(cmd, indices_.vk(), 0, VK_INDEX_TYPE_UINT32);
    const auto frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), rc.frame->aspect(), camera.nearPlane());
    const glm::dmat3 view(camera.viewRotation());
    const glm::dvec3 eye = camera.position();
    shader::VectorMeshPush push{};
    push.highlight = highlight_;
    for (size_t i = 0; i < mesh_->chunks.size(); ++i) {
        const vector::MeshChunk& c = mesh_->chunks[i];
        const double range = glm::length(c.center - eye);
        // The style's camera range, taken from the chunk's nearest and farthest points.
        if (range + c.radius < c.minRangeM || range - c.radius > c.maxRangeM) continue;
        if (globe::sphereBelowHorizon(eye, c.center, c.radius)) continue;
        if (!frustum.intersectsSphere(view * (c.center - eye), c.radius)) continue;
        push.originFromEye = glm::vec3(c.origin - eye);   // double: large minus large
        vkCmdPushConstants(cmd, layout_.vk(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
        vkCmdDrawIndexed(cmd, ranges_[i].indexCount, 1, ranges_[i].firstIndex, ranges_[i].vertexOffset, 0);
        ++chunksDrawn_;
    }
}

}  // namespace orbis::layers
