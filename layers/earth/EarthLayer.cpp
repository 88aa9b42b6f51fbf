#include "layers/earth/EarthLayer.h"

#include "base/Color.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "engine/render/SkyPipeline.h"
#include "engine/scene/JsonReader.h"
#include "globe/Culling.h"
#include "shared/EarthTypes.h"
#include "shared/FrameUniforms.h"

#include "spv/earth/ellipsoid.frag.h"
#include "spv/earth/ellipsoid.vert.h"

#include <cmath>

namespace orbis::layers {
Result<std::unique_ptr<scene::Layer>> EarthLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    EarthSettings s;
    s.graticuleDeg = r.number("graticuleDeg", s.graticuleDeg, 0.0, 90.0).value_or(s.graticuleDeg);
    if (auto c = r.numbers("color", 3, std::vector<double>{s.color.r, s.color.g, s.color.b})) {
        for (double v : *c)
            if (v < 0.0 || v > 1.0) r.fail("color", "colour components must be in [0, 1]");
        if (c->size() == 3) s.color = {(*c)[0], (*c)[1], (*c)[2]};
    }
    s.sky = r.boolean("sky", s.sky).value_or(s.sky);
    if (auto lighting = r.string("lighting", std::string("sun"))) {
        if (*lighting == "sun") s.sunLighting = true;
        else if (*lighting == "headlight") s.sunLighting = false;
        else r.fail("lighting", "expected \"sun\" or \"headlight\", got \"" + *lighting + "\"");
    }
    s.patchDeg = r.number("patchDeg", s.patchDeg, 1.0, 90.0).value_or(s.patchDeg);
    const double patches = 180.0 / s.patchDeg;
    if (std::abs(patches - std::round(patches)) > 1e-9) r.fail("patchDeg", "must divide 180 (e.g. 5, 10, 15, 30)");
    s.segments = static_cast<int>(r.number("segments", s.segments, 1.0, 256.0).value_or(s.segments));
    if (auto done = r.finish(); !done) return done.error();
    return std::unique_ptr<scene::Layer>(new EarthLayer(s));
}

void EarthLayer::onPrepare(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    mesh_ = EarthMesh::build(settings_.patchDeg, settings_.segments);
    const VkDeviceSize vbytes = mesh_.vertices.size() * sizeof(EarthVertex);
    const VkDeviceSize ibytes = mesh_.indices.size() * sizeof(uint32_t);
    vertices_ = gpu::Buffer(device, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            gpu::MemoryUsage::GpuOnly, "globe vertices");
    indices_ = gpu::Buffer(device, ibytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           gpu::MemoryUsage::GpuOnly, "globe indices");
    device.runOnce([&](VkCommandBuffer cmd) {
        services.uploader->toBuffer(cmd, vertices_, mesh_.vertices.data(), vbytes);
        services.uploader->toBuffer(cmd, indices_, mesh_.indices.data(), ibytes);
        for (const gpu::Buffer* b : {&vertices_, &indices_})
            gpu::bufferBarrier(cmd, *b, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT,
                               VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT);
    });
    mesh_.vertices = {};   // on the GPU now; keep the patch table for culling

    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                   sizeof(shader::EarthPush)};
    const VkDescriptorSetLayout sets[] = {services.frameSetLayout};
    layout_ = gpu::createPipelineLayout(device, sets, {&push, 1});

    gpu::GraphicsPipelineDesc surface;
    surface.vertexSpirv = kSpv_earth_ellipsoid_vert;
    surface.fragmentSpirv = kSpv_earth_ellipsoid_frag;
    surface.layout = layout_.vk();
    surface.bindings = {{0, sizeof(EarthVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    surface.attributes = {{shader::kEarthInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(EarthVertex, position)},
                          {shader::kEarthInputNormal, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(EarthVertex, normal)},
                          {shader::kEarthInputLonLat, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(EarthVertex, lonLatDeg)}};
    surface.colorFormat = services.colorFormat;
    surface.depthFormat = services.depthFormat;
    surface.name = "globe surface";
    surface_ = gpu::createGraphicsPipeline(device, surface);

    if (settings_.sky) sky_ = render::createSkyPipeline(device, layout_.vk(), services, "globe sky");
}

void EarthLayer::record(scene::Pass, const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    const scene::Camera& camera = *rc.frame->camera;
    const double aspect = rc.frame->aspect();
    const glm::dmat4 proj = camera.projection(aspect);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);

    shader::EarthPush push{};
    push.graticuleDeg = float(settings_.graticuleDeg);
    push.lineHalfWidthPx = 0.75f;
    push.drawLines = settings_.graticuleDeg > 0.0 ? 1u : 0u;
    push.sunLighting = settings_.sunLighting ? 1u : 0u;
    push.baseColor = glm::vec3(srgbToLinear(settings_.color.r), srgbToLinear(settings_.color.g), srgbToLinear(settings_.color.b));
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_.vk());
    const VkDeviceSize offset = 0;
    const VkBuffer vb = vertices_.vk();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(cmd, indices_.vk(), 0, VK_INDEX_TYPE_UINT32);

    const auto frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), aspect, camera.nearPlane());
    const glm::dmat4 view = camera.viewRotation();
    patchesDrawn_ = 0;
    for (size_t i = 0; i < mesh_.patches.size(); ++i) {
        const EarthPatch& patch = mesh_.patches[i];
        const glm::dvec3 rel = patch.origin - camera.position();   // double: large minus large
        if (globe::sphereBelowHorizon(camera.position(), patch.origin, patch.radius)) continue;
        if (!frustum.intersectsSphere(glm::dmat3(view) * rel, patch.radius)) continue;
        push.modelViewProj = glm::mat4(proj * camera.modelViewRelativeToEye(patch.origin));
        push.originFromEye = glm::vec3(rel);
        vkCmdPushConstants(cmd, layout_.vk(), stages, 0, sizeof(push), &push);
        vkCmdDrawIndexed(cmd, uint32_t(mesh_.indices.size()), 1, 0, int32_t(i * mesh_.verticesPerPatch()), 0);
        ++patchesDrawn_;
    }
    if (sky_) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sky_.vk());
        vkCmdPushConstants(cmd, layout_.vk(), stages, 0, sizeof(push), &push);
        vkCmdDraw(cmd, 3, 1, 0, 0);
    }
}

uint64_t EarthLayer::gpuBytes() const { return vertices_.size() + indices_.size(); }

scene::LayerType EarthLayer::layerType() {
    return {"globe", "WGS84 ellipsoid with graticule, sun lighting and sky", &EarthLayer::create, {}};
}

}  // namespace orbis::layers
