#pragma once
// "annotations": draws the scene's labelled pins (Scene::annotations) over everything else.
// The scene adds it by itself when it has pins (Scene::ensureAnnotationLayer); a scene file may
// also list it to set its style:
//
//   {"type": "annotations", "name": "Pins", "color": [0.95, 0.35, 0.12], "labelScale": 2, "labels": true}
//
// Pins are screen-space rectangles (PinOverlay) rebuilt each frame on the CPU: a few hundred
// pins cost microseconds, and a pin hidden by a hill is left out (no depth test on the label).

#include "base/Result.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/Handle.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "layers/annotations/PinOverlay.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace orbis::layers {

class AnnotationLayer : public scene::Layer, public scene::LiveSettings, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    /// The ranges its numeric setting may take, the same for the scene file (create), a live
    /// edit (setParameter) and the panel (liveSettings).
    static constexpr scene::SettingRange kLabelScaleRange{0.5, 8.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    explicit AnnotationLayer(const PinStyle& style) : style_(style) {}

    std::string_view type() const override { return scene::kAnnotationLayerType; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Overlay; }
    void update(const scene::FrameContext& frame) override;
    void recordTransfers(const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    uint64_t itemsDrawn() const override { return pinsDrawn_; }
    bool setParameter(std::string_view name, double value) override;
    std::vector<scene::LayerSetting> liveSettings() const override;
    std::string status() const override;

private:
    void onPrepare(const render::RenderServices& services) override;
    PinStyle style_;
    std::vector<gpu::Buffer> vertices_;   ///< per frame in flight
    gpu::PipelineLayout layout_;
    gpu::Pipeline pipeline_;
    std::vector<std::byte> data_;
    uint32_t vertexCount_ = 0;
    uint64_t pinsDrawn_ = 0, pinsTotal_ = 0;
    std::size_t dropped_ = 0;
    bool warnedDropped_ = false;
};

}  // namespace orbis::layers
