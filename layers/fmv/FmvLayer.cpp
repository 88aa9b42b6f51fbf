#include "layers/fmv/FmvLayer.h"

#include "base/Color.h"
#include "base/Log.h"
#include "base/ThreadPool.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Uploader.h"
#include "engine/render/RenderContext.h"
#include "globe/Ellipsoid.h"
#include "shared/FmvTypes.h"
#include "shared/FrameUniforms.h"
#include "spv/common/composite.frag.h"
#include "spv/common/fullscreen.vert.h"
#include "spv/fmv/drape.comp.h"
#include "spv/fmv/footprint.comp.h"
#include "spv/fmv/lines.frag.h"
#include "spv/fmv/lines.vert.h"
#include "spv/fmv/sensordepth.frag.h"
#include "spv/fmv/sensordepth.vert.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <cmath>
#include <cstdio>

namespace orbis::layers {

// The pipeline layouts list the sets in order: the frame's, then the layer's.
static_assert(shader::kFmvSet == shader::kFrameSet + 1);

namespace {

constexpr double kMapFovPad = 1.05;        // the distance map sees a little more than the video
constexpr double kMaxHalfSize = 30000.0;   // the heightfield covers at most 60 km a side
constexpr double kSensorNear = 1.0;        // metres: the distance map's near plane

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }

/// The convex hull of `points` (Andrew's monotone chain, counter-clockwise in pixel
/// coordinates) as edge equations (nx, ny, c: inside when nx x + ny y + c >= 0), each edge moved
/// out by `margin`; none for a hull of more than the shader's kFmvHullEdges edges.
std::vector<glm::vec3> hullEdges(std::vector<glm::dvec2> points, double margin) {
    std::vector<glm::vec3> edges;
    std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    const auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    std::vector<glm::dvec2> hull(2 * points.size());
    size_t k = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    for (size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    hull.resize(k > 0 ? k - 1 : 0);
    if (hull.size() >= 3 && hull.size() <= shader::kFmvHullEdges) {
        for (size_t i = 0; i < hull.size(); ++i) {
            const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
            const glm::dvec2 e = b - a;
            const double len = glm::length(e);
            if (len < 1e-9) continue;
            const glm::dvec2 n(-e.y / len, e.x / len);   // inward for a counter-clockwise polygon
            edges.push_back(glm::vec3(glm::vec2(n), float(-glm::dot(n, a) + margin)));
        }
    }
    return edges;
}

}  // namespace

fmv::SensorPose applyOffset(const fmv::SensorPose& pose, const PoseOffset& o) {
    fmv::SensorPose p = pose;
    // Angles into [-180, 180) as longitudes are (heading into [0, 360)).
    p.platformHeadingDeg = globe::wrapLongitude(p.platformHeadingDeg + o.headingDeg - 180.0) + 180.0;
    p.platformPitchDeg = globe::wrapLongitude(p.platformPitchDeg + o.pitchDeg);
    p.platformRollDeg = globe::wrapLongitude(p.platformRollDeg + o.rollDeg);
    p.height += o.altitude;
    return p;
}

FmvLayer::FmvLayer(std::shared_ptr<fmv::VideoFile> video, fmv::FmvTimeline timeline, FmvSettings settings)
    : video_(std::move(video)), timeline_(std::move(timeline)), settings_(settings), startUtc_(settings.startUtc.value_or(0.0)) {}

FmvLayer::FmvLayer(std::unique_ptr<fmv::LiveVideo> live, FmvSettings settings) : live_(std::move(live)), settings_(settings) {}

FmvLayer::~FmvLayer() = default;

// ---------------------------------------------------------------------------------------------
// GPU objects
void FmvLayer::onPrepare(const render::RenderServices& services) {
    services_ = services;
    gpu::Device& device = *services.device;
    linearSampler_ = gpu::createSampler(device, {.filter = VK_FILTER_LINEAR});
    nearestSampler_ = gpu::createSampler(device, {.filter = VK_FILTER_NEAREST});

    const uint32_t frames = services.framesInFlight;
    descriptors_ = gpu::createDescriptorSets(device, shader::kFmvBindings, frames);
    setVersion_.assign(frames, 0);
    for (uint32_t f = 0; f < frames; ++f)
        uniforms_.emplace_back(device, sizeof(shader::FmvUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Upload,
                               "fmv uniforms");
    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(shader::FmvDistancePush)};
    const VkDescriptorSetLayout setLayouts[] = {services.frameSetLayout, descriptors_.layout.vk()};
    layout_ = gpu::createPipelineLayout(device, setLayouts, {&push, 1});
    createImages(device);
    createGrid(services);
    buildPipelines(services);
    if (video_) frames_ = std::make_unique<fmv::FramePrefetcher>(video_, services.jobs(), 4);
    gpuReady_ = true;
}

void FmvLayer::createImages(gpu::Device& device) {
    // The video frame, the heightfield, the distance map (colour: metres; depth).
    const auto image = [&](VkFormat format, uint32_t w, uint32_t h, VkImageUsageFlags usage, const char* name) {
        gpu::ImageDesc d;
        d.format = format;
        d.extent = {w, h, 1};
        d.usage = usage;
        d.name = name;
        return gpu::Image(device, d);
    };
    const VkImageUsageFlags sampledDst = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    // A live stream's frames have their size once they come (ensureFrameImage); until then a
    // pixel stands in, for the descriptors.
    frameImage_ = image(VK_FORMAT_R8G8B8A8_SRGB, video_ ? uint32_t(video_->info().width) : 1u,
                        video_ ? uint32_t(video_->info().height) : 1u, sampledDst, "fmv video frame");
    const uint32_t n = uint32_t(settings_.heightfieldSize), m = uint32_t(settings_.distanceMapSize);
    heightImage_ = image(VK_FORMAT_R32_SFLOAT, n, n, sampledDst, "fmv heightfield");
    distanceImage_ = image(VK_FORMAT_R32_SFLOAT, m, m, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                           "fmv distance map");
    distanceDepth_ = image(VK_FORMAT_D32_SFLOAT, m, m, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "fmv distance map depth");
}

void FmvLayer::createGrid(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    const uint32_t n = uint32_t(settings_.heightfieldSize);
    // The heightfield's grid: two triangles a cell; positions rewritten with the heights.
    std::vector<uint32_t> indices;
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i) {
            const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            indices.insert(indices.end(), {a, c, b, b, c, d});
        }
    gridIndexCount_ = uint32_t(indices.size());
    gridIndices_ = gpu::Buffer(device, indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               gpu::MemoryUsage::GpuOnly, "fmv grid indices");
    device.runOnce([&](VkCommandBuffer cmd) {
        services.uploader->toBuffer(cmd, gridIndices_, indices.data(), indices.size() * sizeof(uint32_t));
        gpu::bufferBarrier(cmd, gridIndices_, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT);
    });
    gridVertices_ = gpu::Buffer(device, size_t(n) * n * sizeof(glm::vec3), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                gpu::MemoryUsage::GpuOnly, "fmv grid vertices");
    footprintBuffer_ = gpu::Buffer(device, shader::kFmvFootprintRays * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                   gpu::MemoryUsage::Readback, "fmv footprint");
}

void FmvLayer::buildPipelines(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    drapePipeline_ = gpu::createComputePipeline(device, layout_.vk(), kSpv_fmv_drape_comp, nullptr, "fmv drape");
    footprintPipeline_ = gpu::createComputePipeline(device, layout_.vk(), kSpv_fmv_footprint_comp, nullptr, "fmv footprint");
    gpu::GraphicsPipelineDesc dist;
    dist.vertexSpirv = kSpv_fmv_sensordepth_vert;
    dist.fragmentSpirv = kSpv_fmv_sensordepth_frag;
    dist.layout = layout_.vk();
    dist.bindings = {{0, sizeof(glm::vec3), VK_VERTEX_INPUT_RATE_VERTEX}};
    dist.attributes = {{shader::kFmvInputPosition, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    dist.cullMode = VK_CULL_MODE_NONE;
    dist.colorFormat = VK_FORMAT_R32_SFLOAT;
    dist.depthFormat = VK_FORMAT_D32_SFLOAT;
    dist.name = "fmv distance map";
    distancePipeline_ = gpu::createGraphicsPipeline(device, dist);
    gpu::GraphicsPipelineDesc composite;
    composite.vertexSpirv = kSpv_common_fullscreen_vert;
    composite.fragmentSpirv = kSpv_common_composite_frag;
    composite.layout = layout_.vk();
    composite.cullMode = VK_CULL_MODE_NONE;
    composite.depthTest = composite.depthWrite = false;
    composite.alphaBlend = true;
    composite.colorFormat = services.colorFormat;
    composite.depthFormat = services.depthFormat;
    composite.name = "fmv composite";
    compositePipeline_ = gpu::createGraphicsPipeline(device, composite);
    for (bool frustum : {false, true}) {
        gpu::Specialization spec;
        spec.set<VkBool32>(shader::kFmvSpecFrustum, frustum ? VK_TRUE : VK_FALSE);
        gpu::GraphicsPipelineDesc lines;
        lines.vertexSpirv = kSpv_fmv_lines_vert;
        lines.fragmentSpirv = kSpv_fmv_lines_frag;
        lines.layout = layout_.vk();
        lines.topology = frustum ? VK_PRIMITIVE_TOPOLOGY_LINE_LIST : VK_PRIMITIVE_TOPOLOGY_LINE_STRIP;
        lines.cullMode = VK_CULL_MODE_NONE;
        lines.depthWrite = false;
        lines.colorFormat = services.colorFormat;
        lines.depthFormat = services.depthFormat;
        lines.specialization = &spec;
        lines.name = frustum ? "fmv frustum" : "fmv footprint outline";
        (frustum ? frustumPipeline_ : outlinePipeline_) = gpu::createGraphicsPipeline(device, lines);
    }
}

// ---------------------------------------------------------------------------------------------
// Each frame: the video frame and pose for the scene's time, and the ground around the view
void FmvLayer::update(const scene::FrameContext& frame) {
    pendingFrame_ = nullptr;
    active_ = false;
    wantedShown_ = true;
    if (live_) return updateLive(frame);
    if (!gpuReady_ || video_->frameCount() == 0) return;
    eye_ = frame.camera->position();
    const double t = toSeconds(frame.time) - startUtc_;
    if (t < 0.0 || t >= video_->info().duration) return;   // the video is not playing now
    wantedIndex_ = video_->frameAt(t);
    pose_ = applyOffset(timeline_.poseAt(t), settings_.offset);
    if (const fmv::VideoFrame* f = frames_->request(wantedIndex_)) {
        if (!shownIndex_ || *shownIndex_ != f->index) pendingFrame_ = f;
    }
    wantedShown_ = (pendingFrame_ && pendingFrame_->index == wantedIndex_) || (shownIndex_ && *shownIndex_ == wantedIndex_);
    if (!frames_->error().empty()) wantedShown_ = true;   // a damaged video: show what there is, do not wait
    active_ = shownIndex_.has_value() || pendingFrame_ != nullptr;
    if (active_) updateHeightfield(frame);
}

/// A live stream runs on the wall clock: the frame due now (LiveVideo's jitter buffer) with the
/// pose of its own time. The layer never waits for it (not busy).
void FmvLayer::updateLive(const scene::FrameContext& frame) {
    liveStats_ = live_->stats();
    if (!gpuReady_) return;
    eye_ = frame.camera->position();
    const std::optional<fmv::LiveFrame> due = live_->due(fmv::wallClockSeconds());
    noSignal_ = liveStats_.state != fmv::LiveState::Live;
    if (!due || !due->pose) return;   // nothing yet, or no KLV pose for it yet
    pose_ = applyOffset(*due->pose, settings_.offset);
    liveFrameUtc_ = due->utc;
    if (!shownIndex_ || *shownIndex_ != due->frame->index) {
        liveFrame_ = due->frame;
        ensureFrameImage(liveFrame_->width, liveFrame_->height);
        pendingFrame_ = liveFrame_.get();
    }
    active_ = true;
    updateHeightfield(frame);
}

void FmvLayer::ensureFrameImage(int width, int height) {
    if (frameImage_ && frameImage_.extent().width == uint32_t(width) && frameImage_.extent().height == uint32_t(height)) return;
    gpu::ImageDesc d;
    d.format = VK_FORMAT_R8G8B8A8_SRGB;
    d.extent = {uint32_t(width), uint32_t(height), 1};
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    d.name = "fmv video frame";
    frameImage_ = gpu::Image(*services_.device, d);   // the old one is retired after its last use
    ++imagesVersion_;
}

void FmvLayer::updateHeightfield(const scene::FrameContext& frame) {
    // Where the sensor looks, roughly: its rays on the ellipsoid raised to the ground under it.
    const fmv::SensorCamera camera(pose_);
    // Heights not known yet (the terrain still loading there) count as 0 and keep the
    // heightfield refreshing.
    bool unknown = false;
    const auto groundAt = [&](double lon, double lat) {
        const std::optional<double> h = frame.groundHeight ? frame.groundHeight(lon, lat) : std::optional<double>(0.0);
        unknown |= !h.has_value();
        return h.value_or(0.0);
    };
    fmv::TerrainHeights flat;
    const double h0 = groundAt(pose_.lonDeg, pose_.latDeg);
    flat.at = [h0](double, double) { return h0; };
    flat.minHeight = flat.maxHeight = h0;
    const fmv::Footprint f = fmv::footprint(camera, &flat, 1e9);
    std::vector<glm::dvec3> points{wgs84().toEcef(pose_.lonDeg, pose_.latDeg, h0), f.centre.ecef};
    for (const auto& c : f.corners) points.push_back(c.ecef);
    glm::dvec3 mean(0.0);
    for (const auto& p : points) mean += p;
    mean /= double(points.size());
    const globe::Geodetic g = wgs84().toGeodetic(mean);
    double half = 0.0;
    {
        const glm::dvec3 o = wgs84().toEcef(g.lonDeg, g.latDeg, 0.0);
        const glm::dmat3 e = wgs84().enuFrame(g.lonDeg, g.latDeg);
        for (const auto& p : points) half = std::max({half, std::abs(glm::dot(p - o, e[0])), std::abs(glm::dot(p - o, e[1]))});
    }
    // The heightfield is a function of the current pose alone (never of the frames before, so
    // that one time gives one picture however it was reached): its size is the next power of two
    // above what the view needs, and its centre snaps to a grid of an eighth of that in lon/lat.
    // Between snaps it is reused as it is.
    double halfSize = std::exp2(std::ceil(std::log2(std::max(half * 1.15 + 200.0, 1.0))));
    const double step = halfSize / 8.0;
    halfSize = std::min(halfSize + step, kMaxHalfSize);
    const double metresPerDegree = 111320.0;
    const double dLat = step / metresPerDegree;
    const double lat = std::clamp(std::round(g.latDeg / dLat) * dLat, -90.0, 90.0);
    const double dLon = step / (metresPerDegree * std::max(std::cos(glm::radians(lat)), 0.01));
    const double lon = globe::wrapLongitude(std::round(g.lonDeg / dLon) * dLon);
    const glm::dvec3 origin = wgs84().toEcef(lon, lat, 0.0);
    // Rebuild when the snapped place or the size changed, or the ground's data changed (tiles
    // loaded or evicted), or parts of it were not known yet.
    const bool same = !heights_.empty() && origin == origin_ && halfSize == halfSize_;
    if (same && heightsComplete_ && frame.groundVersion == groundVersion_) return;
    origin_ = origin;
    enu_ = wgs84().enuFrame(lon, lat);
    halfSize_ = halfSize;
    groundVersion_ = frame.groundVersion;
    sampleHeightfield(groundAt);
    heightsComplete_ = !unknown;
}

void FmvLayer::sampleHeightfield(const std::function<double(double, double)>& groundAt) {
    const int n = settings_.heightfieldSize;
    const double cell = 2.0 * halfSize_ / double(n - 1);
    std::vector<float> heights(size_t(n) * size_t(n));
    gridPositions_.resize(heights.size());
    minHeight_ = 1e30;
    maxHeight_ = -1e30;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec3 onPlane = origin_ + (-halfSize_ + i * cell) * enu_[0] + (halfSize_ - j * cell) * enu_[1];
            const globe::Geodetic s = wgs84().toGeodetic(onPlane);
            const double h = groundAt(s.lonDeg, s.latDeg);
            heights[size_t(j) * size_t(n) + size_t(i)] = float(h);
            gridPositions_[size_t(j) * size_t(n) + size_t(i)] = glm::vec3(wgs84().toEcef(s.lonDeg, s.latDeg, h) - origin_);
            minHeight_ = std::min(minHeight_, h);
            maxHeight_ = std::max(maxHeight_, h);
        }
    ++heightfieldBuilds_;
    heights_ = std::move(heights);
    heightfieldDirty_ = true;
}

void FmvLayer::recordTransfers(const render::RecordContext& rc) {
    if (!active_) return;
    VkCommandBuffer cmd = rc.cmd;
    if (pendingFrame_) {
        rc.uploader->toImage(cmd, frameImage_, pendingFrame_->rgba.data(), pendingFrame_->rgba.size());
        gpu::transition(cmd, frameImage_, gpu::ImageUse::SampledCompute);
        shownIndex_ = pendingFrame_->index;
        pendingFrame_ = nullptr;
    }
    if (heightfieldDirty_) {
        rc.uploader->toImage(cmd, heightImage_, heights_.data(), heights_.size() * sizeof(float));
        gpu::transition(cmd, heightImage_, gpu::ImageUse::SampledCompute);
        gpu::bufferBarrier(cmd, gridVertices_, VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT,
                           VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        rc.uploader->toBuffer(cmd, gridVertices_, gridPositions_.data(), gridPositions_.size() * sizeof(glm::vec3));
        gpu::bufferBarrier(cmd, gridVertices_, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
        heightfieldDirty_ = false;
    }
    writeUniforms(rc);
}

void FmvLayer::writeUniforms(const render::RecordContext& rc) {
    const fmv::SensorCamera camera(pose_);
    const glm::dmat3 axes = camera.axes();
    const glm::dvec3 s = camera.position() - origin_;
    const double tanH = camera.tanHalfFov().x, tanV = camera.tanHalfFov().y;
    const double n = double(settings_.heightfieldSize), cell = 2.0 * halfSize_ / (n - 1.0);
    shader::FmvUniforms u{};
    u.originFromEye = glm::vec3(origin_ - eye_);
    u.opacity = noSignal_ ? 0.0f : float(settings_.opacity);
    u.sensor = glm::vec3(s);
    u.occlusionBias = float(0.5 * cell);
    u.boresight = glm::vec3(axes[0]);
    u.tanHalfFovX = float(tanH);
    u.imageRight = glm::vec3(axes[1]);
    u.tanHalfFovY = float(tanV);
    u.imageDown = glm::vec3(axes[2]);
    u.mapFovScale = float(kMapFovPad);
    const globe::Geodetic og = wgs84().toGeodetic(origin_);
    const double lat = glm::radians(og.latDeg), a = wgs84().equatorialRadius(), e2 = wgs84().flattening() * (2.0 - wgs84().flattening());
    const double w = std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
    const double radius = std::sqrt((a / w) * (a * (1.0 - e2) / (w * w * w)));   // Gaussian mean radius at O
    u.east = glm::vec3(enu_[0]);
    u.halfSize = float(halfSize_);
    u.north = glm::vec3(enu_[1]);
    u.sphereRadius = float(radius);
    u.up = glm::vec3(enu_[2]);
    u.heightfieldSamples = float(n);
    u.lowestHeight = float(minHeight_);
    u.highestHeight = float(maxHeight_);
    u.marchStep = float(std::max(0.5 * cell, 1.0));
    u.frameShown = shownIndex_ ? 1u : 0u;
    // Without signal the last footprint stays, grey.
    const glm::dvec3 c = noSignal_ ? glm::dvec3(0.55) : settings_.footprintColor;
    u.outlineColor = glm::vec3(float(srgbToLinear(c.r)), float(srgbToLinear(c.g)), float(srgbToLinear(c.b)));
    u.occlusionBiasPerMetre = 0.01f;
    u.sensorClip = glm::mat4(sensorClip());
    const ScreenBounds bounds = screenBounds(*rc.frame);
    rect_ = bounds.rect;
    u.rectOrigin = glm::vec2(rect_.x, rect_.y);
    u.rectSize = glm::vec2(rect_.z, rect_.w);
    u.hullEdges = uint32_t(bounds.edges.size());
    for (size_t i = 0; i < bounds.edges.size(); ++i) u.hull[i] = glm::vec4(bounds.edges[i], 0.0f);
    uniforms_[rc.slot].write(&u, sizeof(u));
}

FmvLayer::ScreenBounds FmvLayer::screenBounds(const scene::FrameContext& frame) const {
    constexpr double kMargin = 4.0;   // pixels
    const ScreenBounds whole{glm::uvec4(0u, 0u, frame.width, frame.height), {}};
    const fmv::SensorCamera sensor(pose_);
    // The heights of the ground the sensor sees (the heightfield's samples in its view), else
    // the heightfield's whole range: the tighter the range, the smaller the rectangle.
    double low = 1e30, high = -1e30;
    for (size_t k = 0; k < gridPositions_.size(); ++k) {
        const glm::dvec3 uvd = sensor.project(origin_ + glm::dvec3(gridPositions_[k]));
        if (uvd.z > 0.0 && std::abs(uvd.x) <= 1.1 && std::abs(uvd.y) <= 1.1) {
            low = std::min(low, double(heights_[k]));
            high = std::max(high, double(heights_[k]));
        }
    }
    if (low > high) low = minHeight_, high = maxHeight_;
    // A cell's worth of slack: the ground between samples.
    const double slack = 2.0 * halfSize_ / double(settings_.heightfieldSize - 1);
    low -= slack * 0.5;
    high += slack * 0.5;
    const scene::Camera& camera = *frame.camera;
    const glm::dmat4 viewProj = camera.projection(frame.aspect()) * camera.viewRotation();
    glm::dvec2 lo(1e30), hi(-1e30);
    std::vector<glm::dvec2> points;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 d = sensor.cornerRay(i);
        for (double h : {low, high}) {
            const std::optional<double> t = wgs84().intersectRay(sensor.position(), d, h);
            const glm::dvec3 p = t ? sensor.position() + *t * d : fmv::horizonPoint(sensor.position(), d, h);
            const glm::dvec4 clip = viewProj * glm::dvec4(p - camera.position(), 1.0);
            if (clip.w <= 1e-6) return whole;   // behind the eye: no bound from this side
            const glm::dvec2 px = (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * glm::dvec2(frame.width, frame.height);
            lo = glm::min(lo, px);
            hi = glm::max(hi, px);
            points.push_back(px);
        }
    }
    ScreenBounds out;
    out.edges = hullEdges(std::move(points), kMargin);
    const double x0 = std::clamp(std::floor(lo.x - kMargin), 0.0, double(frame.width));
    const double y0 = std::clamp(std::floor(lo.y - kMargin), 0.0, double(frame.height));
    const double x1 = std::clamp(std::ceil(hi.x + kMargin), 0.0, double(frame.width));
    const double y1 = std::clamp(std::ceil(hi.y + kMargin), 0.0, double(frame.height));
    out.rect = glm::uvec4(uint32_t(x0), uint32_t(y0), uint32_t(x1 - x0), uint32_t(y1 - y0));
    return out;
}

glm::dmat4 FmvLayer::sensorClip() const {
    // Relative to O -> the distance map's clip space: x right, y down (the image's rows),
    // reversed-Z with an infinite far plane, a field of view kMapFovPad times the video's.
    const fmv::SensorCamera camera(pose_);
    const glm::dmat3 axes = camera.axes();
    const glm::dvec3 s = camera.position() - origin_;
    const double tanH = camera.tanHalfFov().x, tanV = camera.tanHalfFov().y;
    const glm::dvec3 rowX = axes[1] / (tanH * kMapFovPad), rowY = axes[2] / (tanV * kMapFovPad), rowW = axes[0];
    glm::dmat4 clip(0.0);
    for (int c = 0; c < 3; ++c) {
        clip[c][0] = rowX[c];
        clip[c][1] = rowY[c];
        clip[c][3] = rowW[c];
    }
    clip[3][0] = -glm::dot(rowX, s);
    clip[3][1] = -glm::dot(rowY, s);
    clip[3][2] = kSensorNear;
    clip[3][3] = -glm::dot(rowW, s);
    return clip;
}

void FmvLayer::writeDescriptors(uint32_t slot) {
    gpu::DescriptorWriter(descriptors_.sets[slot])
        .uniformBuffer(shader::kFmvBindingUniforms, uniforms_[slot], 0, sizeof(shader::FmvUniforms))
        .sampledImage(shader::kFmvBindingSceneDepth, nearestSampler_.vk(), boundDepth_->view())
        .sampledImage(shader::kFmvBindingVideoFrame, linearSampler_.vk(), frameImage_.view())
        .sampledImage(shader::kFmvBindingDistanceMap, linearSampler_.vk(), distanceImage_.view())
        .sampledImage(shader::kFmvBindingHeightfield, linearSampler_.vk(), heightImage_.view())
        .storageImage(shader::kFmvBindingDecal, decalImage_.view())
        .sampledImage(shader::kFmvBindingDecalSampled, nearestSampler_.vk(), decalImage_.view())
        .storageBuffer(shader::kFmvBindingFootprint, footprintBuffer_)
        .update(*services_.device);
    setVersion_[slot] = imagesVersion_;
}

void FmvLayer::renderDistanceMap(VkCommandBuffer cmd) {
    const gpu::ImageTransition targets[] = {{&distanceImage_, gpu::ImageUse::ColorAttachment},
                                            {&distanceDepth_, gpu::ImageUse::DepthAttachment}};
    gpu::transition(cmd, targets);
    const uint32_t m = uint32_t(settings_.distanceMapSize);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = distanceImage_.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{1e30f, 0.0f, 0.0f, 0.0f}};   // nothing seen: nothing hides
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = distanceDepth_.view();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.clearValue.depthStencil = {0.0f, 0};
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {m, m}};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &info);
    const VkViewport viewport{0.0f, 0.0f, float(m), float(m), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {m, m}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, distancePipeline_.vk());
    const fmv::SensorCamera camera(pose_);
    shader::FmvDistancePush push{};
    push.sensorClip = glm::mat4(sensorClip());
    push.sensor = glm::vec3(camera.position() - origin_);
    push.boresight = glm::vec3(camera.axes()[0]);
    vkCmdPushConstants(cmd, layout_.vk(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof push, &push);
    const VkDeviceSize offset = 0;
    VkBuffer vertices = gridVertices_.vk();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vertices, &offset);
    vkCmdBindIndexBuffer(cmd, gridIndices_.vk(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, gridIndexCount_, 1, 0, 0, 0);
    vkCmdEndRendering(cmd);
    gpu::transition(cmd, distanceImage_, gpu::ImageUse::SampledCompute);
}

void FmvLayer::recordCompute(scene::Pass, const render::RecordContext& rc) {
    const scene::FrameContext& frame = *rc.frame;
    VkCommandBuffer cmd = rc.cmd;
    if (!decalImage_ || decalImage_.extent().width != frame.width || decalImage_.extent().height != frame.height) {
        gpu::ImageDesc d;
        d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
        d.extent = {frame.width, frame.height, 1};
        d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        d.name = "fmv decal";
        decalImage_ = gpu::Image(*services_.device, d);
        ++imagesVersion_;
    }
    if (boundDepth_ != rc.sceneDepth) {
        boundDepth_ = rc.sceneDepth;
        ++imagesVersion_;
    }
    if (setVersion_[rc.slot] != imagesVersion_) writeDescriptors(rc.slot);
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.vk(), shader::kFrameSet, 2, sets, 0, nullptr);
    if (!mapPose_ || !(*mapPose_ == pose_) || mapBuilds_ != heightfieldBuilds_) {
        renderDistanceMap(cmd);
        // The footprint: after the last frame's lines read it.
        gpu::bufferBarrier(cmd, footprintBuffer_, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, footprintPipeline_.vk());
        vkCmdDispatch(cmd, (shader::kFmvFootprintRays + shader::kFmvFootprintGroup - 1) / shader::kFmvFootprintGroup, 1, 1);
        gpu::bufferBarrier(cmd, footprintBuffer_, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
        footprintOrigin_ = origin_;
        footprintValid_ = true;
        ++footprintUpdates_;
        mapPose_ = pose_;
        mapBuilds_ = heightfieldBuilds_;
    }
    // The drape.
    gpu::transition(cmd, decalImage_, gpu::ImageUse::StorageCompute);
    const uint32_t g = shader::kFmvGroupSize;
    if (rect_.z > 0 && rect_.w > 0) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, drapePipeline_.vk());
        vkCmdDispatch(cmd, (rect_.z + g - 1) / g, (rect_.w + g - 1) / g, 1);
    }
    gpu::transition(cmd, decalImage_, gpu::ImageUse::SampledFragment);
}

void FmvLayer::record(scene::Pass, const render::RecordContext& rc) {
    if (!active_ || !decalImage_ || !boundDepth_) return;
    VkCommandBuffer cmd = rc.cmd;
    const VkDescriptorSet sets[] = {rc.frameSet, descriptors_.sets[rc.slot]};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 2, sets, 0, nullptr);
    if (rect_.z > 0 && rect_.w > 0 && !noSignal_) {   // only where the video can be (the decal is stale elsewhere)
        const VkRect2D area{{int32_t(rect_.x), int32_t(rect_.y)}, {rect_.z, rect_.w}};
        vkCmdSetScissor(cmd, 0, 1, &area);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, compositePipeline_.vk());
        vkCmdDraw(cmd, 3, 1, 0, 0);
        const VkRect2D screen{{0, 0}, {rc.frame->width, rc.frame->height}};
        vkCmdSetScissor(cmd, 0, 1, &screen);
    }
    if (settings_.footprint) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, outlinePipeline_.vk());
        vkCmdDraw(cmd, 4 * shader::kFmvEdgeRays + 1, 1, 0, 0);   // closed: the first point again
    }
    if (settings_.frustum) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, frustumPipeline_.vk());
        vkCmdDraw(cmd, 8, 1, 0, 0);
    }
}

// ---------------------------------------------------------------------------------------------
// State and stats
bool FmvLayer::busy() const {
    // A live stream is waited for only while it connects (until its first frame, or no signal).
    if (live_) return gpuReady_ && ((!shownIndex_ && liveStats_.state != fmv::LiveState::NoSignal) || (active_ && !heightsComplete_));
    return gpuReady_ && (!wantedShown_ || (active_ && !heightsComplete_));
}

std::vector<std::pair<glm::dvec3, bool>> FmvLayer::footprint() const {
    std::vector<std::pair<glm::dvec3, bool>> out;
    if (!footprintValid_) return out;
    const_cast<gpu::Buffer&>(footprintBuffer_).invalidate();
    const auto* p = static_cast<const glm::vec4*>(footprintBuffer_.mapped());
    for (uint32_t i = 0; i < shader::kFmvFootprintRays; ++i)
        out.push_back({footprintOrigin_ + glm::dvec3(p[i]), p[i].w > 0.5f});
    return out;
}

uint64_t FmvLayer::gpuBytes() const {
    uint64_t bytes = frameImage_ ? uint64_t(frameImage_.extent().width) * frameImage_.extent().height * 4 : 0;
    const uint64_t n = uint64_t(settings_.heightfieldSize), m = uint64_t(settings_.distanceMapSize);
    bytes += n * n * (4 + 12) + (n - 1) * (n - 1) * 24 + m * m * 8;
    if (decalImage_) bytes += uint64_t(decalImage_.extent().width) * decalImage_.extent().height * 8;
    return bytes;
}

bool FmvLayer::setParameter(std::string_view name, double value) {
    if (name == "opacity" && kOpacityRange.contains(value)) settings_.opacity = value;
    else if (name == "headingOffset" && kHeadingOffsetRange.contains(value)) settings_.offset.headingDeg = value;
    else if (name == "pitchOffset" && kPitchOffsetRange.contains(value)) settings_.offset.pitchDeg = value;
    else if (name == "rollOffset" && kRollOffsetRange.contains(value)) settings_.offset.rollDeg = value;
    else if (name == "altitudeOffset" && kAltitudeOffsetRange.contains(value)) settings_.offset.altitude = value;
    else if (name == "footprint") settings_.footprint = value != 0.0;
    else if (name == "frustum") settings_.frustum = value != 0.0;
    else return false;
    return true;
}

std::vector<scene::LayerSetting> FmvLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    return {
        {.name = "opacity", .label = "Video opacity", .kind = Kind::Number, .value = settings_.opacity,
         .min = kOpacityRange.min, .max = kOpacityRange.max},
        {.name = "footprint", .label = "Footprint outline", .kind = Kind::Toggle, .value = settings_.footprint ? 1.0 : 0.0},
        {.name = "frustum", .label = "Sensor frustum", .kind = Kind::Toggle, .value = settings_.frustum ? 1.0 : 0.0},
        {.name = "headingOffset", .label = "Heading offset (deg)", .kind = Kind::Number, .value = settings_.offset.headingDeg,
         .min = kHeadingOffsetRange.min, .max = kHeadingOffsetRange.max, .pointer = "/poseOffset/heading"},
        {.name = "pitchOffset", .label = "Pitch offset (deg)", .kind = Kind::Number, .value = settings_.offset.pitchDeg,
         .min = kPitchOffsetRange.min, .max = kPitchOffsetRange.max, .pointer = "/poseOffset/pitch"},
        {.name = "rollOffset", .label = "Roll offset (deg)", .kind = Kind::Number, .value = settings_.offset.rollDeg,
         .min = kRollOffsetRange.min, .max = kRollOffsetRange.max, .pointer = "/poseOffset/roll"},
        {.name = "altitudeOffset", .label = "Altitude offset (m)", .kind = Kind::Number, .value = settings_.offset.altitude,
         .min = kAltitudeOffsetRange.min, .max = kAltitudeOffsetRange.max, .pointer = "/poseOffset/altitude"},
    };
}

const std::string& FmvLayer::url() const {
    static const std::string none;
    return live_ ? live_->url() : none;
}

scene::FeedStatus FmvLayer::feedStatus() const {
    const fmv::LiveStats& l = liveStats_;
    scene::FeedStatus f;
    f.url = url();
    f.state = fmv::toString(l.state);
    f.bitsPerSecond = l.bitsPerSecond;
    f.latencySeconds = l.latencySeconds;
    f.framesShown = l.framesShown;
    f.framesLost = l.framesLost;
    f.damagedPackets = l.framesDamaged + l.corruptPackets + l.klvRejected;
    f.secondsSinceData = l.secondsSinceData;
    f.width = l.width;
    f.height = l.height;
    f.lastError = l.lastError;
    f.recording = l.recording;
    return f;
}

Result<std::string> FmvLayer::setRecording(bool on) const {
    if (!live_) return makeError("fmv: a file is not recorded");
    std::string path;
    if (on) {
        // <folder>/<layer name>-<UTC, seconds>.ts, the name's odd characters replaced.
        std::string stem = settings_.name.empty() ? std::string("feed") : settings_.name;
        for (char& c : stem)
            if (!(std::isalnum(uint8_t(c)) || c == '-' || c == '_')) c = '_';
        std::string stamp = formatIso8601(fromSeconds(std::floor(fmv::wallClockSeconds())), 0);
        for (char& c : stamp)
            if (c == ':') c = '-';
        path = (std::filesystem::path(settings_.recordFolder.empty() ? "." : settings_.recordFolder) / (stem + "-" + stamp + ".ts")).string();
    }
    if (auto r = live_->record(path); !r) return r.error();
    return path;
}

std::optional<scene::TimeRange> FmvLayer::timeRange() const { return std::nullopt; }   // the scene's time stays its own

std::optional<scene::TrackedPose> FmvLayer::trackedPose(TimeNs t, const scene::GroundHeightFn&) const {
    fmv::SensorPose pose;
    if (live_) {
        if (!active_) return std::nullopt;
        pose = pose_;
    } else {
        const double v = toSeconds(t) - startUtc_;
        if (v < 0.0 || v >= video_->info().duration) return std::nullopt;
        pose = applyOffset(timeline_.poseAt(v), settings_.offset);
    }
    const fmv::SensorCamera camera(pose);
    scene::TrackedPose p;
    p.position = camera.position();
    p.bodyToEcef = glm::quat_cast(camera.axes());
    p.radius = 1.0;
    return p;
}

std::optional<scene::ContentBounds> FmvLayer::contentBounds() const {
    // Where the sensor flies: its poses (a file), or where it is now (live), and the ground it
    // sees from there.
    std::vector<glm::dvec3> points;
    if (live_) {
        if (!active_) return std::nullopt;
        points.push_back(fmv::SensorCamera(pose_).position());
    } else {
        for (const fmv::TimedPose& p : timeline_.poses()) points.push_back(fmv::SensorCamera(p.pose).position());
    }
    glm::dvec3 c(0.0);
    for (const glm::dvec3& q : points) c += q;
    c /= double(points.size());
    double r = 0.0;
    for (const glm::dvec3& q : points) r = std::max(r, glm::length(q - c));
    const double height = live_ ? pose_.height : timeline_.poses().front().pose.height;
    return scene::ContentBounds{c, r + std::max(1000.0, 2.0 * std::abs(height))};
}

std::string FmvLayer::status() const {
    if (live_) {
        const fmv::LiveStats& l = liveStats_;
        char text[400];
        if (l.state == fmv::LiveState::Connecting)
            std::snprintf(text, sizeof text, "fmv: %s: connecting%s%s", live_->url().c_str(), l.lastError.empty() ? "" : " (",
                          l.lastError.empty() ? "" : (l.lastError + ")").c_str());
        else if (l.state == fmv::LiveState::NoSignal)
            std::snprintf(text, sizeof text, "fmv: %s: no signal for %.0f s (%s); the last footprint is grey", live_->url().c_str(),
                          l.secondsSinceData, l.lastError.c_str());
        else
            std::snprintf(text, sizeof text, "fmv: %s: live %dx%d, %.2f Mbit/s, latency %s, %llu frames shown, %llu lost, %llu damaged",
                          live_->url().c_str(), l.width, l.height, l.bitsPerSecond * 1e-6,
                          l.latencySeconds ? (std::to_string(int(std::lround(*l.latencySeconds * 1e3))) + " ms").c_str()
                              : "unknown",
                          (unsigned long long)l.framesShown, (unsigned long long)l.framesLost,
                          (unsigned long long)(l.framesDamaged + l.corruptPackets));
        return text;
    }
    if (!frames_) return {};
    if (!frames_->error().empty()) return std::string("fmv: ").append(frames_->error());
    char text[200];
    if (!active_) return "fmv: the video is not playing at this time";
    std::snprintf(text, sizeof text, "fmv: frame %zu of %zu, sensor at %.5f, %.5f, %.0f m", shownIndex_.value_or(0),
                  video_->frameCount(), pose_.latDeg, pose_.lonDeg, pose_.height);
    return text;
}

}  // namespace orbis::layers
