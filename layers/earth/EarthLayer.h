#pragma once
// "globe": the WGS84 ellipsoid with a lon/lat graticule, lit by the sun at the scene time, over
// a simple sky. The first picture of Orbis; terrain streaming (layers/terrain) replaces it.
//
//   {"type": "globe", "graticuleDeg": 15, "color": [0.1, 0.25, 0.5], "sky": true,
//    "lighting": "sun" | "headlight", "patchDeg": 10, "segments": 16}

#include "base/Result.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/Handle.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/SceneDesc.h"
#include "layers/earth/EarthMesh.h"

#include <memory>

namespace orbis::layers {

struct EarthSettings {
    double graticuleDeg = 15.0;                  ///< 0 = no graticule
    glm::dvec3 color{0.10, 0.24, 0.48};          ///< sRGB
    bool sky = true;
    bool sunLighting = true;                     ///< false: lit from the eye
    double patchDeg = 10.0;
    int segments = 16;
};

class EarthLayer : public scene::Layer, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    explicit EarthLayer(const EarthSettings& settings) : settings_(settings) {}

    std::string_view type() const override { return "globe"; }
    const scene::LayerStats* asStats() const override { return this; }
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Opaque; }
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;

    const EarthSettings& settings() const { return settings_; }
    /// Patches drawn in the last recorded frame (after culling).
    int patchesDrawn() const { return patchesDrawn_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    EarthSettings settings_;
    EarthMesh mesh_;
    gpu::Buffer vertices_;
    gpu::Buffer indices_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline surface_;
    gpu::Pipeline sky_;
    int patchesDrawn_ = 0;
};

}  // namespace orbis::layers
