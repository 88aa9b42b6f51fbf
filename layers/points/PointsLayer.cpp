#include "layers/points/PointsLayer.h"

#include "base/Log.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Image.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "globe/Culling.h"
#include "shared/FrameUniforms.h"
#include "shared/PointTypes.h"
#include "spv/common/fullscreen.vert.h"
#include "spv/points/pointlist.frag.h"
#include "spv/points/pointlist.vert.h"
#include "spv/points/resolve.frag.h"
#include "spv/points/splat.comp.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <queue>

namespace orbis::layers {

// The pipeline layouts list the sets in order: the frame's, then the layer's.
static_assert(shader::kPointSet == shader::kFrameSet + 1);

namespace {

// The colour modes are the shader's kPointSpecColorMode values.
using Color = PointsSettings::Color;
static_assert(uint32_t(Color::Rgb) == shader::kPointColorRgb && uint32_t(Color::Intensity) == shader::kPointColorIntensity &&
              uint32_t(Color::Classification) == shader::kPointColorClassification &&
              uint32_t(Color::Height) == shader::kPointColorHeight && uint32_t(Color::Constant) == shader::kPointColorConstant);

constexpr VkShaderStageFlags kPushStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_COMPUTE_BIT;
constexpr uint64_t kUploadBytesPerFrame = uint64_t(48) << 20;

/// Splat radius for a point size (diameter in pixels): 1 -> 0 (one pixel), 2..3 -> 1, ...
int splatRadius(int pointSize) { return std::clamp(pointSize, 1, 15) / 2; }

// The scene file's names of the colour modes and renderers, in the enums' order.
constexpr const char* kColorNames[] = {"rgb", "intensity", "classification", "height", "constant"};
constexpr const char* kRendererNames[] = {"compute", "pointList"};

}  // namespace

PointsLayer::PointsLayer(std::unique_ptr<points::LasFile> file, points::PointGeoreference georef, PointsSettings settings)
    : file_(std::move(file)), georef_(std::move(georef)), settings_(settings) {}

PointsLayer::~PointsLayer() {
    if (cancel_) cancel_->store(true);   // the job holds what it reads; it stops at its next batch
}

// ---------------------------------------------------------------------------------------------
// Loading (a worker) and residency
void PointsLayer::startLoading() {
    loadProgress_ = std::make_shared<std::atomic<double>>(0.0);
    cancel_ = std::make_shared<std::atomic<bool>>(false);
    std::shared_ptr<points::LasFile> file = file_;
    points::PointGeoreference georef = georef_;
    auto progress = loadProgress_;
    auto cancel = cancel_;
    points::PointLoadOptions o;
    // About 90 bytes a point while a chunk (or a whole small cloud) is built.
    o.inMemoryPoints = o.chunkPoints = std::max<uint64_t>(settings_.cpuMemoryBytes / 96, 1);
    o.cacheFolder = settings_.cacheFolder;
    o.mortonOrder = settings_.mortonOrder;
    loadJob_ = services_.jobs().submit(0.0, jobs::CancelToken::create(),
                                       [file, georef, progress, cancel, o](const jobs::CancelToken&) mutable {
                                           o.cancel = cancel.get();
                                           o.progress = [progress](double f) { progress->store(f); };
                                           // A COPC file is its own octree: nothing to build.
                                           if (file->copc()) return points::loadCopcStore(file, georef, o);
                                           return points::loadPointStore(*file, georef, o);
                                       });
}

void PointsLayer::finishLoading() {
    if (!loadJob_.valid() || !loadJob_.ready()) return;
    auto job = std::move(loadJob_);
    loadJob_ = {};
    try {
        auto loaded = job.get();
        if (!loaded) {
            loadError_ = loaded.message();
            log::error(loadError_);
            return;
        }
        store_ = std::move(loaded).value();
        for (const std::string& damage : file_->damagedChunks()) log::warn("points: ", damage);
    } catch (const std::exception& e) {
        loadError_ = std::string(file_->path()).append(": loading failed: ").append(e.what());
        log::error(loadError_);
        return;
    }
    // One GPU buffer for the resident nodes (the budget, or the whole cloud when smaller), in
    // pages that a shader sees one at a time: maxStorageBufferRange can be smaller than the
    // budget (128 MB on lavapipe). A page is bound by a dynamic offset, a uint32.
    const VkPhysicalDeviceLimits& limits = services_.device->properties().limits;
    const uint64_t align = std::max<uint64_t>(limits.minStorageBufferOffsetAlignment, points::NodeResidency::kAlignment);
    uint64_t page = std::min<uint64_t>(limits.maxStorageBufferRange, settings_.gpuMemoryBytes);
    if (settings_.gpuPageBytes > 0) page = std::min(page, settings_.gpuPageBytes);
    page = std::max(page / align * align, align);
    const uint64_t budget = std::min<uint64_t>(settings_.gpuMemoryBytes, (uint64_t(UINT32_MAX) / page + 1) * page);
    residency_ = std::make_unique<points::NodeResidency>(store_, budget, page, services_.framesInFlight);
    if (residency_->pages() > 1)
        log::info("points: the resident nodes' buffer is ", residency_->pages(), " pages of ", double(residency_->pageBytes()) / 1048576.0,
                  " MB (the device's maxStorageBufferRange is ", limits.maxStorageBufferRange >> 20, " MB)");
    if (residency_->oversizedNodes() > 0)
        log::warn("points: ", file_->path(), ": ", residency_->oversizedNodes(), " octree nodes are larger than a ",
                  double(residency_->pageBytes()) / 1048576.0, " MB page of gpuMemoryMB and are never drawn (nor the nodes below them)");
    drawnFrame_.assign(store_->nodes().size(), 0);
    levelsBelow_.assign(store_->nodes().size(), 0);
    loadedFrame_ = frame_ + 1;   // this frame's (update counts it next): its near plane did not know the cloud yet
    if (residency_->capacity() == 0) return;
    data_ = gpu::Buffer(*services_.device, residency_->capacity(),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::GpuOnly,
                        "point data");
    ++buffersVersion_;
}

void PointsLayer::recordTransfers(const render::RecordContext& rc) {
    if (!gpuReady_ || !residency_ || !data_) return;
    const uint64_t bytes = residency_->upload(kUploadBytesPerFrame, [&](int32_t, std::span<const uint8_t> d, uint64_t offset) {
        rc.uploader->toBuffer(rc.cmd, data_, d.data(), d.size(), offset);
    });
    if (bytes > 0) {
        const VkPipelineStageFlags2 readers = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT |
                                              VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
        gpu::bufferBarrier(rc.cmd, data_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, readers,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
    writeUniforms(rc);
}

bool PointsLayer::busy() const {
    if (loadJob_.valid()) return true;
    // Until a frame after the one that finished loading has selected nodes, and then while
    // nodes are being read or uploaded.
    return residency_ && gpuReady_ && (frame_ <= loadedFrame_ || residency_->busy());
}

std::optional<double> PointsLayer::nearestContent(const glm::dvec3& eye) const {
    if (!store_ || store_->nodes().empty()) return std::nullopt;
    // The nodes drawn last frame (their spheres: at most nearer than the points), else the root.
    const auto& nodes = store_->nodes();
    const auto gap = [&](const points::StoredNode& n) { return std::max(0.0, glm::length(n.centre - eye) - n.radius()); };
    double d = drawList_.empty() ? gap(nodes[0]) : std::numeric_limits<double>::max();
    for (int32_t k : drawList_) d = std::min(d, gap(nodes[size_t(k)]));
    return d;
}

// ---------------------------------------------------------------------------------------------
// Selection: the largest nodes on screen first, within the budget
void PointsLayer::update(const scene::FrameContext& frame) {
    finishLoading();
    ++frame_;
    wanted_.clear();
    drawList_.clear();
    drawnPoints_ = 0;
    if (!store_ || !residency_ || !gpuReady_ || store_->nodes().empty()) return;
    residency_->beginFrame(frame_);
    if (!residency_->error().empty() && loadError_.empty()) {
        loadError_ = residency_->error();
        log::error(loadError_);
    }
    const scene::Camera& camera = *frame.camera;
    eye_ = camera.position();
    const glm::dmat4 view = camera.viewRotation();
    viewProj_ = camera.projection(frame.aspect()) * view;
    const globe::ViewFrustum frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), frame.aspect(), camera.nearPlane());
    const double pixelsPerRadian = double(frame.height) / (2.0 * std::tan(0.5 * camera.verticalFovRad()));
    const auto& nodes = store_->nodes();
    const auto visible = [&](const points::StoredNode& n) {
        const glm::dvec3 rel = n.centre - eye_;
        return frustum.intersectsSphere(glm::dvec3(view * glm::dvec4(rel, 0.0)), n.radius()) &&
               !globe::sphereBelowHorizon(eye_, n.centre, n.radius());
    };
    const auto screenSize = [&](const points::StoredNode& n) {
        const double d = glm::length(n.centre - eye_) - n.radius();
        return d <= 0.0 ? 1e30 : n.radius() / d * pixelsPerRadian;
    };
    // Wanted: by screen size within the budget. Drawn: the wanted nodes on the GPU whose parent
    // is drawn (a child pops after its parent, so the parent's flag is set by then).
    using Entry = std::pair<double, int32_t>;
    std::priority_queue<Entry> queue;
    if (visible(nodes[0])) queue.push({screenSize(nodes[0]), 0});
    const uint64_t budget = settings_.pointBudget ? settings_.pointBudget : ~uint64_t(0);
    uint64_t wantedPoints = 0;
    while (!queue.empty()) {
        const int32_t i = queue.top().second;
        queue.pop();
        const points::StoredNode& n = nodes[size_t(i)];
        if (wantedPoints + n.count > budget) break;   // the largest left does not fit: stop
        wanted_.push_back(i);
        wantedPoints += n.count;
        if (residency_->resident(i) && (n.parent < 0 || drawnFrame_[size_t(n.parent)] == frame_)) {
            drawList_.push_back(i);
            drawnFrame_[size_t(i)] = frame_;
            drawnPoints_ += n.count;
        }
        for (int32_t c : n.children)
            if (c >= 0 && visible(nodes[size_t(c)])) queue.push({screenSize(nodes[size_t(c)]), c});
    }
    residency_->want(wanted_, store_->onDisk() ? &services_.jobs() : nullptr);
}

// ---------------------------------------------------------------------------------------------
// GPU objects
void PointsLayer::onPrepare(const render::RenderServices& services) {
    services_ = services;
    gpu::Device& device = *services.device;
    if (settings_.renderer == PointsSettings::Renderer::Compute && !device.features().bufferInt64Atomics) {
        log::warn("points: the device has no 64-bit buffer atomics; drawing point lists instead of compute rasterisation");
        settings_.renderer = PointsSettings::Renderer::PointList;
    }
    const uint32_t frames = services.framesInFlight;
    descriptors_ = gpu::createDescriptorSets(device, shader::kPointBindings, frames);
    slots_.resize(frames);
    for (uint32_t f = 0; f < frames; ++f) {
        Slot& slot = slots_[f];
        slot.set = descriptors_.sets[f];
        slot.uniforms = gpu::Buffer(device, sizeof(shader::PointUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                    gpu::MemoryUsage::Upload, "point uniforms");
    }
    const VkPushConstantRange push{kPushStages, 0, sizeof(shader::PointPush)};
    const VkDescriptorSetLayout setLayouts[] = {services.frameSetLayout, descriptors_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, setLayouts, {&push, 1});
    depthSampler_ = gpu::createSampler(device, {.filter = VK_FILTER_NEAREST});
    gpuReady_ = true;
    startLoading();
}

gpu::Pipeline& PointsLayer::splatPipeline(int radius, bool quantised) {
    const bool adaptive = settings_.adaptiveSize;
    gpu::Pipeline& p = splatPipelines_[((int(settings_.color) * 16 + radius) * 2 + (quantised ? 1 : 0)) * 2 + (adaptive ? 1 : 0)];
    if (!p) {
        gpu::Specialization spec;
        spec.set<int32_t>(shader::kPointSpecRadius, radius);
        spec.set<uint32_t>(shader::kPointSpecColorMode, uint32_t(settings_.color));
        spec.set<VkBool32>(shader::kPointSpecQuantised, quantised ? VK_TRUE : VK_FALSE);
        spec.set<VkBool32>(shader::kPointSpecAdaptive, adaptive ? VK_TRUE : VK_FALSE);
        p = gpu::createComputePipeline(*services_.device, layout_.vk(), kSpv_points_splat_comp, &spec, "points splat");
    }
    return p;
}

gpu::Pipeline& PointsLayer::graphicsPipeline(std::map<int, gpu::Pipeline>& cache, int key, bool pointList,
                                             const gpu::Specialization& spec) {
    // Below full opacity the cloud blends over the scene (premultiplied, depth still written:
    // the nearest point of a pixel hides what the later passes would draw behind it).
    const bool blend = settings_.opacity < 1.0;
    gpu::Pipeline& p = cache[key * 2 + (blend ? 1 : 0)];
    if (!p) {
        gpu::GraphicsPipelineDesc d;
        d.vertexSpirv = pointList ? std::span<const uint32_t>(kSpv_points_pointlist_vert) : kSpv_common_fullscreen_vert;
        d.fragmentSpirv = pointList ? std::span<const uint32_t>(kSpv_points_pointlist_frag) : kSpv_points_resolve_frag;
        d.layout = layout_.vk();
        if (pointList) d.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
        d.cullMode = VK_CULL_MODE_NONE;
        d.colorFormat = services_.colorFormat;
        d.depthFormat = services_.depthFormat;
        d.specialization = &spec;
        d.alphaBlend = blend;
        d.name = pointList ? "points list" : "points resolve";
        p = gpu::createGraphicsPipeline(*services_.device, d);
    }
    return p;
}

gpu::Pipeline& PointsLayer::pointListPipeline(bool quantised) {
    gpu::Specialization spec;
    spec.set<uint32_t>(shader::kPointSpecColorMode, uint32_t(settings_.color));
    spec.set<VkBool32>(shader::kPointSpecQuantised, quantised ? VK_TRUE : VK_FALSE);
    return graphicsPipeline(pointListPipelines_, int(settings_.color) * 2 + (quantised ? 1 : 0), true, spec);
}

gpu::Pipeline& PointsLayer::resolvePipeline() {
    gpu::Specialization spec;
    spec.set<VkBool32>(shader::kPointSpecEdl, settings_.edl ? VK_TRUE : VK_FALSE);
    return graphicsPipeline(resolvePipelines_, settings_.edl ? 1 : 0, false, spec);
}

bool PointsLayer::computePath() const { return settings_.renderer == PointsSettings::Renderer::Compute; }

bool PointsLayer::computesBefore(scene::Pass pass) const {
    return pass == scene::Pass::Points && computePath() && !drawList_.empty();
}

void PointsLayer::ensureScreen(uint32_t width, uint32_t height) {
    const uint64_t bytes = uint64_t(width) * height * sizeof(uint64_t);
    if (screen_ && screen_.size() == bytes) return;
    screen_ = gpu::Buffer(*services_.device, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          gpu::MemoryUsage::GpuOnly, "points screen buffer");
    ++buffersVersion_;
}

void PointsLayer::ensureFrameBuffers(uint32_t s, size_t nodes, size_t batches) {
    Slot& slot = slots_[s];
    const auto grow = [&](gpu::Buffer& b, size_t bytes, const char* name) {
        if (b && b.size() >= bytes) return;
        size_t size = 4096;
        while (size < bytes) size *= 2;
        b = gpu::Buffer(*services_.device, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Upload, name);
        slot.version = 0;   // its set names the old buffer
    };
    grow(slot.nodes, std::max<size_t>(nodes, 1) * sizeof(shader::PointNode), "point nodes");
    grow(slot.batches, std::max<size_t>(batches, 1) * sizeof(shader::PointBatch), "point batches");
}

void PointsLayer::writeDescriptors(uint32_t s) {
    Slot& slot = slots_[s];
    const VkDeviceSize page = residency_ ? residency_->pageBytes() : VK_WHOLE_SIZE;   // at dynamic offsets
    gpu::DescriptorWriter w(slot.set);
    w.uniformBuffer(shader::kPointBindingUniforms, slot.uniforms, 0, sizeof(shader::PointUniforms));
    // What is not made yet is left out: the pipelines in use do not read it.
    if (data_) {
        w.storageBufferDynamic(shader::kPointBindingWords, data_, page);
        w.storageBufferDynamic(shader::kPointBindingAttributes, data_, page);
    }
    if (slot.batches) w.storageBuffer(shader::kPointBindingBatches, slot.batches);
    if (slot.nodes) w.storageBuffer(shader::kPointBindingNodes, slot.nodes);
    if (screen_) w.storageBuffer(shader::kPointBindingScreen, screen_);
    if (boundDepth_) w.sampledImage(shader::kPointBindingSceneDepth, depthSampler_.vk(), boundDepth_->view());
    w.update(*services_.device);
    slot.version = buffersVersion_;
}

// ---------------------------------------------------------------------------------------------
// Frames
void PointsLayer::writeUniforms(const render::RecordContext& rc) {
    const scene::FrameContext& frame = *rc.frame;
    if (drawList_.empty()) return;
    const auto& nodes = store_->nodes();
    size_t batches = 0;
    for (int32_t k : drawList_) batches += (nodes[size_t(k)].count + shader::kPointBatch - 1) / shader::kPointBatch;
    ensureFrameBuffers(rc.slot, drawList_.size(), batches);
    Slot& slot = slots_[rc.slot];
    nodeData_.resize(drawList_.size());
    batchData_.resize(batches);
    const uint64_t pageBytes = residency_->pageBytes();
    nodePage_.resize(drawList_.size());
    // Level-aware sizes: per drawn node and octant, the levels drawn below it there (the fewest
    // over the octant's child's own octants: where any part is left coarse, its points stay large
    // enough to cover it). Children come after their parents in the draw list: bottom up.
    std::vector<uint32_t> octants(drawList_.size(), 0);
    for (size_t k = settings_.adaptiveSize ? drawList_.size() : 0; k-- > 0;) {
        const points::StoredNode& n = nodes[size_t(drawList_[k])];
        uint32_t fewest = 15;
        for (int c = 0; c < 8; ++c) {
            const int32_t child = n.children[c];
            const bool drawn = child >= 0 && drawnFrame_[size_t(child)] == frame_;
            const uint32_t below = drawn ? std::min<uint32_t>(15u, 1u + levelsBelow_[size_t(child)]) : 0u;
            octants[k] |= below << (4 * c);
            fewest = std::min(fewest, below);
        }
        levelsBelow_[size_t(drawList_[k])] = uint8_t(fewest);
    }
    // A node's spacing: the root's points over its cube's face, halved at each level.
    const points::StoredNode& root = nodes[0];
    const double rootSpacing = 2.0 * root.halfSize / std::sqrt(double(std::max<uint32_t>(root.count, 1)));
    for (size_t k = 0; k < drawList_.size(); ++k) {
        const points::StoredNode& n = nodes[size_t(drawList_[k])];
        const uint64_t offset = residency_->offset(drawList_[k]) % pageBytes;   // within its page
        nodePage_[k] = uint32_t(residency_->offset(drawList_[k]) / pageBytes);
        nodeData_[k] = {glm::vec3(n.centre - eye_), float(n.step), uint32_t(offset / 8),
                        uint32_t((offset + n.positionOffset()) / 4), n.count, octants[k],
                        float(rootSpacing * std::exp2(-double(n.level))), 0u, 0u, 0u};
    }
    // The batches by position format (quantised first) and page: one dispatch each.
    std::vector<uint32_t> order(drawList_.size());
    for (uint32_t k = 0; k < order.size(); ++k) order[k] = k;
    const auto group = [&](uint32_t k) {
        return std::pair<int, uint32_t>(nodes[size_t(drawList_[k])].step > 0.0 ? 0 : 1, nodePage_[k]);
    };
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return group(a) < group(b); });
    dispatches_.clear();
    size_t b = 0;
    for (uint32_t k : order) {
        const points::StoredNode& n = nodes[size_t(drawList_[k])];
        const bool quantised = n.step > 0.0;
        if (dispatches_.empty() || dispatches_.back().quantised != quantised || dispatches_.back().page != nodePage_[k])
            dispatches_.push_back({quantised, nodePage_[k], uint32_t(b), 0});
        for (uint32_t off = 0; off < n.count; off += shader::kPointBatch) {
            batchData_[b++] = {k, off, std::min(shader::kPointBatch, n.count - off), 0u};
            ++dispatches_.back().batches;
        }
    }
    slot.nodes.write(nodeData_.data(), nodeData_.size() * sizeof(shader::PointNode));
    slot.batches.write(batchData_.data(), b * sizeof(shader::PointBatch));

    shader::PointUniforms u{};
    u.viewProj = glm::mat4(viewProj_);
    u.opacity = float(settings_.opacity);
    u.intensityGain = store_->info().intensityGain;
    u.heightLow = float(settings_.heightRange.x);
    u.heightScale = float(1.0 / std::max(settings_.heightRange.y - settings_.heightRange.x, 1e-6));
    u.constantColor = glm::vec4(glm::vec3(settings_.constantColor), 1.0f);
    u.edlStrength = float(settings_.edlStrength);
    u.edlRadiusPx = float(settings_.edlRadius);
    u.pointSizePx = float(settings_.pointSize);
    // Pixels a metre at 1 m: the projection's vertical scale over half the image's height.
    // Level-aware sizes: discs two spacings across (the radius one spacing), which the sweep on
    // the 5 M survey found best among 1, 2 and 3 for error against frame time (README).
    constexpr float kAdaptiveScale = 2.0f;
    u.adaptivePixels = settings_.adaptiveSize ? kAdaptiveScale * float(frame.height) * 0.5f / std::tan(0.5f * float(frame.camera->verticalFovRad())) : 0.0f;
    u.screenSize = glm::vec2(float(frame.width), float(frame.height));
    slot.uniforms.write(&u, sizeof(u));
    if (!computePath() && slot.version != buffersVersion_) writeDescriptors(rc.slot);
}

void PointsLayer::recordCompute(scene::Pass, const render::RecordContext& rc) {
    if (drawList_.empty()) return;
    VkCommandBuffer cmd = rc.cmd;
    ensureScreen(rc.frame->width, rc.frame->height);
    if (boundDepth_ != rc.sceneDepth) {
        boundDepth_ = rc.sceneDepth;
        ++buffersVersion_;
    }
    Slot& slot = slots_[rc.slot];
    if (slot.version != buffersVersion_) writeDescriptors(rc.slot);
    // The last frame's resolve read the screen buffer: clear it after that, before the splats.
    gpu::bufferBarrier(cmd, screen_, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                       VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, screen_.vk(), 0, VK_WHOLE_SIZE, 0u);
    gpu::bufferBarrier(cmd, screen_, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    const VkDescriptorSet sets[] = {rc.frameSet, slot.set};
    const gpu::Pipeline* bound = nullptr;
    for (const Dispatch& d : dispatches_) {
        const uint32_t offsets[2] = {pageOffset(d.page), pageOffset(d.page)};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.vk(), shader::kFrameSet, 2, sets, 2, offsets);
        gpu::Pipeline& p = splatPipeline(splatRadius(settings_.pointSize), d.quantised);
        if (&p != bound) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.vk());
        bound = &p;
        const shader::PointPush push{0, d.firstBatch};
        vkCmdPushConstants(cmd, layout_.vk(), kPushStages, 0, sizeof push, &push);
        vkCmdDispatch(cmd, d.batches, 1, 1);
    }
    gpu::bufferBarrier(cmd, screen_, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

void PointsLayer::record(scene::Pass, const render::RecordContext& rc) {
    if (drawList_.empty()) return;
    VkCommandBuffer cmd = rc.cmd;
    const VkDescriptorSet sets[] = {rc.frameSet, slots_[rc.slot].set};
    if (computePath()) {
        if (!screen_) return;
        const uint32_t offsets[2] = {0, 0};   // the resolve reads only the screen buffer
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, resolvePipeline().vk());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 2, offsets);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        return;
    }
    int bound = -1;                 // the position format of the bound pipeline
    uint32_t boundPage = UINT32_MAX;
    for (uint32_t k = 0; k < drawList_.size(); ++k) {
        const points::StoredNode& n = store_->nodes()[size_t(drawList_[k])];
        if (nodePage_[k] != boundPage) {
            boundPage = nodePage_[k];
            const uint32_t offsets[2] = {pageOffset(boundPage), pageOffset(boundPage)};
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 2, offsets);
        }
        if (int(n.step > 0.0) != bound) {
            bound = int(n.step > 0.0);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pointListPipeline(bound != 0).vk());
        }
        const shader::PointPush push{k, 0};
        vkCmdPushConstants(cmd, layout_.vk(), kPushStages, 0, sizeof push, &push);
        vkCmdDraw(cmd, n.count, 1, 0, 0);
    }
}

uint32_t PointsLayer::pageOffset(uint32_t page) const { return uint32_t(uint64_t(page) * residency_->pageBytes()); }

// ---------------------------------------------------------------------------------------------
// Settings and stats
bool PointsLayer::computeAvailable() const {
    return !services_.device || services_.device->features().bufferInt64Atomics;
}

bool PointsLayer::setParameter(std::string_view name, double value) {
    // The ranges the scene file accepts (create()), so that a saved scene loads again.
    if (name == "pointBudget" && kPointBudgetRange.contains(value)) settings_.pointBudget = uint64_t(value);
    else if (name == "pointSize" && kPointSizeRange.contains(value)) settings_.pointSize = int(value);
    else if (name == "opacity" && kOpacityRange.contains(value)) settings_.opacity = value;
    else if (name == "edl") settings_.edl = value != 0.0;
    else if (name == "adaptiveSize") settings_.adaptiveSize = value != 0.0;
    else if (name == "edlStrength" && kEdlStrengthRange.contains(value)) settings_.edlStrength = value;
    else if (name == "edlRadius" && kEdlRadiusRange.contains(value)) settings_.edlRadius = value;
    else if (name == "renderer" && (value == 0.0 || value == 1.0)) {
        const bool compute = value == 0.0 && computeAvailable();
        settings_.renderer = compute ? PointsSettings::Renderer::Compute : PointsSettings::Renderer::PointList;
    } else return false;
    return true;
}

bool PointsLayer::setOption(std::string_view name, std::string_view value) {
    if (name == "renderer") {
        if (value == "compute" && computeAvailable()) settings_.renderer = PointsSettings::Renderer::Compute;
        else if (value == "pointList") settings_.renderer = PointsSettings::Renderer::PointList;
        else return false;
        return true;
    }
    if (name != "color") return false;
    for (size_t i = 0; i < std::size(kColorNames); ++i) {
        if (value == kColorNames[i]) {
            settings_.color = PointsSettings::Color(i);
            return true;
        }
    }
    return false;
}

std::vector<scene::LayerSetting> PointsLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    std::vector<std::string> renderers = {kRendererNames[1]};
    if (computeAvailable()) renderers.insert(renderers.begin(), kRendererNames[0]);
    return {
        {.name = "color", .label = "Colour by", .kind = Kind::Choice, .choice = kColorNames[size_t(settings_.color)],
         .choices = {std::begin(kColorNames), std::end(kColorNames)}},
        {.name = "pointBudget", .label = "Point budget (0: all)", .kind = Kind::Integer,
         .value = double(settings_.pointBudget), .min = kPointBudgetRange.min, .max = kPointBudgetRange.max, .logarithmic = true},
        {.name = "pointSize", .label = "Point size (px)", .kind = Kind::Integer, .value = double(settings_.pointSize),
         .min = kPointSizeRange.min, .max = kPointSizeRange.max},
        {.name = "adaptiveSize", .label = "Sizes by level (no holes)", .kind = Kind::Toggle, .value = settings_.adaptiveSize ? 1.0 : 0.0},
        {.name = "opacity", .label = "Opacity", .kind = Kind::Number, .value = settings_.opacity, .min = kOpacityRange.min, .max = kOpacityRange.max},
        {.name = "edl", .label = "Eye-dome lighting", .kind = Kind::Toggle, .value = settings_.edl ? 1.0 : 0.0},
        {.name = "edlStrength", .label = "EDL strength", .kind = Kind::Number, .value = settings_.edlStrength,
         .min = kEdlStrengthRange.min, .max = kEdlStrengthRange.max, .logarithmic = true},
        {.name = "edlRadius", .label = "EDL radius (px)", .kind = Kind::Number, .value = settings_.edlRadius,
         .min = kEdlRadiusRange.min, .max = kEdlRadiusRange.max},
        {.name = "renderer", .label = "Renderer", .kind = Kind::Choice,
         .choice = kRendererNames[size_t(settings_.renderer)], .choices = std::move(renderers)},
    };
}

uint64_t PointsLayer::gpuBytes() const {
    uint64_t bytes = data_ ? data_.size() : 0;
    if (screen_) bytes += screen_.size();
    return bytes;
}

uint64_t PointsLayer::cacheBytes() const {
    if (!store_) return 0;
    return store_->memoryBytes() + (residency_ ? residency_->readyBytes() : 0);
}

std::string PointsLayer::status() const {
    char text[320];
    if (!loadError_.empty()) return loadError_;
    if (loadJob_.valid()) {
        std::snprintf(text, sizeof text, "points: loading %s, %.0f %%", file_->path().c_str(), 100.0 * loadProgress_->load());
        return text;
    }
    if (!store_ || !residency_) return {};
    const uint64_t skipped = file_->skippedPoints();
    std::snprintf(text, sizeof text,
                  "points: %s%.3g M of %.3g M drawn in %zu nodes; %.3g M resident (%.0f of %.0f MB), %llu reads, %llu evicted",
                  skipped > 0 ? (std::to_string(skipped).append(" points of damaged LAZ chunks left out; ")).c_str() : "",
                  drawnPoints_ * 1e-6, double(store_->info().points) * 1e-6, drawList_.size(),
                  double(residency_->residentPoints()) * 1e-6, double(residency_->residentBytes()) / 1048576.0,
                  double(residency_->capacity()) / 1048576.0, static_cast<unsigned long long>(residency_->readsInFlight()),
                  static_cast<unsigned long long>(residency_->evictions()));
    return text;
}

}  // namespace orbis::layers
