#include "layers/annotations/AnnotationLayer.h"

#include "base/Log.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Pipeline.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/JsonReader.h"
#include "shared/FrameUniforms.h"
#include "shared/PolylineTypes.h"

// The model layer's screen-space shader (kScreen): clip-space positions, premultiplied colour.
#include "spv/common/polyline.frag.h"
#include "spv/common/polyline.vert.h"

#include <algorithm>
#include <cstring>

namespace orbis::layers {
namespace {

/// Rectangles a frame can hold: some 200 labelled pins, 3 MB a frame in flight.
constexpr std::size_t kMaxQuads = 16384;

}  // namespace

Result<std::unique_ptr<scene::Layer>> AnnotationLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    PinStyle s;
    if (auto c = r.numbers("color", 3, std::vector<double>{s.color.r, s.color.g, s.color.b})) {
        for (double v : *c)
            if (v < 0.0 || v > 1.0) r.fail("color", "colour components must be in [0, 1]");
        if (c->size() == 3) s.color = {(*c)[0], (*c)[1], (*c)[2]};
    }
    s.labelScale = r.number("labelScale", s.labelScale, kLabelScaleRange.min, kLabelScaleRange.max).value_or(s.labelScale);
    s.labels = r.boolean("labels", s.labels).value_or(s.labels);
    if (auto done = r.finish(); !done) return done.error();
    return std::unique_ptr<scene::Layer>(new AnnotationLayer(s));
}

void AnnotationLayer::onPrepare(const render::RenderServices& services) {
    gpu::Device& device = *services.device;
    for (uint32_t i = 0; i < services.framesInFlight; ++i)
        vertices_.emplace_back(device, kMaxQuads * 6 * sizeof(shader::PolylineVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                               gpu::MemoryUsage::Upload, "annotation pins");
    const VkDescriptorSetLayout sets[] = {services.frameSetLayout};
    layout_ = gpu::createPipelineLayout(device, sets, {});
    gpu::GraphicsPipelineDesc d;
    d.vertexSpirv = kSpv_common_polyline_vert;
    d.fragmentSpirv = kSpv_common_polyline_frag;
    d.layout = layout_.vk();
    d.bindings = {{0, sizeof(shader::PolylineVertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.attributes = {{shader::kPolylineInputPosition, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(shader::PolylineVertex, position)},
                    {shader::kPolylineInputColor, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(shader::PolylineVertex, color)}};
    d.cullMode = VK_CULL_MODE_NONE;
    d.alphaBlend = true;
    d.depthWrite = false;
    d.depthTest = false;
    d.colorFormat = services.colorFormat;
    d.depthFormat = services.depthFormat;
    gpu::Specialization screen;
    screen.set<VkBool32>(shader::kPolylineSpecScreen, VK_TRUE);
    d.specialization = &screen;
    d.name = "annotation pins";
    pipeline_ = gpu::createGraphicsPipeline(device, d);
}

void AnnotationLayer::update(const scene::FrameContext& frame) {
    data_.clear();
    vertexCount_ = 0;
    pinsDrawn_ = 0;
    dropped_ = 0;
    pinsTotal_ = frame.annotations ? frame.annotations->size() : 0;
    if (!frame.annotations || !frame.camera || frame.annotations->empty()) return;
    const PinLayout layout = layoutPins(*frame.annotations, *frame.camera, frame.width, frame.height, frame.groundHeight,
                                        style_, kMaxQuads);
    const std::vector<PinQuad>& quads = layout.quads;
    dropped_ = layout.dropped;
    pinsDrawn_ = layout.drawn;
    if (dropped_ > 0 && !warnedDropped_) {
        log::warn("annotations: ", dropped_, " pin(s) in view are not drawn (at most ", kMaxQuads,
                  " rectangles a frame; the nearest pins come first)");
        warnedDropped_ = true;
    }
    data_.resize(quads.size() * 6 * sizeof(shader::PolylineVertex));
    auto* v = reinterpret_cast<shader::PolylineVertex*>(data_.data());
    const double w = frame.width, h = frame.height;
    for (const PinQuad& q : quads) {
        const glm::dvec2 corners[6] = {q.min, {q.max.x, q.min.y}, q.max, q.min, q.max, {q.min.x, q.max.y}};
        for (const glm::dvec2& c : corners) {
            v->position = glm::vec4(float(c.x / w * 2.0 - 1.0), float(c.y / h * 2.0 - 1.0), 1.0f, 1.0f);
            v->color = q.color;
            ++v;
        }
    }
    vertexCount_ = uint32_t(quads.size() * 6);
}

void AnnotationLayer::recordTransfers(const render::RecordContext& rc) {
    if (vertexCount_ > 0) vertices_[rc.slot].write(data_.data(), data_.size());
}

void AnnotationLayer::record(scene::Pass pass, const render::RecordContext& rc) {
    if (pass != scene::Pass::Overlay || vertexCount_ == 0) return;
    const VkDeviceSize zero = 0;
    vkCmdBindPipeline(rc.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.vk());
    vkCmdBindDescriptorSets(rc.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.vk(), shader::kFrameSet, 1, &rc.frameSet, 0, nullptr);
    const VkBuffer b = vertices_[rc.slot].vk();
    vkCmdBindVertexBuffers(rc.cmd, 0, 1, &b, &zero);
    vkCmdDraw(rc.cmd, vertexCount_, 1, 0, 0);
}

uint64_t AnnotationLayer::gpuBytes() const {
    uint64_t bytes = 0;
    for (const gpu::Buffer& b : vertices_) bytes += b.size();
    return bytes;
}

bool AnnotationLayer::setParameter(std::string_view name, double value) {
    if (name == "labelScale" && kLabelScaleRange.contains(value)) style_.labelScale = value;
    else if (name == "labels") style_.labels = value != 0.0;
    else return false;
    return true;
}

std::vector<scene::LayerSetting> AnnotationLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    return {
        {.name = "labels", .label = "Labels", .kind = Kind::Toggle, .value = style_.labels ? 1.0 : 0.0},
        {.name = "labelScale", .label = "Label size", .kind = Kind::Number, .value = style_.labelScale, .min = kLabelScaleRange.min, .max = kLabelScaleRange.max},
    };
}

std::string AnnotationLayer::status() const {
    std::string s = std::to_string(pinsTotal_) + " pin(s), " + std::to_string(pinsDrawn_) + " in view";
    if (dropped_ > 0) s += ", " + std::to_string(dropped_) + " in view not drawn";
    return s;
}

scene::LayerType AnnotationLayer::layerType() {
    return {scene::kAnnotationLayerType, "the scene's labelled pins (added by itself when the scene has any)", &AnnotationLayer::create, {}};
}

}  // namespace orbis::layers
