#include "layers/volume/VolumeLayer.h"

#include "base/Log.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "globe/Ellipsoid.h"
#include "shared/FrameUniforms.h"
#include "shared/VolumeTypes.h"
#include "spv/common/composite.frag.h"
#include "spv/common/fullscreen.vert.h"
#include "spv/volume/raycast.comp.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace orbis::layers {

// The pipeline layouts list the sets in order: the frame's, then the layer's.
static_assert(shader::kVolumeSet == shader::kFrameSet + 1);

namespace {

/// IEEE half from a float, rounded to nearest even; NaN stays NaN, overflow becomes infinity,
/// values below the smallest normal half flush to zero.
uint16_t halfFloat(float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    const uint32_t sign = (bits >> 16) & 0x8000u;
    const uint32_t absBits = bits & 0x7fffffffu;
    if (absBits > 0x7f800000u) return uint16_t(sign | 0x7e00u);   // NaN
    const int exp = int(absBits >> 23) - 127 + 15;
    if (exp >= 31) return uint16_t(sign | 0x7c00u);
    if (exp <= 0) return uint16_t(sign);
    uint32_t h = (uint32_t(exp) << 10) | ((absBits & 0x7fffffu) >> 13);
    const uint32_t rest = absBits & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;   // (a carry rounds up the exponent)
    return uint16_t(sign | std::min(h, 0x7c00u));
}

}  // namespace

VolumeLayer::VolumeLayer(VolumeField field, VolumeSettings settings, std::vector<std::vector<float>> moreTimeSteps,
                         std::vector<TimeNs> timeStepTimes)
    : field_(std::move(field)), moreTimeSteps_(std::move(moreTimeSteps)), timeStepTimes_(std::move(timeStepTimes)),
      settings_(std::move(settings)) {
    if (timeStepTimes_.size() != 1 + moreTimeSteps_.size()) timeStepTimes_.clear();   // no time axis to follow
}

VolumeLayer::~VolumeLayer() = default;

// ---------------------------------------------------------------------------------------------
// GPU resources

void VolumeLayer::onPrepare(const render::RenderServices& services) {
    servicesCopy_ = services;
    services_ = &servicesCopy_;
    gpu::Device& device = *services.device;
    std::vector<float> texels = stackTexels();
    const std::vector<float> axisTable = buildLookups();
    buildBricks(texels);
    const std::vector<uint16_t> halves = settings_.halfField ? toHalfFloats(texels) : std::vector<uint16_t>();
    box_ = makeVolumeBox(lonAxis_, field_.latDeg, field_.heightM, settings_.verticalExaggeration);
    uploadData(texels, halves, axisTable);
    createRayCaster();
    gpu::GraphicsPipelineDesc composite;
    composite.vertexSpirv = kSpv_common_fullscreen_vert;
    composite.fragmentSpirv = kSpv_common_composite_frag;
    composite.layout = layout_.vk();
    composite.cullMode = VK_CULL_MODE_NONE;
    composite.depthTest = false;
    composite.depthWrite = false;
    composite.alphaBlend = true;
    composite.colorFormat = services.colorFormat;
    composite.depthFormat = services.depthFormat;
    composite.name = "volume composite";
    compositePipeline_ = gpu::createGraphicsPipeline(device, composite);
}

std::vector<float> VolumeLayer::stackTexels() {
    // Longitudes: a periodic field gets its first column again at the end (first + 360), so
    // that filtering across the seam is continuous.
    lonAxis_ = field_.lonDeg;
    const size_t nx = field_.nx(), ny = field_.ny(), nz = field_.nz();
    const bool wrapColumn = field_.lonWraps && lonAxis_.back() < lonAxis_.front() + 360.0 - 1e-9;
    if (wrapColumn) lonAxis_.push_back(lonAxis_.front() + 360.0);
    const size_t gx = lonAxis_.size(), timeSteps = 1 + moreTimeSteps_.size();
    // Time steps stacked along z: time step s, level k is texel layer s * nz + k.
    std::vector<float> texels(gx * ny * nz * timeSteps);
    for (size_t ts = 0; ts < timeSteps; ++ts) {
        const std::vector<float>& v = ts == 0 ? field_.values : moreTimeSteps_[ts - 1];
        float* out = texels.data() + ts * gx * ny * nz;
        for (size_t k = 0; k < nz; ++k)
            for (size_t j = 0; j < ny; ++j)
                for (size_t i = 0; i < gx; ++i) out[(k * ny + j) * gx + i] = v[(k * ny + j) * nx + (i % nx)];
    }
    return texels;
}

std::vector<float> VolumeLayer::buildLookups() {
    // In the shader's axis order: lookups_[kVolumeAxisLon] is the longitude's.
    lookups_[shader::kVolumeAxisLon] = AxisLookup::build(lonAxis_, shader::kVolumeAxisTable);
    lookups_[shader::kVolumeAxisLat] = AxisLookup::build(field_.latDeg, shader::kVolumeAxisTable);
    lookups_[shader::kVolumeAxisHeight] = AxisLookup::build(field_.heightM, shader::kVolumeAxisTable);
    std::vector<float> axisTable(3 * shader::kVolumeAxisTable, 0.0f);
    for (size_t a = 0; a < 3; ++a)
        for (size_t t = 0; t < lookups_[a].table.size() && t < shader::kVolumeAxisTable; ++t)
            axisTable[a * shader::kVolumeAxisTable + t] = lookups_[a].table[t];
    return axisTable;
}

void VolumeLayer::buildBricks(const std::vector<float>& texels) {
    // Min/max bricks over the uploaded texels (the wrap column included), widened over the
    // time steps. The brick size keeps the bits within one vkCmdUpdateBuffer (64 KiB).
    // Bricks of about a sixteenth of the largest dimension (measured on lavapipe: 16-voxel bricks
    // at 256^3 jump further than 8-voxel ones and cost the same per sample).
    const size_t gx = lonAxis_.size(), ny = field_.ny(), nz = field_.nz(), timeSteps = 1 + moreTimeSteps_.size();
    int brickSize = 4;
    while (brickSize * 32 <= int(std::max({gx, ny, nz}))) brickSize *= 2;
    while (((gx + brickSize - 1) / brickSize) * ((ny + brickSize - 1) / brickSize) * ((nz + brickSize - 1) / brickSize) >
           size_t(65536) * 8)
        brickSize *= 2;
    for (size_t ts = 0; ts < timeSteps && settings_.emptySkipping; ++ts) {
        BrickGrid g = buildBrickGrid(texels.data() + ts * gx * ny * nz, gx, ny, nz, brickSize);
        if (ts == 0) bricks_ = std::move(g);
        else mergeBrickGrid(bricks_, g);
    }
}

std::vector<uint16_t> VolumeLayer::toHalfFloats(std::vector<float>& texels) {
    // Values relative to the data's range; the bricks widen by the rounding.
    const double lo = field_.validCount ? field_.minValue : 0.0, hi = field_.validCount ? field_.maxValue : 1.0;
    fieldScale_ = glm::dvec2(hi > lo ? 0.5 * (hi - lo) : 1.0, 0.5 * (lo + hi));
    std::vector<uint16_t> halves(texels.size());
    for (size_t i = 0; i < texels.size(); ++i)
        halves[i] = halfFloat(float((double(texels[i]) - fieldScale_.y) / fieldScale_.x));
    const float widen = float(fieldScale_.x * std::ldexp(1.0, -10));
    for (auto& mm : bricks_.minMax)
        if (mm.first <= mm.second) mm.first -= widen, mm.second += widen;
    std::vector<float>().swap(texels);
    return halves;
}

void VolumeLayer::uploadData(const std::vector<float>& texels, const std::vector<uint16_t>& halves,
                             const std::vector<float>& axisTable) {
    gpu::Device& device = *services_->device;
    gpu::ImageDesc fd;
    fd.type = VK_IMAGE_TYPE_3D;
    fd.viewType = VK_IMAGE_VIEW_TYPE_3D;
    fd.format = settings_.halfField ? VK_FORMAT_R16_SFLOAT : VK_FORMAT_R32_SFLOAT;
    fd.extent = {uint32_t(lonAxis_.size()), uint32_t(field_.ny()), uint32_t(field_.nz() * timeSteps())};
    fd.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    fd.name = "volume field";
    fieldImage_ = gpu::Image(device, fd);
    std::vector<uint16_t> tf = transferTexels();
    updateOccupancy();
    occupancyBuffer_ = gpu::Buffer(device, occupancy_.size() * sizeof(uint32_t),
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   gpu::MemoryUsage::GpuOnly, "volume brick bits");
    gpu::ImageDesc td;
    td.type = VK_IMAGE_TYPE_1D;
    td.viewType = VK_IMAGE_VIEW_TYPE_1D;
    td.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    td.extent = {shader::kVolumeTransferSize, 1, 1};
    td.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    td.name = "volume transfer function";
    transferImage_ = gpu::Image(device, td);
    axisBuffer_ = gpu::Buffer(device, axisTable.size() * sizeof(float),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              gpu::MemoryUsage::GpuOnly, "volume axis tables");
    gpu::Uploader& uploader = *services_->uploader;
    device.runOnce([&](VkCommandBuffer cmd) {
        if (settings_.halfField) uploader.toImage(cmd, fieldImage_, halves.data(), halves.size() * sizeof(uint16_t));
        else uploader.toImage(cmd, fieldImage_, texels.data(), texels.size() * sizeof(float));
        uploader.toImage(cmd, transferImage_, tf.data(), tf.size() * sizeof(uint16_t));
        uploader.toBuffer(cmd, axisBuffer_, axisTable.data(), axisTable.size() * sizeof(float));
        uploader.toBuffer(cmd, occupancyBuffer_, occupancy_.data(), occupancy_.size() * sizeof(uint32_t));
        gpu::bufferBarrier(cmd, occupancyBuffer_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
        gpu::transition(cmd, fieldImage_, gpu::ImageUse::SampledCompute);
        gpu::transition(cmd, transferImage_, gpu::ImageUse::SampledCompute);
        gpu::bufferBarrier(cmd, axisBuffer_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    });
}

gpu::Specialization VolumeLayer::rayCasterModes(int pass) {
    gpu::Specialization modes;
    modes.set<VkBool32>(shader::kVolumeSpecDvr, settings_.dvr ? VK_TRUE : VK_FALSE);
    modes.set<int32_t>(shader::kVolumeSpecIsoCount, int32_t(settings_.isovalues.size()));
    modes.set<int32_t>(shader::kVolumeSpecSliceCount, int32_t(settings_.slices.size()));
    modes.set<VkBool32>(shader::kVolumeSpecHitOutput, hitOutput_ ? VK_TRUE : VK_FALSE);
    modes.set<VkBool32>(shader::kVolumeSpecRefine, refine_ ? VK_TRUE : VK_FALSE);
    const bool blends = !moreTimeSteps_.empty() && timeStepTimes_.size() > 1 && settings_.timeMode == VolumeSettings::TimeMode::Blend;
    modes.set<VkBool32>(shader::kVolumeSpecBlendTimeSteps, blends ? VK_TRUE : VK_FALSE);
    // The brick test costs on every sample (~15 % on lavapipe): it is compiled in only when at
    // least 1 brick in 16 can be skipped with the scene's settings (live edits keep the choice).
    if (!skippingDecided_) {
        size_t visibleBricks = 0;
        for (uint32_t word : occupancy_) visibleBricks += size_t(std::popcount(word));
        skipEmpty_ = settings_.emptySkipping && (bricks_.minMax.size() - visibleBricks) * 16 >= bricks_.minMax.size();
        skippingDecided_ = true;
    }
    modes.set<VkBool32>(shader::kVolumeSpecSkipEmpty, skipEmpty_ ? VK_TRUE : VK_FALSE);
    int32_t uniformAxes = 0;
    for (int axis = 0; axis < 3; ++axis) uniformAxes |= lookups_[size_t(axis)].uniform ? 1 << axis : 0;
    modes.set<int32_t>(shader::kVolumeSpecUniformAxes, uniformAxes);
    modes.set<VkBool32>(shader::kVolumeSpecPreIntegrate, preIntegrates() ? VK_TRUE : VK_FALSE);
    modes.set<int32_t>(shader::kVolumeSpecPass, pass);
    return modes;
}

void VolumeLayer::createRayCaster() {
    gpu::Device& device = *services_->device;
    linearSampler_ = gpu::createSampler(device, {.filter = VK_FILTER_LINEAR});
    nearestSampler_ = gpu::createSampler(device, {.filter = VK_FILTER_NEAREST});
    const uint32_t frames = services_->framesInFlight;
    descriptors_ = gpu::createDescriptorSets(device, shader::kVolumeBindings, frames);
    for (uint32_t f = 0; f < frames; ++f) {
        setVersion_.push_back(0);
        uniformBuffers_.emplace_back(device, sizeof(shader::VolumeUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                     gpu::MemoryUsage::Upload, "volume uniforms");
    }
    // The shaders' sets in order: the frame's, then the volume's.
    static_assert(shader::kFrameSet == 0 && shader::kVolumeSet == 1, "setLayouts and the binds list the sets in order");
    const VkDescriptorSetLayout setLayouts[] = {services_->frameSetLayout, descriptors_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, setLayouts, {});
    // Without measurement the hit image is a 1 x 1 stand-in that is never written.
    gpu::ImageDesc hd;
    hd.format = VK_FORMAT_R32_SFLOAT;
    hd.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    hd.name = "volume hit distances";
    hitImage_ = gpu::Image(device, hd);
    // Without reduced-resolution rays the reduced image is a 1 x 1 stand-in that is never written.
    gpu::ImageDesc ld;
    ld.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    ld.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    ld.name = "volume reduced-resolution rays";
    lowImage_ = gpu::Image(device, ld);
    createCastPipelines();
}

bool VolumeLayer::preIntegrates() const { return settings_.preIntegration && settings_.dvr; }

bool VolumeLayer::reducedRays() const { return settings_.rayResolution < 1.0 && !hitOutput_; }

void VolumeLayer::createCastPipelines() {
    gpu::Device& device = *services_->device;
    // The old pipelines are retired after their frames.
    const gpu::Specialization modes = rayCasterModes(reducedRays() ? shader::kVolumePassLowRes : shader::kVolumePassFull);
    castPipeline_ = gpu::createComputePipeline(device, layout_.vk(), kSpv_volume_raycast_comp, &modes, "volume ray cast");
    if (reducedRays()) {
        const gpu::Specialization refine = rayCasterModes(shader::kVolumePassRefine);
        refinePipeline_ = gpu::createComputePipeline(device, layout_.vk(), kSpv_volume_raycast_comp, &refine,
                                                     "volume ray cast refine");
    } else {
        refinePipeline_ = gpu::Pipeline();
    }
    pipelineDirty_ = false;
}

void VolumeLayer::ensureCastImage(uint32_t width, uint32_t height) {
    // The reduced image: the image's size times rayResolution, rounded up (1 x 1 when unused).
    const uint32_t lowW = reducedRays() ? std::max(1u, uint32_t(std::ceil(width * settings_.rayResolution))) : 1u;
    const uint32_t lowH = reducedRays() ? std::max(1u, uint32_t(std::ceil(height * settings_.rayResolution))) : 1u;
    if (lowImage_.extent().width != lowW || lowImage_.extent().height != lowH) {
        gpu::ImageDesc ld = lowImage_.desc();
        ld.extent = {lowW, lowH, 1};
        lowImage_ = gpu::Image(*services_->device, ld);   // the old one is retired after its frames
        ++imagesVersion_;
    }
    if (castImage_ && castImage_.extent().width == width && castImage_.extent().height == height) return;
    gpu::ImageDesc d;
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    d.extent = {width, height, 1};
    d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    d.name = "volume ray-cast image";
    castImage_ = gpu::Image(*services_->device, d);   // the old one is retired after its frames
    if (hitOutput_) {
        gpu::ImageDesc hd = hitImage_.desc();
        hd.extent = {width, height, 1};
        hitImage_ = gpu::Image(*services_->device, hd);
        hitReadback_ = gpu::Buffer(*services_->device, uint64_t(width) * height * sizeof(float),
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "volume hit readback");
    }
    ++imagesVersion_;
}

void VolumeLayer::writeDescriptors(uint32_t f) {
    gpu::DescriptorWriter(descriptors_.sets[f])
        .uniformBuffer(shader::kVolumeBindingUniforms, uniformBuffers_[f], 0, sizeof(shader::VolumeUniforms))
        .sampledImage(shader::kVolumeBindingField, linearSampler_.vk(), fieldImage_.view())
        .storageBuffer(shader::kVolumeBindingAxes, axisBuffer_)
        .sampledImage(shader::kVolumeBindingTransfer, linearSampler_.vk(), transferImage_.view())
        .sampledImage(shader::kVolumeBindingSceneDepth, nearestSampler_.vk(), boundDepth_->view())
        .storageImage(shader::kVolumeBindingCastImage, castImage_.view())
        .sampledImage(shader::kVolumeBindingCastSampled, nearestSampler_.vk(), castImage_.view())
        .storageImage(shader::kVolumeBindingHits, hitImage_.view())
        .storageBuffer(shader::kVolumeBindingBricks, occupancyBuffer_)
        .sampledImage(shader::kVolumeBindingPreIntegrated, linearSampler_.vk(), preImage_.view())
        .storageImage(shader::kVolumeBindingLowRes, lowImage_.view())
        .update(*services_->device);
}

// ---------------------------------------------------------------------------------------------
// Frames

void VolumeLayer::update(const scene::FrameContext& frame) {
    ++frameCounter_;
    timeStepA_ = timeStepB_ = timeStepWeight_ = 0.0f;
    if (timeStepTimes_.size() < 2 || settings_.timeMode == VolumeSettings::TimeMode::Fixed) return;
    const TimeNs t = frame.time;
    const size_t last = timeStepTimes_.size() - 1;
    if (t <= timeStepTimes_.front()) return;
    if (t >= timeStepTimes_.back()) {
        timeStepA_ = timeStepB_ = float(last);
        return;
    }
    const size_t i = size_t(std::upper_bound(timeStepTimes_.begin(), timeStepTimes_.end(), t) - timeStepTimes_.begin()) - 1;
    const double w = double(t - timeStepTimes_[i]) / double(timeStepTimes_[i + 1] - timeStepTimes_[i]);
    if (settings_.timeMode == VolumeSettings::TimeMode::Nearest) {
        timeStepA_ = timeStepB_ = float(w < 0.5 ? i : i + 1);
    } else {
        timeStepA_ = float(i);
        timeStepB_ = float(i + 1);
        timeStepWeight_ = float(w);
    }
}

void VolumeLayer::recordCompute(scene::Pass, const render::RecordContext& rc) {
    const scene::FrameContext& frame = *rc.frame;
    if (pipelineDirty_) createCastPipelines();
    ensureCastImage(frame.width, frame.height);
    ensurePreIntegrationImage();
    if (boundDepth_ != rc.sceneDepth) {
        boundDepth_ = rc.sceneDepth;
        ++imagesVersion_;
    }
    // Each frame slot's set is rewritten when the images it names changed; the slot's previous
    // frame has completed by now (the frame ring waited for it).
    if (setVersion_[rc.slot] != imagesVersion_) {
        writeDescriptors(rc.slot);
        setVersion_[rc.slot] = imagesVersion_;
    }
    const shader::VolumeUniforms u = packVolumeUniforms(frameInputs(*frame.camera));
    uniformBuffers_[rc.slot].write(&u, sizeof(u));

    VkCommandBuffer cmd = rc.cmd;
    recordEdits(cmd);
    recordDispatches(cmd, rc, frame.width, frame.height);
    gpu::transition(cmd, castImage_, gpu::ImageUse::SampledFragment);
    if (hitOutput_) recordHitReadback(cmd, frame.width, frame.height);
}

VolumeFrameInputs VolumeLayer::frameInputs(const scene::Camera& camera) const {
    const glm::dmat4 view = camera.viewRotation();
    return {
        .settings = settings_,
        .box = box_,
        .lonRange = {lonAxis_.front(), lonAxis_.back()},
        .latRange = {field_.latDeg.front(), field_.latDeg.back()},
        .heightRange = {field_.heightM.front(), field_.heightM.back()},
        .samples = glm::uvec3(lonAxis_.size(), field_.ny(), field_.nz()),
        .bricks = glm::uvec3(bricks_.bx, bricks_.by, bricks_.bz),
        .brickSize = uint32_t(bricks_.size),
        .valueScale = fieldScale_,
        .timeSteps = timeSteps(),
        .timeBlend = timeBlend(),
        .eye = camera.position(),
        .forward = -glm::dvec3(view[0][2], view[1][2], view[2][2]),
        .nearPlane = camera.nearPlane(),
        .frame = frameCounter_,
    };
}

void VolumeLayer::recordEdits(VkCommandBuffer cmd) {
    if (transferDirty_) {
        // After the earlier frames' reads (the transitions wait for them); before this frame's.
        const std::vector<uint16_t> tf = transferTexels();
        services_->uploader->toImage(cmd, transferImage_, tf.data(), tf.size() * sizeof(uint16_t));
        gpu::transition(cmd, transferImage_, gpu::ImageUse::SampledCompute);
        transferDirty_ = false;
        occupancyDirty_ = true;
        preDirty_ = true;
    }
    if (preDirty_) {
        const std::vector<uint16_t> texels = preIntegrationTexels();
        services_->uploader->toImage(cmd, preImage_, texels.data(), texels.size() * sizeof(uint16_t));
        gpu::transition(cmd, preImage_, gpu::ImageUse::SampledCompute);
        preDirty_ = false;
    }
    if (occupancyDirty_ && !skipEmpty_) occupancyDirty_ = false;   // the pipeline never reads the bits
    if (occupancyDirty_) {
        // After the earlier frames' reads; before this frame's.
        updateOccupancy();
        gpu::bufferBarrier(cmd, occupancyBuffer_, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                           VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        vkCmdUpdateBuffer(cmd, occupancyBuffer_.vk(), 0, occupancy_.size() * sizeof(uint32_t), occupancy_.data());
        gpu::bufferBarrier(cmd, occupancyBuffer_, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
}

void VolumeLayer::recordDispatches(VkCommandBuffer cmd, const render::RecordContext& rc, uint32_t width, uint32_t height) {
    const gpu::ImageTransition writes[] = {{&castImage_, gpu::ImageUse::StorageCompute},
                                           {&hitImage_, gpu::ImageUse::StorageCompute},
                                           {&lowImage_, gpu::ImageUse::StorageCompute}};
    gpu::transition(cmd, writes);
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.vk(), shader::kFrameSet,
                            uint32_t(std::size(sets)), sets, 0, nullptr);
    const uint32_t g = shader::kVolumeGroupSize;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, castPipeline_.vk());
    if (reducedRays()) {
        // The reduced rays, then (after their writes) the full-resolution pass that reads them.
        vkCmdDispatch(cmd, (lowImage_.extent().width + g - 1) / g, (lowImage_.extent().height + g - 1) / g, 1);
        gpu::transition(cmd, lowImage_, gpu::ImageUse::StorageCompute);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, refinePipeline_.vk());
    }
    vkCmdDispatch(cmd, (width + g - 1) / g, (height + g - 1) / g, 1);
}

void VolumeLayer::ensurePreIntegrationImage() {
    const bool on = preIntegrates();
    const uint32_t side = on ? shader::kVolumeTransferSize : 1u;
    if (preImage_ && preImage_.extent().width == side) return;
    gpu::ImageDesc d;
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    d.extent = {side, side, 1};
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    d.name = on ? "volume pre-integrated transfer function" : "volume pre-integration stand-in";
    preImage_ = gpu::Image(*services_->device, d);   // the old one is retired after its frames
    preDirty_ = true;
    ++imagesVersion_;
}

std::vector<uint16_t> VolumeLayer::preIntegrationTexels() const {
    if (!preIntegrates()) return std::vector<uint16_t>(4, 0);
    const double step = std::sqrt(3.0) / double(settings_.steps);   // the march's normalised step
    const std::vector<std::array<float, 4>> table = buildPreIntegratedTable(transferTable_, step, 1.0 / settings_.opacityUnit);
    std::vector<uint16_t> texels(table.size() * 4);
    for (size_t t = 0; t < table.size(); ++t)
        for (size_t c = 0; c < 4; ++c) texels[t * 4 + c] = halfFloat(table[t][c]);
    return texels;
}

void VolumeLayer::recordHitReadback(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
    gpu::transition(cmd, hitImage_, gpu::ImageUse::TransferSrc);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width, height, 1};
    vkCmdCopyImageToBuffer(cmd, hitImage_.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, hitReadback_.vk(), 1, &region);
    gpu::bufferBarrier(cmd, hitReadback_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

std::vector<float> VolumeLayer::hitDistances() const {
    if (!hitOutput_ || !hitReadback_) return {};
    const_cast<gpu::Buffer&>(hitReadback_).invalidate();
    const auto* p = static_cast<const float*>(hitReadback_.mapped());
    return std::vector<float>(p, p + hitReadback_.size() / sizeof(float));
}

glm::dvec3 VolumeLayer::voxelAt(const glm::dvec3& ecef) const {
    const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(ecef);
    const double first = lonAxis_.front();
    const double lon = first + std::fmod(std::fmod(g.lonDeg - first, 360.0) + 360.0, 360.0);
    const double coords[3] = {lon, g.latDeg, g.height / settings_.verticalExaggeration};
    static_assert(shader::kVolumeAxisLon == 0 && shader::kVolumeAxisLat == 1 && shader::kVolumeAxisHeight == 2,
                  "lookups_ and the result are in (lon, lat, height) order");
    const std::vector<double>* axes[3] = {&lonAxis_, &field_.latDeg, &field_.heightM};
    glm::dvec3 v(0.0);
    for (int a = 0; a < 3; ++a) v[a] = lookups_[a].exact(*axes[a], coords[a]) * double(axes[a]->size()) - 0.5;
    return v;
}

void VolumeLayer::record(scene::Pass, const render::RecordContext& rc) {
    if (!castImage_ || !boundDepth_) return;
    VkCommandBuffer cmd = rc.cmd;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, compositePipeline_.vk());
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet,
                            uint32_t(std::size(sets)), sets, 0, nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
}

uint64_t VolumeLayer::gpuBytes() const {
    uint64_t bytes = uint64_t(lonAxis_.size()) * field_.ny() * field_.nz() * (settings_.halfField ? 2 : 4) *
                         (1 + moreTimeSteps_.size()) + shader::kVolumeTransferSize * 8 +
                     3 * shader::kVolumeAxisTable * 4;
    if (castImage_) bytes += uint64_t(castImage_.extent().width) * castImage_.extent().height * 8;
    if (preImage_) bytes += uint64_t(preImage_.extent().width) * preImage_.extent().height * 8;
    if (lowImage_) bytes += uint64_t(lowImage_.extent().width) * lowImage_.extent().height * 8;
    return bytes;
}

bool VolumeLayer::setParameter(std::string_view name, double value) {
    if (name == "steps") {
        const int steps = std::clamp(int(std::lround(value)), int(kStepsRange.min), int(kStepsRange.max));
        preDirty_ = preDirty_ || steps != settings_.steps;   // the table's segment length
        settings_.steps = steps;
        return true;
    }
    // Isovalues and slice positions live in the per-frame uniforms: moving them re-uploads
    // nothing ("isovalue" is "isovalue0"; the count is fixed by the scene).
    const auto indexed = [&](std::string_view prefix, size_t count) -> std::optional<size_t> {
        if (name.substr(0, prefix.size()) != prefix) return std::nullopt;
        const std::string_view rest = name.substr(prefix.size());
        if (rest.empty()) return count > 0 ? std::optional<size_t>(0) : std::nullopt;
        if (rest.size() != 1 || rest[0] < '0' || rest[0] > '9') return std::nullopt;
        const size_t i = size_t(rest[0] - '0');
        return i < count ? std::optional<size_t>(i) : std::nullopt;
    };
    if (!std::isfinite(value)) return false;
    if (auto i = indexed("isovalue", settings_.isovalues.size())) {
        settings_.isovalues[*i] = value;
        occupancyDirty_ = true;
        return true;
    }
    if (name == "opacityUnit") {
        if (!kOpacityUnitRange.contains(value)) return false;
        settings_.opacityUnit = value;
        preDirty_ = true;
        return true;
    }
    if (name == "rangeMin" || name == "rangeMax") {
        auto& t = settings_.transfer;
        const double lo = name == "rangeMin" ? value : t.rangeMin, hi = name == "rangeMax" ? value : t.rangeMax;
        if (!(hi > lo)) return false;
        t.rangeMin = lo, t.rangeMax = hi;
        transferDirty_ = true;
        return true;
    }
    if (name == "opacityScale") {
        if (!kOpacityScaleRange.contains(value)) return false;
        settings_.transfer.opacityScale = value;
        transferDirty_ = true;
        return true;
    }
    if (name == "isoOpacity" || name == "sliceOpacity") {
        if (!kOpacityRange.contains(value)) return false;
        (name == "isoOpacity" ? settings_.isoOpacity : settings_.sliceOpacity) = value;
        return true;
    }
    if (name == "preIntegration") {
        const bool on = value != 0.0;
        pipelineDirty_ = pipelineDirty_ || on != settings_.preIntegration;
        settings_.preIntegration = on;
        return true;
    }
    if (name == "rayResolution") {
        if (!kRayResolutionRange.contains(value)) return false;
        const bool wasReduced = reducedRays();
        settings_.rayResolution = value;
        pipelineDirty_ = pipelineDirty_ || reducedRays() != wasReduced;
        return true;
    }
    if (name == "refineThreshold") {
        if (!kRefineThresholdRange.contains(value)) return false;
        settings_.refineThreshold = value;
        return true;
    }
    if (name == "emptySkipping") {
        settings_.emptySkipping = value != 0.0;
        occupancyDirty_ = true;
        return true;
    }
    if (auto i = indexed("slice", settings_.slices.size())) {
        auto& sl = settings_.slices[*i];
        sl.value = sl.axis == VolumeSettings::Slice::Axis::Lat ? kSliceLatitudeRange.clamp(value) : value;
        return true;
    }
    return false;
}

std::vector<scene::LayerSetting> VolumeLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    // Data-valued settings slide over the data's extent, widened to hold the current value.
    const auto span = [](double lo, double hi, double value) { return std::pair(std::min(lo, value), std::max(hi, value)); };
    const bool hasData = field_.validCount > 0;
    const double dataMin = hasData ? field_.minValue : 0.0, dataMax = hasData ? field_.maxValue : 1.0;
    const auto& t = settings_.transfer;
    const auto [lo, hi] = span(std::min(dataMin, t.rangeMin), std::max(dataMax, t.rangeMax), t.rangeMin);
    std::vector<scene::LayerSetting> out = {
        {.name = "steps", .label = "Ray steps (per box diagonal)", .kind = Kind::Integer,
         .value = double(settings_.steps), .min = kStepsRange.min, .max = kStepsRange.max, .logarithmic = true},
        {.name = "opacityScale", .label = "Opacity scale", .kind = Kind::Number, .value = t.opacityScale,
         .min = kOpacityScaleRange.min, .max = kOpacityScaleRange.max, .logarithmic = true},
        {.name = "opacityUnit", .label = "Opacity unit distance (box diagonals)", .kind = Kind::Number,
         .value = settings_.opacityUnit, .min = kOpacityUnitRange.min, .max = kOpacityUnitRange.max, .logarithmic = true},
        {.name = "rangeMin", .label = "Colour range low", .kind = Kind::Number, .value = t.rangeMin, .min = lo, .max = hi,
         .pointer = "/range/0"},
        {.name = "rangeMax", .label = "Colour range high", .kind = Kind::Number, .value = t.rangeMax, .min = lo, .max = hi,
         .pointer = "/range/1"},
        {.name = "colorMap", .label = "Colour map", .kind = Kind::Choice, .choice = t.colorMap, .choices = colorMapNames()},
        {.name = "emptySkipping", .label = "Skip empty bricks", .kind = Kind::Toggle,
         .value = settings_.emptySkipping ? 1.0 : 0.0},
    };
    for (size_t i = 0; i < settings_.isovalues.size(); ++i) {
        const auto [a, b] = span(dataMin, dataMax, settings_.isovalues[i]);
        out.push_back({.name = "isovalue" + std::to_string(i), .label = "Isovalue " + std::to_string(i + 1),
                       .kind = Kind::Number, .value = settings_.isovalues[i], .min = a, .max = b,
                       .pointer = "/isovalues/" + std::to_string(i)});
    }
    if (!settings_.isovalues.empty())
        out.push_back({.name = "isoOpacity", .label = "Isosurface opacity", .kind = Kind::Number,
                       .value = settings_.isoOpacity, .min = kOpacityRange.min, .max = kOpacityRange.max});
    for (size_t i = 0; i < settings_.slices.size(); ++i) {
        const VolumeSettings::Slice& sl = settings_.slices[i];
        using Axis = VolumeSettings::Slice::Axis;
        const std::vector<double>& axis = sl.axis == Axis::Lon ? field_.lonDeg : sl.axis == Axis::Lat ? field_.latDeg : field_.heightM;
        auto [a, b] = axis.empty() ? std::pair(sl.value, sl.value)
                                   : span(std::min(axis.front(), axis.back()), std::max(axis.front(), axis.back()), sl.value);
        if (sl.axis == Axis::Lat) a = std::max(a, kSliceLatitudeRange.min), b = std::min(b, kSliceLatitudeRange.max);
        const char* what = sl.axis == Axis::Lon ? " longitude (deg)" : sl.axis == Axis::Lat ? " latitude (deg)" : " height (m)";
        const char* key = sl.axis == Axis::Lon ? "lon" : sl.axis == Axis::Lat ? "lat" : "height";   // {"lat": 45}
        out.push_back({.name = "slice" + std::to_string(i), .label = "Slice " + std::to_string(i + 1) + what,
                       .kind = Kind::Number, .value = sl.value, .min = a, .max = b,
                       .pointer = "/slices/" + std::to_string(i) + "/" + key});
    }
    // The opacity curve over the colour range, drawn on the colour map (the transfer table's
    // colours; an empty list is the default ramp).
    scene::LayerSetting curve{.name = "opacity", .label = "Opacity (value, alpha)", .kind = Kind::Curve};
    if (t.opacity.empty()) curve.points = {{t.rangeMin, 0.0}, {t.rangeMax, 1.0}};
    for (const OpacityPoint& p : t.opacity) curve.points.push_back({p.value, p.alpha});
    curve.min = std::min(t.rangeMin, curve.points.front().x);
    curve.max = std::max(t.rangeMax, curve.points.back().x);
    if (auto table = buildTransferTable(TransferFunctionDesc{t.colorMap, curve.min, curve.max, {}, 1.0}, 64))
        for (const auto& c : *table) curve.gradient.push_back({c[0], c[1], c[2]});
    out.push_back(std::move(curve));
    if (!settings_.slices.empty())
        out.push_back({.name = "sliceOpacity", .label = "Slice opacity", .kind = Kind::Number,
                       .value = settings_.sliceOpacity, .min = kOpacityRange.min, .max = kOpacityRange.max});
    out.push_back({.name = "rayResolution", .label = "Ray resolution (of the image's)", .kind = Kind::Number,
                   .value = settings_.rayResolution, .min = kRayResolutionRange.min, .max = kRayResolutionRange.max});
    if (settings_.rayResolution < 1.0)
        out.push_back({.name = "refineThreshold", .label = "Refine where rays differ by", .kind = Kind::Number,
                       .value = settings_.refineThreshold, .min = kRefineThresholdRange.min, .max = kRefineThresholdRange.max});
    if (settings_.dvr)
        out.push_back({.name = "preIntegration", .label = "Pre-integrated transfer function", .kind = Kind::Toggle,
                       .value = settings_.preIntegration ? 1.0 : 0.0});
    return out;
}

std::vector<uint16_t> VolumeLayer::transferTexels() {
    auto table = buildTransferTable(settings_.transfer, shader::kVolumeTransferSize);
    if (table) transferTable_ = std::move(table).value();   // (the settings were checked: it builds)
    // Colour, and log2(1 - alpha) for the ray caster's opacity correction (one exp2 a sample).
    std::vector<uint16_t> tf(transferTable_.size() * 4);
    for (size_t t = 0; t < transferTable_.size(); ++t) {
        for (size_t c = 0; c < 3; ++c) tf[t * 4 + c] = halfFloat(transferTable_[t][c]);
        tf[t * 4 + 3] = halfFloat(float(std::log2(1.0 - std::min(double(transferTable_[t][3]), 0.9999))));
    }
    return tf;
}

void VolumeLayer::updateOccupancy() {
    occupancy_ = brickOccupancy(bricks_, transferTable_, settings_.transfer.rangeMin, settings_.transfer.rangeMax,
                                settings_.dvr, settings_.isovalues);
    if (!settings_.emptySkipping) std::fill(occupancy_.begin(), occupancy_.end(), ~0u);
    if (occupancy_.empty()) occupancy_.push_back(0u);
    occupancyDirty_ = false;
}

bool VolumeLayer::setOption(std::string_view name, std::string_view value) {
    if (name != "colorMap" || !hasColorMap(std::string(value))) return false;
    settings_.transfer.colorMap = std::string(value);
    transferDirty_ = true;
    return true;
}

bool VolumeLayer::setCurve(std::string_view name, const std::vector<glm::dvec2>& points) {
    if (name != "opacity" || points.empty() || points.size() > kMaxOpacityPoints) return false;
    std::vector<OpacityPoint> opacity;
    for (const glm::dvec2& p : points) {
        if (!std::isfinite(p.x) || !(p.y >= 0.0 && p.y <= 1.0)) return false;
        opacity.push_back({p.x, p.y});
    }
    std::stable_sort(opacity.begin(), opacity.end(), [](const OpacityPoint& a, const OpacityPoint& b) { return a.value < b.value; });
    settings_.transfer.opacity = std::move(opacity);
    transferDirty_ = true;
    return true;
}

std::string VolumeLayer::status() const {
    return field_.variable + ": " + std::to_string(field_.nx()) + " x " + std::to_string(field_.ny()) + " x " +
           std::to_string(field_.nz()) + ", " + std::to_string(settings_.steps) + " steps";
}

}  // namespace orbis::layers
