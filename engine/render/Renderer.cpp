#include "engine/render/Renderer.h"

#include "base/Color.h"
#include "base/Log.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "base/ThreadPool.h"
#include "globe/Ellipsoid.h"
#include "globe/Sun.h"
#include "shared/FrameUniforms.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

namespace orbis::render {
namespace {

constexpr uint32_t kFramesInFlight = 2;

const char* passName(scene::Pass p) {
    switch (p) {
        case scene::Pass::Opaque: return "opaque";
        case scene::Pass::Points: return "points";
        case scene::Pass::Fmv: return "fmv";
        case scene::Pass::Volume: return "volume";
        case scene::Pass::Overlay: return "overlay";
    }
    return "?";
}

/// GPU timer scope of the compute work recorded before a pass.
const char* computeName(scene::Pass p) {
    switch (p) {
        case scene::Pass::Points: return "points compute";
        case scene::Pass::Fmv: return "fmv compute";
        case scene::Pass::Volume: return "volume compute";
        default: return "compute";
    }
}

}  // namespace

Renderer::Renderer(gpu::Device& device, uint32_t width, uint32_t height)
    : device_(device),
      target_(std::make_unique<gpu::RenderTarget>(device, width, height)),
      ring_(device, kFramesInFlight),
      timer_(device, kFramesInFlight),
      uploader_(device) {
    frameSets_ = gpu::createDescriptorSets(device, shader::kFrameBindings, kFramesInFlight);
    for (uint32_t i = 0; i < kFramesInFlight; ++i) {
        frameUniforms_.emplace_back(device, sizeof(shader::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                    gpu::MemoryUsage::Upload, "frame uniforms");
        gpu::DescriptorWriter(frameSets_.sets[i])
            .uniformBuffer(shader::kFrameBinding, frameUniforms_.back(), 0, sizeof(shader::FrameUniforms))
            .update(device);
    }

    services_.device = &device_;
    services_.uploader = &uploader_;
    services_.colorFormat = gpu::RenderTarget::kColorFormat;
    services_.depthFormat = gpu::RenderTarget::kDepthFormat;
    services_.frameSetLayout = frameSets_.layout.vk();
    services_.framesInFlight = ring_.framesInFlight();
    services_.jobs = [this]() -> jobs::ThreadPool& { return jobs(); };
}

Renderer::~Renderer() = default;

jobs::ThreadPool& Renderer::jobs() {
    if (!jobs_) {
        const unsigned threads = std::max(2u, std::thread::hardware_concurrency());
        jobs_ = std::make_unique<jobs::ThreadPool>(threads, "orbis-worker");
        log::debug("started ", threads, " worker threads");
    }
    return *jobs_;
}

void Renderer::resize(uint32_t width, uint32_t height) {
    if (width == target_->width() && height == target_->height()) return;
    target_ = std::make_unique<gpu::RenderTarget>(device_, width, height);
}

void Renderer::prepareLayer(scene::Layer& layer) {
    layer.prepare(services_);
}

void Renderer::writeFrameUniforms(uint32_t slot, const scene::Scene& scene, const scene::FrameContext& ctx) {
    const scene::Camera& cam = scene.camera();
    const auto& ell = globe::Ellipsoid::wgs84();
    const glm::dmat4 view = cam.viewRotation();
    const glm::dmat4 proj = cam.projection(ctx.aspect());
    shader::FrameUniforms u{};
    u.viewRotation = glm::mat4(view);
    u.projection = glm::mat4(proj);
    u.clipToWorldDir = glm::mat4(glm::inverse(proj * view));
    const double height = ctx.cameraHeight;
    u.eyeEcef = glm::vec3(cam.position());
    u.eyeHeight = static_cast<float>(height);
    u.sunDirection = glm::vec3(globe::sunDirectionEcef(ctx.time));
    u.sunLighting = 1.0f;
    u.viewportSize = glm::vec2(ctx.width, ctx.height);
    u.invViewportSize = glm::vec2(1.0f / ctx.width, 1.0f / ctx.height);
    const double a = ell.equatorialRadius(), b = ell.polarRadius();
    u.equatorialRadius = static_cast<float>(a);
    u.polarRadius = static_cast<float>(b);
    u.invEquatorialRadius2 = static_cast<float>(1.0 / (a * a));
    u.invPolarRadius2 = static_cast<float>(1.0 / (b * b));
    const glm::dvec3 bg = scene.desc().background;
    u.background = glm::vec3(srgbToLinear(bg.r), srgbToLinear(bg.g), srgbToLinear(bg.b));
    const double secondsOfDay = std::fmod(toSeconds(ctx.time), 86400.0);
    u.secondsOfDay = static_cast<float>(secondsOfDay < 0 ? secondsOfDay + 86400.0 : secondsOfDay);
    frameUniforms_[slot].write(&u, sizeof(u));
}

void Renderer::recordPass(scene::Pass pass, const char* name, scene::Scene& scene, const RecordContext& rc,
                          bool clear, const glm::dvec3& background) {
    VkCommandBuffer cmd = rc.cmd;
    const gpu::ImageTransition uses[] = {{&target_->color(), gpu::ImageUse::ColorAttachment},
                                         {&target_->depth(), gpu::ImageUse::DepthAttachment}};
    gpu::transition(cmd, uses);
    const int scope = timer_.begin(cmd, name);

    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = target_->color().view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{float(srgbToLinear(background.r)), float(srgbToLinear(background.g)),
                               float(srgbToLinear(background.b)), 1.0f}};
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = target_->depth().view();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {0.0f, 0};   // reversed-Z: 0 is infinitely far
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {target_->width(), target_->height()}};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &info);
    const VkViewport viewport{0.0f, 0.0f, float(target_->width()), float(target_->height()), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {target_->width(), target_->height()}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    for (auto& r : scene.resources())
        if (r.visible && r.layer->drawsIn(pass)) r.layer->record(pass, rc);
    vkCmdEndRendering(cmd);
    timer_.end(cmd, scope);
}

int Renderer::settle(scene::Scene& scene, double maxSeconds, const std::function<void()>& afterFrame) {
    const auto start = std::chrono::steady_clock::now();
    int frames = 0;
    do {
        const FrameResult f = render(scene, /*readback=*/false, /*draw=*/false, nullptr);
        device_.wait(f.timelineValue);
        ++frames;
        if (afterFrame) afterFrame();
        if (!scene.busy()) break;
        // Let the workers load rather than spin: a frame that draws nothing is cheap, but
        // selection and uploads still take the main thread.
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    } while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < maxSeconds);
    return frames;
}

FrameResult Renderer::render(scene::Scene& scene, bool readback) { return render(scene, readback, true, nullptr); }

FrameResult Renderer::render(scene::Scene& scene, bool readback, const FrameHooks& hooks) {
    return render(scene, readback, true, &hooks);
}

FrameResult Renderer::render(scene::Scene& scene, bool readback, bool draw, const FrameHooks* hooks) {
    const auto t0 = std::chrono::steady_clock::now();
    // GPU objects are built before the frame starts recording, and only for visible layers.
    for (auto& r : scene.resources())
        if (r.visible && !r.layer->prepared()) prepareLayer(*r.layer);
    for (auto& r : scene.resources())
        if (r.visible && r.layer->prepared()) r.layer->poll();
    const double eyeHeight = placeCamera(scene);

    gpu::FrameRing::Frame& frame = ring_.begin();
    timer_.beginFrame(frame.cmd, frame.slot);
    uploader_.resetCounter();

    const scene::FrameContext ctx = frameContext(scene, frame.number, eyeHeight);
    for (auto& r : scene.resources())
        if (r.visible) r.layer->update(ctx);
    writeFrameUniforms(frame.slot, scene, ctx);

    RecordContext rc;
    rc.cmd = frame.cmd;
    rc.frame = &ctx;
    rc.frameSet = frameSets_.sets[frame.slot];
    rc.uploader = &uploader_;
    rc.slot = frame.slot;
    for (auto& r : scene.resources())
        if (r.visible) r.layer->recordTransfers(rc);
    if (draw) recordPasses(scene, rc);
    if (hooks && hooks->overlay) {
        gpu::transition(frame.cmd, target_->color(), gpu::ImageUse::ColorAttachment);
        const int scope = timer_.begin(frame.cmd, "ui");
        hooks->overlay(frame.cmd, *target_);
        timer_.end(frame.cmd, scope);
    }
    if (readback) {
        const int scope = timer_.begin(frame.cmd, "readback");
        target_->recordReadback(frame.cmd);
        timer_.end(frame.cmd, scope);
    }
    if (hooks && hooks->finish) hooks->finish(frame.cmd, *target_);
    FrameResult result;
    result.frameNumber = frame.number;
    result.slot = frame.slot;
    result.timelineValue = hooks ? ring_.submit(frame, hooks->waits, hooks->signals) : ring_.submit(frame);
    result.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

double Renderer::placeCamera(scene::Scene& scene) {
    // A camera mode that watches a moving layer puts the camera first (at the scene's time).
    scene.updateCamera(double(target_->width()) / double(std::max(1u, target_->height())));
    // The near plane follows the camera's height above the ground and the nearest content that
    // floats above it (reversed-Z keeps precision at any range).
    const globe::Geodetic eye = globe::Ellipsoid::wgs84().toGeodetic(scene.camera().position());
    const double ground = scene.heightAt(eye.lonDeg, eye.latDeg).value_or(0.0);
    double clearance = eye.height - std::min(ground, eye.height);
    for (auto& r : scene.resources()) {
        const auto* content = r.layer->asFloatingContent();
        if (!content || !r.visible || !r.layer->prepared()) continue;
        if (auto d = content->nearestContent(scene.camera().position())) clearance = std::min(clearance, *d);
    }
    scene.camera().setNear(scene::Camera::autoNear(clearance));
    return eye.height;
}

scene::FrameContext Renderer::frameContext(scene::Scene& scene, uint64_t frameNumber, double eyeHeight) const {
    scene::FrameContext ctx;
    ctx.camera = &scene.camera();
    ctx.time = scene.time().now();
    ctx.width = target_->width();
    ctx.height = target_->height();
    ctx.frameNumber = frameNumber;
    ctx.cameraHeight = eyeHeight;
    ctx.groundHeight = [&scene](double lon, double lat) { return scene.heightAt(lon, lat); };
    ctx.groundSnapshot = [&scene] { return scene.groundSnapshot(); };
    ctx.annotations = &scene.annotations();
    for (auto& r : scene.resources()) {
        if (!r.visible || !r.layer->prepared()) continue;
        if (const auto* ground = r.layer->asGroundSource()) ctx.groundVersion += ground->groundVersion();
        if (const auto* draped = r.layer->asDrapedContent())
            if (auto source = draped->drapeSource())
                ctx.drapes.push_back({r.layer.get(), std::move(source), draped->drapeVersion(), draped->drapeOpacity(), draped});
    }
    return ctx;
}

void Renderer::recordPasses(scene::Scene& scene, const RecordContext& rc) {
    const auto visible = [&](scene::Pass pass, bool computing) {
        return [pass, computing](const scene::Resource& r) {
            return r.visible && r.layer->drawsIn(pass) && (!computing || r.layer->computesBefore(pass));
        };
    };
    // The opaque pass always runs (it clears); later passes only when a visible layer uses them.
    recordPass(scene::Pass::Opaque, passName(scene::Pass::Opaque), scene, rc, true, scene.desc().background);
    for (scene::Pass pass : {scene::Pass::Points, scene::Pass::Fmv, scene::Pass::Volume, scene::Pass::Overlay}) {
        const auto& resources = scene.resources();
        if (std::none_of(resources.begin(), resources.end(), visible(pass, false))) continue;
        if (std::any_of(resources.begin(), resources.end(), visible(pass, true))) {
            // Compute before the pass (ray casting): the depth so far is read, not written.
            gpu::transition(rc.cmd, target_->depth(), gpu::ImageUse::SampledCompute);
            RecordContext crc = rc;
            crc.sceneDepth = &target_->depth();
            const int scope = timer_.begin(rc.cmd, computeName(pass));
            for (auto& r : scene.resources())
                if (visible(pass, true)(r)) r.layer->recordCompute(pass, crc);
            timer_.end(rc.cmd, scope);
        }
        recordPass(pass, passName(pass), scene, rc, false, scene.desc().background);
    }
}

std::vector<uint8_t> Renderer::readPixels(const FrameResult& frame) {
    device_.wait(frame.timelineValue);
    return target_->readPixels();
}

std::vector<gpu::PassTime> Renderer::gpuTimes(const FrameResult& frame) {
    device_.wait(frame.timelineValue);
    return timer_.resolve(frame.slot);
}

}  // namespace orbis::render
