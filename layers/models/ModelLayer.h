#pragma once
// "model": a glTF 2.0 model placed on the globe, standing still or moving along a trajectory or
// a live position feed on the scene's virtual time, with its path drawn as a line and a label.
//
//   {"type": "model", "name": "Train", "file": "models/train.glb",
//    "scale": 1, "minimumPixelSize": 0, "orientation": [0, 0, 0], "color": [1, 1, 1],
//    "lighting": "sun" | "headlight",
//    // one of:
//    "position": [lon, lat, height], "attitude": [heading, pitch, roll], "altitude": "ellipsoid" | "ground",
//    "trajectory": {"file": "track.csv", "interpolation": "linear" | "catmull-rom",
//                   "altitude": "ellipsoid" | "msl" | "ground" (default: from the file),
//                   "clampToGround": false, "extrapolate": "hold" | "linear" | "hide",
//                   "start": "2026-03-20T08:00:00Z"},   // time 0 of files with relative times
//    "live": {"url": "tcp://127.0.0.1:5000", "protocol": "nmea" | "xml" | "auto", "altitude": "ellipsoid" | "ground"},
//    "copies": {"count": 1, "spacing": 1.0},          // followers, `spacing` seconds apart
//    "path": {"show": true, "trail": 0, "color": [1, 0.8, 0.2], "opacity": 1, "maxPoints": 4096},
//    "label": true | "text", "labelColor": [1, 1, 1]}
//
// Axes: the model's glTF axes (+Y up, +Z front) are put on the body axes of the pose (x forward,
// y right, z down; layers/motion/Attitude.h), after "orientation" (heading, pitch, roll in
// degrees, to turn a model whose front is not +Z) and "scale". "minimumPixelSize" scales a
// model up when it would cover fewer pixels than that (0: true size only).
//
// Copies: `count` models along the same trajectory, copy i at (t - i x spacing): a train's
// wagons, a convoy, or the benchmark's 1 000 animated models. One instanced draw per glTF
// primitive draws every copy.
//
// The path line is the trajectory between (t - trail) and t (trail 0: the whole path), drawn
// after the opaque geometry with depth test. The label is the layer's name (or the given text)
// beside the first copy, in the overlay pass, hidden when the model is behind the globe.

#include "engine/core/Result.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "engine/scene/Layer.h"
#include "engine/scene/SceneDesc.h"
#include "layers/models/GltfModel.h"
#include "layers/models/ModelMotion.h"

#include <memory>
#include <string>
#include <vector>

namespace orbis::layers {

struct ModelPathSettings {
    bool show = false;
    double trailSeconds = 0.0;               ///< 0: the whole path
    glm::dvec3 color{1.0, 0.8, 0.2};         ///< sRGB
    double opacity = 1.0;
    uint32_t maxPoints = 4096;
};

struct ModelSettings {
    std::string name;
    double scale = 1.0;
    double minimumPixelSize = 0.0;
    glm::dvec3 orientationDeg{0.0};          ///< heading, pitch, roll of the model on the body
    glm::dvec3 color{1.0};                   ///< sRGB tint
    bool sunLighting = true;
    uint32_t copies = 1;
    double copySpacingSeconds = 1.0;
    ModelPathSettings path;
    bool label = false;
    std::string labelText;
    glm::dvec3 labelColor{1.0};
};

class ModelLayer : public scene::Layer {
public:
    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    ModelLayer(ModelSettings settings, models::ModelData model, std::unique_ptr<models::ModelMotion> motion);
    ~ModelLayer() override;

    std::string_view type() const override { return "model"; }
    void prepare(const scene::RenderServices& services) override;
    void poll() override;
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override;
    void recordTransfers(const scene::RecordContext& context) override;
    void record(scene::Pass pass, const scene::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    uint64_t itemsDrawn() const override { return drawnCopies_; }
    std::optional<double> nearestContent(const glm::dvec3& eye) const override;
    std::optional<scene::TimeRange> timeRange() const override;
    std::optional<scene::TrackedPose> trackedPose(TimeNs t, const scene::GroundHeightFn& ground) const override;
    std::optional<scene::ContentBounds> contentBounds() const override;
    std::string status() const override;
    /// Live: "scale" (1e-6 .. 1e6) and "minimumPixelSize" (0 .. 1024 px).
    bool setParameter(std::string_view name, double value) override;
    /// The settings above, under the scene file's keys.
    std::vector<scene::LayerSetting> liveSettings() const override;

    const ModelSettings& settings() const { return settings_; }
    const models::ModelData& model() const { return model_; }
    /// The model-to-ECEF transform of copy 0 at the last update (rotation x scale, translation),
    /// for tests.
    const std::vector<glm::dmat4>& copyTransforms() const { return copyTransforms_; }

private:
    struct Texture {
        gpu::Image image;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    void buildPipelines(const scene::RenderServices& services);
    void uploadModel(const scene::RenderServices& services);
    /// Model space -> ECEF (rotation x scale in the 3x3, the position in the translation).
    glm::dmat4 modelToEcef(const scene::TrackedPose& pose, double scale) const;
    void buildPath(const scene::FrameContext& frame);
    void buildLabel(const scene::FrameContext& frame);

    ModelSettings settings_;
    models::ModelData model_;
    std::unique_ptr<models::ModelMotion> motion_;
    glm::dmat3 modelToBody_{1.0};             ///< glTF axes -> body, with "orientation"

    // Per frame (CPU).
    std::vector<glm::dmat4> copyTransforms_;  ///< every visible copy, model -> ECEF
    std::optional<scene::TrackedPose> leadPose_;   ///< copy 0's pose this frame (the label's anchor)
    glm::dvec3 eye_{0.0};
    uint32_t drawnCopies_ = 0;
    std::vector<std::byte> instanceData_;
    std::vector<std::byte> pathData_;
    uint32_t pathVertices_ = 0;
    std::vector<std::byte> labelData_;
    uint32_t labelVertices_ = 0;

    // GPU.
    gpu::Buffer vertices_, indices_, nodes_;
    std::vector<gpu::Buffer> instanceBuffers_;    ///< one per frame in flight
    std::vector<gpu::Buffer> pathBuffers_, labelBuffers_;
    uint32_t maxCopies_ = 0;
    gpu::DescriptorSets frameSets_;               ///< set 1 per frame in flight
    gpu::DescriptorSets materialSets_;            ///< set 2: one per texture
    gpu::Sampler repeatSampler_, clampSampler_;
    std::vector<Texture> textures_;               ///< one per model texture, then a white one
    gpu::PipelineLayout layout_, lineLayout_;
    gpu::Pipeline opaque_, blend_, path_, label_;
    uint64_t gpuBytes_ = 0;
};

}  // namespace orbis::layers
