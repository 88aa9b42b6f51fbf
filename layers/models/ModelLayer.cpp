#include "layers/models/ModelLayer.h"

#include "base/Color.h"
#include "base/LabelText.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/gpu/VkCheck.h"
#include "engine/render/RenderContext.h"
#include "formats/motion/Attitude.h"
#include "globe/Culling.h"
#include "globe/Ellipsoid.h"
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"
#include "shared/PolylineTypes.h"

#include "spv/common/polyline.frag.h"
#include "spv/common/polyline.vert.h"
#include "spv/models/model.frag.h"
#include "spv/models/model.vert.h"
#include "spv/models/model_animated.vert.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace orbis::layers {

// The pipeline layouts list the sets in order: the frame's, then the layer's.
static_assert(shader::kModelSet == shader::kFrameSet + 1 && shader::kModelMaterialSet == shader::kModelSet + 1);

namespace {

constexpr uint32_t kLabelMaxVertices = 6 * 2048;

glm::vec4 linearColor(const glm::dvec3& srgb, double alpha) {
    return glm::vec4(float(srgbToLinear(srgb.r)), float(srgbToLinear(srgb.g)), float(srgbToLinear(srgb.b)), float(alpha));
}

template <typename T>
void append(std::vector<std::byte>& out, const T& value) {
    const auto* p = reinterpret_cast<const std::byte*>(&value);
    out.insert(out.end(), p, p + sizeof(T));
}

}  // namespace

ModelLayer::ModelLayer(ModelSettings settings, models::ModelData model, std::unique_ptr<models::ModelMotion> motion)
    : settings_(std::move(settings)), model_(std::move(model)), motion_(std::move(motion)) {
    const glm::dvec3& o = settings_.orientationDeg;
    modelToBody_ = glm::mat3_cast(motion::bodyToNed(o.x, o.y, o.z)) * models::gltfToBody();
    maxCopies_ = std::max(1u, settings_.copies);
    motion_->setFootprint(footprint());
    if (model_.animated()) {
        poser_.emplace(model_, settings_.animation.animation);
        const uint64_t blockBytes = uint64_t(poser_->layout().vec4s) * sizeof(glm::vec4);
        // A model that does not move in time has one pose for every copy.
        poseCapacity_ = !poser_->moves() ? 1u : uint32_t(std::clamp<uint64_t>(kMaxPoseBytes / blockBytes, 1, maxCopies_));
        poseData_.reserve(size_t(poseCapacity_) * poser_->layout().vec4s);
        poseOfTime_.reserve(poseCapacity_);
    }
}

ModelLayer::~ModelLayer() = default;

bool ModelLayer::drawsIn(scene::Pass pass) const {
    return pass == scene::Pass::Opaque || (pass == scene::Pass::Overlay && settings_.label);
}

void ModelLayer::onPrepare(const render::RenderServices& services) {
    uploadModel(services);
    createFrameSets(services);
    createMaterialSets(*services.device);
    buildPipelines(services);
    if (settings_.path.show || settings_.label) buildLinePipelines(services);
}

void ModelLayer::uploadModel(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const VkDeviceSize vbytes = model_.vertices.size() * sizeof(models::ModelVertex);
    const VkDeviceSize ibytes = model_.indices.size() * sizeof(uint32_t);
    std::vector<shader::ModelNode> nodes(model_.draws.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
        nodes[i].transform = model_.draws[i].transform;
        nodes[i].normal = glm::mat4(glm::transpose(glm::inverse(glm::mat3(model_.draws[i].transform))));
    }
    if (model_.animated()) nodes.resize(1);   // unused: the poses hold the node matrices
    const VkDeviceSize nbytes = nodes.size() * sizeof(shader::ModelNode);
    vertices_ = gpu::Buffer(device, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            gpu::MemoryUsage::GpuOnly, "model vertices");
    indices_ = gpu::Buffer(device, ibytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           gpu::MemoryUsage::GpuOnly, "model indices");
    nodes_ = gpu::Buffer(device, nbytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         gpu::MemoryUsage::GpuOnly, "model nodes");
    gpuBytes_ = vbytes + ibytes + nbytes;
    // Animated models: the joints/weights stream (one zero element read at stride 0 when nothing
    // is skinned) and the morph deltas (a dummy float when nothing morphs).
    std::vector<models::ModelSkinVertex> noSkin(1, models::ModelSkinVertex{});
    std::vector<float> noMorph(4, 0.0f);
    const auto& skin = model_.rig.skinVertices.empty() ? noSkin : model_.rig.skinVertices;
    const auto& morph = model_.rig.morphDeltas.empty() ? noMorph : model_.rig.morphDeltas;
    const VkDeviceSize sbytes = skin.size() * sizeof(models::ModelSkinVertex), mbytes = morph.size() * sizeof(float);
    if (model_.animated()) {
        skinVertices_ = gpu::Buffer(device, sbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    gpu::MemoryUsage::GpuOnly, "model skin vertices");
        morphDeltas_ = gpu::Buffer(device, mbytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   gpu::MemoryUsage::GpuOnly, "model morph deltas");
        gpuBytes_ += sbytes + mbytes;
    }
    device.runOnce([&](VkCommandBuffer cmd) {
        services.uploader->toBuffer(cmd, vertices_, model_.vertices.data(), vbytes);
        services.uploader->toBuffer(cmd, indices_, model_.indices.data(), ibytes);
        services.uploader->toBuffer(cmd, nodes_, nodes.data(), nbytes);
        if (model_.animated()) {
            services.uploader->toBuffer(cmd, skinVertices_, skin.data(), sbytes);
            services.uploader->toBuffer(cmd, morphDeltas_, morph.data(), mbytes);
            gpu::bufferBarrier(cmd, skinVertices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
            gpu::bufferBarrier(cmd, morphDeltas_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
        }
        gpu::bufferBarrier(cmd, vertices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
        gpu::bufferBarrier(cmd, indices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT);
        gpu::bufferBarrier(cmd, nodes_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    });
    uploadTextures(services);
    // On the GPU now; keep the draw list and materials (and the bounds) for recording.
    model_.vertices = {};
    model_.indices = {};
    model_.rig.skinVertices = {};
    model_.rig.morphDeltas = {};
    for (auto& t : model_.textures) t.mips = {};
}

void ModelLayer::uploadTextures(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    // Textures: the model's, then one white texel for untextured materials.
    std::vector<const models::ModelTexture*> sources;
    for (const auto& t : model_.textures) sources.push_back(&t);
    models::ModelTexture white;
    white.width = white.height = 1;
    white.mips = {std::vector<uint8_t>{255, 255, 255, 255}};
    sources.push_back(&white);
    textures_.resize(sources.size());
    for (size_t i = 0; i < sources.size(); ++i) {
        gpu::ImageDesc d;
        d.format = VK_FORMAT_R8G8B8A8_SRGB;
        d.extent = {sources[i]->width, sources[i]->height, 1};
        d.mipLevels = uint32_t(sources[i]->mips.size());
        d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        d.name = "model texture";
        textures_[i].image = gpu::Image(device, d);
    }

    device.runOnce([&](VkCommandBuffer cmd) {
        for (size_t i = 0; i < sources.size(); ++i) {
            const models::ModelTexture& t = *sources[i];
            std::vector<uint8_t> blob;
            std::vector<VkBufferImageCopy> regions;
            for (uint32_t level = 0; level < t.mips.size(); ++level) {
                VkBufferImageCopy r{};
                r.bufferOffset = blob.size();
                r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
                r.imageExtent = {std::max(1u, t.width >> level), std::max(1u, t.height >> level), 1};
                regions.push_back(r);
                blob.insert(blob.end(), t.mips[level].begin(), t.mips[level].end());
            }
            services.uploader->toImageRegions(cmd, textures_[i].image, blob.data(), blob.size(), regions);
            gpu::transition(cmd, textures_[i].image, gpu::ImageUse::SampledFragment);
            gpuBytes_ += blob.size();
        }
    });
}

void ModelLayer::createFrameSets(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const uint32_t frames = services.framesInFlight;
    // Static models: instances and node matrices; animated ones: instances, poses, morph deltas.
    const bool animated = model_.animated();
    frameSets_ = animated ? gpu::createDescriptorSets(device, shader::kModelAnimatedBindings, frames)
                          : gpu::createDescriptorSets(device, shader::kModelStaticBindings, frames);
    for (uint32_t f = 0; f < frames; ++f) {
        instanceBuffers_.emplace_back(device, uint64_t(maxCopies_) * sizeof(shader::ModelInstance),
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Upload, "model instances");
        gpuBytes_ += instanceBuffers_.back().size();
        gpu::DescriptorWriter w(frameSets_.sets[f]);
        w.storageBuffer(shader::kModelBindingInstances, instanceBuffers_[f]);
        if (animated) {
            poseBuffers_.emplace_back(device, uint64_t(poseCapacity_) * poser_->layout().vec4s * sizeof(glm::vec4),
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Upload, "model poses");
            gpuBytes_ += poseBuffers_.back().size();
            w.storageBuffer(shader::kModelBindingPoses, poseBuffers_[f]).storageBuffer(shader::kModelBindingMorphDeltas, morphDeltas_);
        } else {
            w.storageBuffer(shader::kModelBindingNodes, nodes_);
        }
        w.update(device);
        if (settings_.path.show) {
            pathBuffers_.emplace_back(device, uint64_t(settings_.path.maxPoints) * sizeof(shader::PolylineVertex),
                                      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::Upload, "model path");
            gpuBytes_ += pathBuffers_.back().size();
        }
        if (settings_.label) {
            labelBuffers_.emplace_back(device, uint64_t(kLabelMaxVertices) * sizeof(shader::PolylineVertex),
                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryUsage::Upload, "model label");
            gpuBytes_ += labelBuffers_.back().size();
        }
    }
}

void ModelLayer::createMaterialSets(gpu::Device& device) {
    // Trilinear samplers, one for each wrap (u, v) the textures ask for; the white texture clamps.
    const auto address = [](models::TextureWrap w) {
        return w == models::TextureWrap::Clamp ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
               : w == models::TextureWrap::Mirror ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                          : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    };
    materialSets_ = gpu::createDescriptorSets(device, shader::kModelMaterialBindings, uint32_t(textures_.size()));
    for (size_t i = 0; i < textures_.size(); ++i) {
        models::ModelTexture wrap;   // the white texture: clamped
        wrap.wrapU = wrap.wrapV = models::TextureWrap::Clamp;
        const models::ModelTexture& t = i < model_.textures.size() ? model_.textures[i] : wrap;
        const uint32_t key = uint32_t(t.wrapU) | uint32_t(t.wrapV) << 2;
        auto it = samplers_.find(key);
        if (it == samplers_.end())
            it = samplers_.emplace(key, gpu::createSampler(device, {.address = address(t.wrapU),
                                                                    .addressV = address(t.wrapV),
                                                                    .mipmaps = true})).first;
        textures_[i].set = materialSets_.sets[i];
        gpu::DescriptorWriter(textures_[i].set)
            .sampledImage(shader::kModelBindingBaseColor, it->second.vk(), textures_[i].image.view())
            .update(device);
    }
}

void ModelLayer::buildPipelines(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const bool animated = model_.animated();
    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(shader::ModelPush)};
    const VkDescriptorSetLayout sets[] = {services.frameSetLayout, frameSets_.layout.vk(), materialSets_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, sets, {&push, 1});

    gpu::GraphicsPipelineDesc d;
    d.vertexSpirv = animated ? std::span<const uint32_t>(kSpv_models_model_animated_vert) : std::span<const uint32_t>(kSpv_models_model_vert);
    d.fragmentSpirv = kSpv_models_model_frag;
    d.layout = layout_.vk();
    d.bindings = {{0, sizeof(models::ModelVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.attributes = {{shader::kModelInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(models::ModelVertex, position)},
                    {shader::kModelInputNormal, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(models::ModelVertex, normal)},
                    {shader::kModelInputUv, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(models::ModelVertex, uv)},
                    {shader::kModelInputColor, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(models::ModelVertex, color)}};
    if (animated) {
        // Stride 0 when nothing is skinned: every vertex reads the one zero element.
        const uint32_t stride = model_.primitives.empty() || !std::any_of(model_.draws.begin(), model_.draws.end(),
                                                                            [](const models::ModelDraw& m) { return m.skin >= 0; })
                                    ? 0u
                                    : uint32_t(sizeof(models::ModelSkinVertex));
        d.bindings.push_back({1, stride, VK_VERTEX_INPUT_RATE_VERTEX});
        d.attributes.push_back({shader::kModelInputJoints, 1, VK_FORMAT_R16G16B16A16_UINT, offsetof(models::ModelSkinVertex, joints)});
        d.attributes.push_back({shader::kModelInputWeights, 1, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(models::ModelSkinVertex, weights)});
    }
    // Both faces: double-sided materials and mirrored nodes need them, and a closed mesh loses
    // its back faces to the depth test anyway.
    d.cullMode = VK_CULL_MODE_NONE;
    d.colorFormat = services.colorFormat;
    d.depthFormat = services.depthFormat;
    d.name = "model opaque";
    opaque_ = gpu::createGraphicsPipeline(device, d);
    const bool anyBlend = std::any_of(model_.materials.begin(), model_.materials.end(),
                                      [](const models::ModelMaterial& m) { return m.alphaMode == models::AlphaMode::Blend; });
    d.alphaBlend = true;
    d.depthWrite = false;
    d.name = "model blend";
    blendDesc_ = d;
    device_ = &device;
    // Only models with BLEND materials, or drawn translucent, build the blending pipeline.
    if (anyBlend) blend_ = gpu::createGraphicsPipeline(device, d);
    if (settings_.opacity < 1.0) buildTranslucentPipelines();
}

void ModelLayer::buildLinePipelines(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const VkDescriptorSetLayout lineSets[] = {services.frameSetLayout};
    lineLayout_ = gpu::createPipelineLayout(device, lineSets, {});
    gpu::GraphicsPipelineDesc l;
    l.vertexSpirv = kSpv_common_polyline_vert;
    l.fragmentSpirv = kSpv_common_polyline_frag;
    l.layout = lineLayout_.vk();
    l.bindings = {{0, sizeof(shader::PolylineVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    l.attributes = {{shader::kPolylineInputPosition, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(shader::PolylineVertex, position)},
                    {shader::kPolylineInputColor, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(shader::PolylineVertex, color)}};
    l.cullMode = VK_CULL_MODE_NONE;
    l.alphaBlend = true;
    l.depthWrite = false;
    l.colorFormat = services.colorFormat;
    l.depthFormat = services.depthFormat;
    if (settings_.path.show) {
        l.topology = VK_PRIMITIVE_TOPOLOGY_LINE_STRIP;
        l.name = "model path";
        path_ = gpu::createGraphicsPipeline(device, l);
    }
    if (settings_.label) {
        gpu::Specialization screen;
        screen.set<VkBool32>(shader::kPolylineSpecScreen, VK_TRUE);
        l.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        l.depthTest = false;
        l.specialization = &screen;
        l.name = "model label";
        label_ = gpu::createGraphicsPipeline(device, l);
    }
}

glm::dmat4 ModelLayer::modelToEcef(const scene::TrackedPose& pose, double scale) const {
    const glm::dmat3 r = glm::mat3_cast(pose.bodyToEcef) * modelToBody_ * scale;
    glm::dmat4 m(r);
    m[3] = glm::dvec4(pose.position, 1.0);
    return m;
}

motion::Footprint ModelLayer::footprint() const {
    // The bounding box's corners on the body axes (x forward, y right), at the layer's scale.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? model_.boundsMax.x : model_.boundsMin.x, (c & 2) ? model_.boundsMax.y : model_.boundsMin.y,
                                (c & 4) ? model_.boundsMax.z : model_.boundsMin.z);
        const glm::dvec3 body = modelToBody_ * corner * settings_.scale;
        lo = glm::min(lo, body);
        hi = glm::max(hi, body);
    }
    return {0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y)};
}

void ModelLayer::poll() { motion_->update(); }

void ModelLayer::buildTranslucentPipelines() {
    if (!blendDesc_ || !device_) return;
    if (!blend_) blend_ = gpu::createGraphicsPipeline(*device_, *blendDesc_);
    if (!depthOnly_) {
        gpu::GraphicsPipelineDesc d = *blendDesc_;
        d.alphaBlend = false;
        d.colorWrite = false;
        d.depthWrite = true;
        d.name = "model depth";
        depthOnly_ = gpu::createGraphicsPipeline(*device_, d);
    }
}

void ModelLayer::update(const scene::FrameContext& frame) {
    if (settings_.opacity < 1.0 && (!blend_ || !depthOnly_)) buildTranslucentPipelines();
    const scene::Camera& camera = *frame.camera;
    eye_ = camera.position();
    const models::GroundFn& ground = frame.groundHeight;
    const double aspect = frame.aspect();
    const auto frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), aspect, camera.nearPlane());
    const glm::dmat3 view(camera.viewRotation());
    const double pixelsPerRadian = double(frame.height) / camera.verticalFovRad();
    const glm::dvec3 centerModel = model_.center();
    const double radius = std::max(model_.radius(), 1e-6);

    copyTransforms_.clear();
    instanceData_.clear();
    leadPose_.reset();
    poseData_.clear();
    poseOfTime_.clear();
    poseCount_ = 0;
    const glm::vec3 tint(linearColor(settings_.color, 1.0));
    for (uint32_t i = 0; i < maxCopies_; ++i) {
        const TimeNs t = frame.time - fromSeconds(double(i) * settings_.copySpacingSeconds);
        const auto pose = motion_->pose(t, ground);
        if (!pose) continue;
        if (i == 0) leadPose_ = pose;
        double scale = settings_.scale;
        if (settings_.minimumPixelSize > 0.0) {
            const double distance = std::max(glm::length(pose->position - eye_), 1e-3);
            const double pixels = 2.0 * radius * scale / distance * pixelsPerRadian;
            if (pixels < settings_.minimumPixelSize) scale *= settings_.minimumPixelSize / pixels;
        }
        const glm::dmat4 m = modelToEcef(*pose, scale);
        const glm::dvec3 center = glm::dvec3(m * glm::dvec4(centerModel, 1.0));
        if (i == 0) copyTransforms_.push_back(m);
        const double r = radius * scale;
        if (globe::sphereBelowHorizon(eye_, center, r)) continue;
        if (glm::length(center - eye_) < r) continue;   // the eye is inside (a pilot view): the model would hide everything
        if (!frustum.intersectsSphere(view * (center - eye_), r)) continue;
        if (i != 0) copyTransforms_.push_back(m);
        glm::dmat4 toEye = m;
        toEye[3] = glm::dvec4(pose->position - eye_, 1.0);   // large minus large, in double
        shader::ModelInstance inst{};
        inst.modelToEye = glm::mat4(toEye);
        inst.tint = tint;
        inst.poseBase = poser_ ? poseFor(t) : 0u;
        append(instanceData_, inst);
    }
    drawnCopies_ = uint32_t(instanceData_.size() / sizeof(shader::ModelInstance));
    if (settings_.path.show) buildPath(frame);
    if (settings_.label) buildLabel(frame);
}

uint32_t ModelLayer::poseFor(TimeNs t) {
    // Clamped to the keyframes' span: copies before the start or after the end share a pose.
    const double seconds = poser_->moves() ? std::clamp(models::animationSeconds(settings_.animation, poser_->duration(), t),
                                                        poser_->start(), poser_->duration())
                                           : 0.0;
    uint64_t key = 0;
    std::memcpy(&key, &seconds, sizeof key);
    if (const auto it = poseOfTime_.find(key); it != poseOfTime_.end()) return it->second;
    const uint32_t vec4s = poser_->layout().vec4s;
    if (poseCount_ == poseCapacity_) {   // full: the pose evaluated last, the copy just before in time
        ++posesShared_;
        return (poseCount_ - 1) * vec4s;
    }
    const uint32_t at = poseCount_ * vec4s;
    poseData_.resize(size_t(at) + vec4s);
    poser_->evaluate(seconds, poseData_.data() + at);
    ++poseCount_;
    poseOfTime_.emplace(key, at);
    return at;
}

void ModelLayer::buildPath(const scene::FrameContext& frame) {
    pathData_.clear();
    pathVertices_ = 0;
    const auto range = motion_->range();
    if (!range) return;
    const TimeNs to = std::clamp(frame.time, range->start, range->end);
    const TimeNs from = settings_.path.trailSeconds > 0.0
                            ? std::max(range->start, to - fromSeconds(settings_.path.trailSeconds))
                            : range->start;
    const TimeNs end = settings_.path.trailSeconds > 0.0 ? to : range->end;
    const auto points = motion_->path(from, end, settings_.path.maxPoints, frame.groundHeight);
    const glm::vec4 color = linearColor(settings_.path.color, settings_.path.opacity);
    for (const glm::dvec3& p : points) {
        shader::PolylineVertex v;
        // 1 m up (geocentric up is close enough for that): the straight segments between points
        // on the ground would otherwise dip into the terrain between its samples.
        v.position = glm::vec4(glm::vec3(p + glm::normalize(p) - eye_), 1.0f);
        v.color = color;
        append(pathData_, v);
    }
    pathVertices_ = uint32_t(points.size());
}

void ModelLayer::buildLabel(const scene::FrameContext& frame) {
    labelData_.clear();
    labelVertices_ = 0;
    const auto& pose = leadPose_;   // copy 0, placed by update()
    if (!pose) return;
    const scene::Camera& camera = *frame.camera;
    // Anchor: the top of the model's bounding sphere, along the local up.
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const globe::Geodetic g = wgs84.toGeodetic(pose->position);
    const double top = model_.radius() * settings_.scale;
    const glm::dvec3 anchor = pose->position + wgs84.surfaceNormal(g.lonDeg, g.latDeg) * top;
    if (globe::sphereBelowHorizon(eye_, anchor, 0.0)) return;
    const glm::dvec4 clip = camera.projection(frame.aspect()) * camera.viewRotation() * glm::dvec4(anchor - eye_, 1.0);
    if (clip.w <= 0.0) return;
    const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
    if (std::abs(ndc.x) > 1.5 || std::abs(ndc.y) > 1.5) return;
    const std::string text = settings_.labelText.empty() ? settings_.name : settings_.labelText;
    const auto quads = label::labelQuads(text, glm::dvec2((ndc.x * 0.5 + 0.5) * frame.width, (ndc.y * 0.5 + 0.5) * frame.height),
                                          2.0, kLabelMaxVertices / 6);
    const glm::vec4 textColor = linearColor(settings_.labelColor, 1.0);
    const glm::vec4 boxColor(0.0f, 0.0f, 0.0f, 0.55f);
    for (const label::LabelQuad& q : quads) {
        const glm::vec4 color = q.background ? boxColor : textColor;
        const glm::dvec2 corners[6] = {q.min, {q.max.x, q.min.y}, q.max, q.min, q.max, {q.min.x, q.max.y}};
        for (const glm::dvec2& c : corners) {
            shader::PolylineVertex v;
            v.position = glm::vec4(float(c.x / frame.width * 2.0 - 1.0), float(c.y / frame.height * 2.0 - 1.0), 1.0f, 1.0f);
            v.color = color;
            append(labelData_, v);
        }
    }
    labelVertices_ = uint32_t(labelData_.size() / sizeof(shader::PolylineVertex));
}

void ModelLayer::recordTransfers(const render::RecordContext& rc) {
    if (!instanceData_.empty()) instanceBuffers_[rc.slot].write(instanceData_.data(), instanceData_.size());
    if (poseCount_ > 0) poseBuffers_[rc.slot].write(poseData_.data(), poseData_.size() * sizeof(glm::vec4));
    if (pathVertices_ > 0) pathBuffers_[rc.slot].write(pathData_.data(), pathData_.size());
    if (labelVertices_ > 0) labelBuffers_[rc.slot].write(labelData_.data(), labelData_.size());
}

void ModelLayer::record(scene::Pass pass, const render::RecordContext& rc) {
    VkCommandBuffer cmd = rc.cmd;
    const VkDeviceSize zero = 0;
    if (pass == scene::Pass::Overlay) {
        if (labelVertices_ == 0) return;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, label_.vk());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lineLayout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);
        const VkBuffer b = labelBuffers_[rc.slot].vk();
        vkCmdBindVertexBuffers(cmd, 0, 1, &b, &zero);
        vkCmdDraw(cmd, labelVertices_, 1, 0, 0);
        return;
    }
    if (drawnCopies_ > 0) {
        // Opaque and masked materials first, then blended ones over them. A translucent model
        // (opacity below 1) lays down its depth first, then blends every material where it is
        // the nearest surface.
        const bool translucent = settings_.opacity < 1.0;
        for (const bool blended : {false, true}) {
            const gpu::Pipeline& pipeline = blended ? blend_ : translucent ? depthOnly_ : opaque_;
            if (pipeline) drawCopies(rc, pipeline, blended);
        }
    }
    if (pathVertices_ > 1) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, path_.vk());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lineLayout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);
        const VkBuffer b = pathBuffers_[rc.slot].vk();
        vkCmdBindVertexBuffers(cmd, 0, 1, &b, &zero);
        vkCmdDraw(cmd, pathVertices_, 1, 0, 0);
    }
}

void ModelLayer::drawCopies(const render::RecordContext& rc, const gpu::Pipeline& pipeline, bool blended) {
    VkCommandBuffer cmd = rc.cmd;
    const VkDeviceSize zero = 0;
    const VkDescriptorSet sets[] = {rc.frameSet, frameSets_.sets[rc.slot]};
    const VkBuffer vb = vertices_.vk();
    const bool translucent = settings_.opacity < 1.0;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.vk());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 0, nullptr);
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &zero);
    if (poser_) {
        const VkBuffer sb = skinVertices_.vk();
        vkCmdBindVertexBuffers(cmd, 1, 1, &sb, &zero);
    }
    vkCmdBindIndexBuffer(cmd, indices_.vk(), 0, VK_INDEX_TYPE_UINT32);
    VkDescriptorSet boundMaterial = VK_NULL_HANDLE;
    for (uint32_t di = 0; di < model_.draws.size(); ++di) {
        const models::ModelPrimitive& prim = model_.primitives[model_.draws[di].primitive];
        const models::ModelMaterial* mat = prim.material >= 0 ? &model_.materials[size_t(prim.material)] : nullptr;
        const bool isBlend = mat && mat->alphaMode == models::AlphaMode::Blend;
        if (!translucent && isBlend != blended) continue;
        if (translucent && !blended && isBlend) continue;   // BLEND materials do not hide
        const int tex = mat ? mat->baseColorTexture : -1;
        const VkDescriptorSet set = textures_[tex >= 0 ? size_t(tex) : textures_.size() - 1].set;
        if (set != boundMaterial) {
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kModelMaterialSet, 1, &set, 0, nullptr);
            boundMaterial = set;
        }
        const shader::ModelPush push = drawPush(di, mat);
        vkCmdPushConstants(cmd, layout_.vk(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push), &push);
        vkCmdDrawIndexed(cmd, prim.indexCount, drawnCopies_, prim.firstIndex, prim.vertexOffset, 0);
    }
}

shader::ModelPush ModelLayer::drawPush(uint32_t di, const models::ModelMaterial* mat) const {
    const models::ModelPrimitive& prim = model_.primitives[model_.draws[di].primitive];
    shader::ModelPush push{};
    push.baseColor = mat ? mat->baseColorFactor : glm::vec4(1.0f);
    push.baseColor.a *= float(settings_.opacity);
    push.alphaCutoff = mat && mat->alphaMode == models::AlphaMode::Mask ? mat->alphaCutoff : -1.0f;
    push.unlit = mat && mat->unlit ? 1u : 0u;
    push.sunLighting = settings_.sunLighting ? 1u : 0u;
    push.textured = mat && mat->baseColorTexture >= 0 ? 1u : 0u;
    push.node = di;
    if (poser_) {
        const models::PoseLayout& l = poser_->layout();
        const bool morphs = l.drawWeights[di] != models::kPoseNone;
        const uint32_t targets = morphs ? prim.morphTargets : 0u;
        push.node = l.drawMatrix[di];
        push.joints = l.drawJoints[di];
        push.morphTargets = targets;
        push.morphWeights = morphs ? l.drawWeights[di] : 0u;
        // Wraps modulo 2^32 like the shader's uint arithmetic.
        push.morphBase = prim.morphBase - uint32_t(prim.vertexOffset) * targets;
    }
    return push;
}

uint64_t ModelLayer::gpuBytes() const { return gpuBytes_; }

std::optional<double> ModelLayer::nearestContent(const glm::dvec3& eye) const {
    double best = -1.0;
    const double radius = model_.radius();
    for (const glm::dmat4& m : copyTransforms_) {
        const glm::dvec3 c = glm::dvec3(m * glm::dvec4(model_.center(), 1.0));
        const double r = radius * glm::length(glm::dvec3(m[0]));
        const double d = std::max(0.0, glm::length(c - eye) - r);
        if (best < 0.0 || d < best) best = d;
    }
    if (best < 0.0) return std::nullopt;
    return best;
}

std::optional<scene::TimeRange> ModelLayer::timeRange() const {
    auto r = motion_->range();
    if (r && maxCopies_ > 1) r->end += fromSeconds(double(maxCopies_ - 1) * settings_.copySpacingSeconds);
    return r;
}

std::optional<scene::TrackedPose> ModelLayer::trackedPose(TimeNs t, const scene::GroundHeightFn& ground) const {
    auto pose = motion_->pose(t, ground);
    if (pose) pose->radius = std::max(model_.radius() * settings_.scale, 0.1);
    return pose;
}

std::optional<scene::ContentBounds> ModelLayer::contentBounds() const {
    scene::ContentBounds b = motion_->bounds();
    b.radius += model_.radius() * settings_.scale;
    return b;
}

std::string ModelLayer::status() const {
    std::string s = std::to_string(drawnCopies_) + " of " + std::to_string(maxCopies_) + " drawn";
    if (poser_ && poser_->moves()) {
        const auto& a = model_.rig.animations[size_t(poser_->animation())];
        s += "; animation '" + (a.name.empty() ? std::to_string(poser_->animation()) : a.name) + "': " + std::to_string(poseCount_) +
             " poses";
        if (posesShared_ > 0) s += " (" + std::to_string(posesShared_) + " copies shared a pose: pose buffer full)";
    }
    const std::string m = motion_->status();
    return m.empty() ? s : s + "; " + m;
}

bool ModelLayer::setParameter(std::string_view name, double value) {
    // Both are read every frame (the copies' transforms, the label's height, tracked poses).
    // The ranges are the scene file's (create()), so that a saved scene loads again.
    if (name == "scale" && kScaleRange.contains(value)) {
        settings_.scale = value;
        motion_->setFootprint(footprint());
    }
    else if (name == "minimumPixelSize" && kMinimumPixelSizeRange.contains(value)) settings_.minimumPixelSize = value;
    else if (name == "opacity" && kOpacityRange.contains(value)) settings_.opacity = value;
    else return false;
    return true;
}

std::vector<scene::LayerSetting> ModelLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    return {
        {.name = "scale", .label = "Scale", .kind = Kind::Number, .value = settings_.scale, .min = kScaleRange.min, .max = kScaleRange.max,
         .logarithmic = true},
        {.name = "minimumPixelSize", .label = "Minimum size (px)", .kind = Kind::Number,
         .value = settings_.minimumPixelSize, .min = kMinimumPixelSizeRange.min, .max = kMinimumPixelSizeRange.max},
        {.name = "opacity", .label = "Opacity", .kind = Kind::Number, .value = settings_.opacity, .min = kOpacityRange.min, .max = kOpacityRange.max},
    };
}

}  // namespace orbis::layers
