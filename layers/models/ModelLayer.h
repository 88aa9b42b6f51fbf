#pragma once
// "model": a glTF 2.0 model placed on the globe, standing still or moving along a trajectory or
// a live position feed on the scene's virtual time, with its path drawn as a line and a label.
//
//   {"type": "model", "name": "Train", "file": "models/train.glb",
//    "scale": 1, "minimumPixelSize": 0, "opacity": 1, "orientation": [0, 0, 0], "color": [1, 1, 1],
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
//    "label": true | "text", "labelColor": [1, 1, 1],
//    "animation": false | {"name": "Walk" | "index": 0, "loop": true, "speed": 1,
//                          "start": "2026-03-20T08:00:00Z"}}
//
// Axes: the model's glTF axes (+Y up, +Z front) are put on the body axes of the pose (x forward,
// y right, z down; formats/motion/Attitude.h), after "orientation" (heading, pitch, roll in
// degrees, to turn a model whose front is not +Z) and "scale". "minimumPixelSize" scales a
// model up when it would cover fewer pixels than that (0: true size only).
//
// On the ground: a model on a trajectory or live feed whose altitude is "ground" (at most 1 m
// above it, clampToGround included) keeps its track's heading and pitches and rolls with the
// terrain under its footprint, the bounding box on the body axes at "scale"
// (formats/motion/GroundAttitude.h). A model at a fixed position keeps its "attitude".
//
// Copies: `count` models along the same trajectory, copy i at (t - i x spacing): a train's
// wagons, a convoy, or the benchmark's 1 000 animated models. One instanced draw per glTF
// primitive draws every copy.
//
// Animation (layers/models/GltfAnimation.h). A model with animations (glTF's, or a mesh file's
// node animations, MeshModel.h) plays one on the scene's virtual time, never the wall clock: the
// first unless "animation" names another (by name or index), looped unless "loop" is false, at
// "speed" animation seconds per scene second. Its time 0 is "start", by default the
// trajectory's first sample, else the scene's "time.start", else 1970-01-01T00:00:00Z. Copy i, which is where the model was i x spacing
// seconds earlier, is also in its animation i x spacing seconds earlier. "animation": false
// keeps the rest pose. Skins and morph targets are applied whether or not an animation plays.
//
// Animated models are drawn by model_animated.vert: each distinct animation time of a frame
// is evaluated once on the CPU (a few microseconds for a vehicle-sized rig, see `orbis bench`)
// into a pose block (node matrices, joint matrices, morph weights) that every copy drawn at that
// time shares; morphing and skinning happen in the vertex shader, so the vertex data stays on
// the GPU unchanged and a frame uploads only the poses (bytes per pose x distinct times).
// Skinning on the CPU would upload every vertex of every copy each frame. Models without skins,
// morph targets or animations keep the static path (model.vert, node matrices uploaded once).
// Pose blocks are bounded by kMaxPoseBytes per frame in flight; past that, copies share the
// pose evaluated last (the copy just before them in time).
//
// The path line is the trajectory between (t - trail) and t (trail 0: the whole path), drawn
// after the opaque geometry with depth test. The label is the layer's name (or the given text)
// beside the first copy, in the overlay pass, hidden when the model is behind the globe.

#include "base/Result.h"
#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Pipeline.h"
#include "engine/gpu/Image.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "layers/models/GltfAnimation.h"
#include "layers/models/GltfModel.h"
#include "layers/models/ModelMotion.h"
#include "shared/ModelTypes.h"

#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <string>
#include <vector>

namespace orbis::layers {

/// Pose blocks of an animated model, per frame in flight (see the header).
inline constexpr uint64_t kMaxPoseBytes = uint64_t(32) << 20;

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
    /// 0..1. Below 1 the model's depth is drawn first, then every material blends over the
    /// scene where it is nearest: the front surface shows, not the faces behind it.
    double opacity = 1.0;
    bool sunLighting = true;
    uint32_t copies = 1;
    double copySpacingSeconds = 1.0;
    ModelPathSettings path;
    bool label = false;
    std::string labelText;
    glm::dvec3 labelColor{1.0};
    models::AnimationPlayback animation;      ///< animation -1: the rest pose
};

class ModelLayer : public scene::Layer, public scene::LiveSettings, public scene::MovingContent, public scene::FloatingContent, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    /// The ranges its numeric settings may take, the same for the scene file (create), a live
    /// edit (setParameter) and the panel (liveSettings).
    static constexpr scene::SettingRange kScaleRange{1e-6, 1e6};
    static constexpr scene::SettingRange kMinimumPixelSizeRange{0.0, 1024.0};
    static constexpr scene::SettingRange kOpacityRange{0.0, 1.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    ModelLayer(ModelSettings settings, models::ModelData model, std::unique_ptr<models::ModelMotion> motion);
    ~ModelLayer() override;

    std::string_view type() const override { return "model"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::MovingContent* asMovingContent() const override { return this; }
    const scene::FloatingContent* asFloatingContent() const override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    void poll() override;
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override;
    void recordTransfers(const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    uint64_t itemsDrawn() const override { return drawnCopies_; }
    std::optional<double> nearestContent(const glm::dvec3& eye) const override;
    std::optional<scene::TimeRange> timeRange() const override;
    std::optional<scene::TrackedPose> trackedPose(TimeNs t, const scene::GroundHeightFn& ground) const override;
    std::optional<scene::ContentBounds> contentBounds() const override;
    std::string status() const override;
    /// Live: "scale" (1e-6 .. 1e6), "minimumPixelSize" (0 .. 1024 px) and "opacity" (0 .. 1).
    bool setParameter(std::string_view name, double value) override;
    /// The settings above, under the scene file's keys.
    std::vector<scene::LayerSetting> liveSettings() const override;

    const ModelSettings& settings() const { return settings_; }
    const models::ModelData& model() const { return model_; }
    /// The model-to-ECEF transform of copy 0 at the last update (rotation x scale, translation),
    /// for tests.
    const std::vector<glm::dmat4>& copyTransforms() const { return copyTransforms_; }
    /// Distinct poses evaluated at the last update (animated models; 0 for static ones).
    uint32_t posesThisFrame() const { return poseCount_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    struct Texture {
        gpu::Image image;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    void createFrameSets(const render::RenderServices& services);
    void createMaterialSets(gpu::Device& device);
    void buildPipelines(const render::RenderServices& services);
    void buildLinePipelines(const render::RenderServices& services);
    void uploadModel(const render::RenderServices& services);
    void uploadTextures(const render::RenderServices& services);
    /// The copies' draws of the materials `blended` selects, with `pipeline`.
    void drawCopies(const render::RecordContext& rc, const gpu::Pipeline& pipeline, bool blended);
    shader::ModelPush drawPush(uint32_t draw, const models::ModelMaterial* material) const;
    /// Half the model's extent along the body's x and y axes at the layer's scale: the
    /// footprint on which a vehicle on the ground follows the terrain's slope.
    motion::Footprint footprint() const;
    /// Model space -> ECEF (rotation x scale in the 3x3, the position in the translation).
    glm::dmat4 modelToEcef(const scene::TrackedPose& pose, double scale) const;
    void buildPath(const scene::FrameContext& frame);
    /// The pose block's first vec4 for copy time `t`, evaluated unless this frame has it already.
    uint32_t poseFor(TimeNs t);
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

    // Animated models only (model_.animated()).
    std::optional<models::PoseEvaluator> poser_;
    uint32_t poseCapacity_ = 0;                   ///< pose blocks per frame
    std::vector<glm::vec4> poseData_;             ///< this frame's blocks
    uint32_t poseCount_ = 0;
    uint64_t posesShared_ = 0;                    ///< copies that got a neighbour's pose (capacity full)
    std::unordered_map<uint64_t, uint32_t> poseOfTime_;   ///< animation seconds (bits) -> first vec4

    // GPU.
    gpu::Buffer vertices_, indices_, nodes_;
    gpu::Buffer skinVertices_, morphDeltas_;      ///< animated models: joints/weights stream, morph deltas
    std::vector<gpu::Buffer> poseBuffers_;        ///< animated models: one per frame in flight
    std::vector<gpu::Buffer> instanceBuffers_;    ///< one per frame in flight
    std::vector<gpu::Buffer> pathBuffers_, labelBuffers_;
    uint32_t maxCopies_ = 0;
    gpu::DescriptorSets frameSets_;               ///< set 1 per frame in flight
    gpu::DescriptorSets materialSets_;            ///< set 2: one per texture
    std::map<uint32_t, gpu::Sampler> samplers_;   ///< by wrap u and v (createMaterialSets)
    std::vector<Texture> textures_;               ///< one per model texture, then a white one
    gpu::PipelineLayout layout_, lineLayout_;
    gpu::Pipeline opaque_, blend_, depthOnly_, path_, label_;
    /// How blend_ and depthOnly_ are made, for a model whose opacity drops below 1 later
    /// (built then, in update()).
    std::optional<gpu::GraphicsPipelineDesc> blendDesc_;
    void buildTranslucentPipelines();
    gpu::Device* device_ = nullptr;
    uint64_t gpuBytes_ = 0;
};

}  // namespace orbis::layers
