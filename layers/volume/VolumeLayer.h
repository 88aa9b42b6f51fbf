#pragma once
// "volume": a scalar field on a (lon, lat, height) grid drawn where it is on the globe, in a box
// that follows the Earth's curvature, by ray casting in a compute shader before the volume
// pass (rays end at the scene depth), composited over the scene inside the pass.
//
//   {"type": "volume", "name": "Air temperature",
//    "path": "air.nc", "variable": "t", "timeStep": 0, "pressureToHeight": "standard" | "scaleHeight",
//    -- or, instead of a file --
//    "synthetic": {"field": "sphere" | "waves" | "constant" | "empty", "size": [64, 64, 64],
//                  "lon": [-10, 10], "lat": [40, 60], "height": [0, 200000],
//                  "times": ["2026-06-21T00:00:00Z", "2026-06-21T06:00:00Z"]},
//    "time": "blend" | "nearest" | "fixed",
//    "mode": ["dvr", "iso", "slice"], "isovalues": [250, 280], "isoOpacity": 1,
//    "slices": [{"lon": 5}, {"lat": 45}, {"height": 10000}], "sliceOpacity": 1,
//    "steps": 100, "colorMap": "viridis", "range": [200, 310],
//    "opacity": [[200, 0], [310, 0.5]], "opacityScale": 1, "verticalExaggeration": 1,
//    "preIntegration": false, "rayResolution": 1, "refineThreshold": 0.05}
//
// Rays are clipped to the box and to the shell between its bottom and top heights, then sampled
// in equal steps of the box's normalised coordinates ("steps" along its diagonal), so a thin
// shell gets as many samples across as a thick box. The transfer function's opacity is per
// hundredth of that diagonal, so changing "steps" changes quality, not the look. Isosurfaces
// are found by sign changes between samples and refined by secant/bisection steps. Slices are
// exact ray hits with a meridian half-plane, a cone of constant geodetic latitude or a surface
// of constant height. What the modes do not use is left out of the compute pipeline
// (specialisation constants).

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "engine/gpu/Pipeline.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/SceneDesc.h"
#include "layers/volume/VolumeData.h"
#include "layers/volume/VolumeReader.h"
#include "layers/volume/VolumeSettings.h"
#include "layers/volume/VolumeUniforms.h"

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace orbis::layers {

/// A synthetic field for tests and benchmarks: "sphere" is the distance from the grid's centre
/// in voxel units (known geometry: every isosurface is a sphere in index space), "waves" a
/// smooth product of sines, "constant" 1 everywhere (zero gradient), "empty" all no data,
/// "peer" the field of the VTK peer benchmark (../shared/peers/vtk_peer.py) over the box mapped
/// onto [-1, 1]^3: sin(3x) cos(2y) z + 1.5 exp(-|p - (0.3, -0.2, 0.2)|^2 / (2 0.3^2)).
struct SyntheticVolume {
    std::string field = "sphere";
    size_t nx = 64, ny = 64, nz = 64;
    double west = -10, east = 10, south = 40, north = 60, bottom = 0, top = 200000;
    /// Time steps (UTC); time step s holds the field plus s. Empty: one time step, no time.
    std::vector<TimeNs> times;
};
VolumeField makeSyntheticVolume(const SyntheticVolume& s);

class VolumeLayer final : public scene::Layer, public scene::LiveSettings, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);
    VolumeLayer(VolumeField field, VolumeSettings settings, std::vector<std::vector<float>> moreTimeSteps = {},
                std::vector<TimeNs> timeStepTimes = {});
    ~VolumeLayer() override;

    std::string_view type() const override { return "volume"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Volume; }
    bool computesBefore(scene::Pass pass) const override { return pass == scene::Pass::Volume; }
    void recordCompute(scene::Pass pass, const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    /// Live edits; the field is never re-uploaded. Uniforms only: "steps", "isovalue" /
    /// "isovalue0".."isovalue7" (also refreshes the brick bits, 1 bit per brick), "slice0"..
    /// "slice3" (the slice's lon, lat or height), "opacityUnit", "isoOpacity", "sliceOpacity".
    /// The transfer function (a 256-entry table and the brick bits): "rangeMin", "rangeMax",
    /// "opacityScale". "emptySkipping" 0 or 1 (where the scene built the ray caster with skipping).
    /// "preIntegration" 0 or 1 (the ray caster is rebuilt; the 2-D table is made or released;
    /// the table is also rebuilt when the transfer function, "steps" or "opacityUnit" change).
    /// "rayResolution" (0.125..1: the reduced image is remade; the passes are rebuilt when it
    /// crosses 1), "refineThreshold" (0..1, a uniform).
    bool setParameter(std::string_view name, double value) override;
    /// "colorMap": one of colorMapNames() (rebuilds the 256-entry table).
    bool setOption(std::string_view name, std::string_view value) override;
    /// "opacity": the transfer function's opacity control points, (value, alpha).
    bool setCurve(std::string_view name, const std::vector<glm::dvec2>& points) override;
    /// Every setting above that the scene uses (one "isovalueN" per isovalue, one "sliceN" per
    /// slice). Most are the scene file's keys; "rangeMin"/"rangeMax", "isovalueN" and "sliceN"
    /// are elements of "range", "isovalues" and "slices", which the scene saver maps
    /// (scene::writeLiveSettings).
    std::vector<scene::LayerSetting> liveSettings() const override;
    std::string status() const override;

    /// Measurement (tests, benchmarks), set before the first frame: write each ray's first
    /// isosurface distance (metres from the eye along the ray; -1 for none), and find crossings
    /// with or without secant/bisection refinement.
    void setMeasurement(bool hitOutput, bool refine) { hitOutput_ = hitOutput, refine_ = refine; }
    /// The distances written by the last frame (after it completed), row by row.
    std::vector<float> hitDistances() const;
    /// Fractional voxel coordinates (along lon, lat, height; sample i at i) of an ECEF point,
    /// in double precision: to measure how far apart two hits are, in voxels.
    glm::dvec3 voxelAt(const glm::dvec3& ecef) const;

    const VolumeField& field() const { return field_; }
    size_t timeSteps() const { return 1 + moreTimeSteps_.size(); }
    /// The time steps shown now: (A, B, weight of B), from the last update().
    glm::vec3 timeBlend() const { return {timeStepA_, timeStepB_, timeStepWeight_}; }
    const VolumeSettings& settings() const { return settings_; }
    /// Whether the ray caster was built with empty-space skipping (after prepare()).
    bool skipsEmptyBricks() const { return skipEmpty_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    // prepare(), in order: the field's texels (time steps stacked along z, with the wrap column
    // of a periodic field), the axis lookups (returns their table), the brick grid, half floats
    // (sets fieldScale_, releases the floats), the GPU objects and their upload, the ray caster.
    std::vector<float> stackTexels();
    std::vector<float> buildLookups();
    void buildBricks(const std::vector<float>& texels);
    std::vector<uint16_t> toHalfFloats(std::vector<float>& texels);
    void uploadData(const std::vector<float>& texels, const std::vector<uint16_t>& halves,
                    const std::vector<float>& axisTable);
    void createRayCaster();
    gpu::Specialization rayCasterModes(int pass);   // also decides skipEmpty_ (the first time)
    // recordCompute(), in order: the cast image and the descriptors, the uniforms, the live
    // edits (transfer function, brick bits), the dispatch, the hit distances' readback.
    void ensureCastImage(uint32_t width, uint32_t height);
    void writeDescriptors(uint32_t frameSlot);
    VolumeFrameInputs frameInputs(const scene::Camera& camera) const;
    void recordEdits(VkCommandBuffer cmd);
    void ensurePreIntegrationImage();   // the table's size follows the setting (1 x 1 when off)
    bool preIntegrates() const;         // DVR steps read the pre-integrated table
    bool reducedRays() const;           // rays at a reduced resolution, then the refining pass
    void createCastPipelines();         // the pass(es) the settings use
    void recordDispatches(VkCommandBuffer cmd, const render::RecordContext& rc, uint32_t width, uint32_t height);
    std::vector<uint16_t> preIntegrationTexels() const;   // RGBA16F, from transferTable_
    void recordHitReadback(VkCommandBuffer cmd, uint32_t width, uint32_t height);

    VolumeField field_;                               // time step 0 (or the fixed one), with the grid
    std::vector<std::vector<float>> moreTimeSteps_;   // the values of time steps 1.., when time animates
    std::vector<TimeNs> timeStepTimes_;               // one per uploaded time step (empty: no time)
    float timeStepA_ = 0.0f, timeStepB_ = 0.0f, timeStepWeight_ = 0.0f;
    VolumeSettings settings_;
    const render::RenderServices* services_ = nullptr;
    render::RenderServices servicesCopy_;

    VolumeBox box_;                     // the curved box in its frame
    glm::dvec2 fieldScale_{1.0, 0.0};   // value = stored * x + y
    std::vector<double> lonAxis_;   // with the wrap column when the field is periodic
    std::array<AxisLookup, 3> lookups_;
    uint64_t frameCounter_ = 0;

    gpu::Image fieldImage_, transferImage_, castImage_;
    gpu::Buffer axisBuffer_;
    // Empty-space skipping: min/max per brick (the union over time steps) and one bit per brick
    // for "can show something", refreshed when the isovalues or the setting change.
    BrickGrid bricks_;
    std::vector<std::array<float, 4>> transferTable_;
    std::vector<uint32_t> occupancy_;
    bool occupancyDirty_ = false;
    bool transferDirty_ = false;   // the table changed: rebuilt and uploaded with the next frame
    std::vector<uint16_t> transferTexels();   // rebuilds transferTable_; RGBA16F texels
    bool skipEmpty_ = false;   // the pipeline tests bricks
    bool skippingDecided_ = false;   // skipEmpty_ is chosen once, by the first pipeline
    // Pre-integration: the 2-D table (kVolumeTransferSize squared, or 1 x 1 when the setting is
    // off), rebuilt and uploaded with the next frame when dirty; the pipeline is rebuilt when
    // the setting changes.
    gpu::Image preImage_;
    bool preDirty_ = true;
    bool pipelineDirty_ = false;
    gpu::Buffer occupancyBuffer_;
    void updateOccupancy();
    std::vector<gpu::Buffer> uniformBuffers_;
    gpu::Sampler linearSampler_, nearestSampler_;
    gpu::DescriptorSets descriptors_;   // one set per frame in flight
    gpu::PipelineLayout layout_;
    gpu::Pipeline castPipeline_, compositePipeline_;
    gpu::Pipeline refinePipeline_;   // rays at a reduced resolution only: the full-resolution pass
    gpu::Image lowImage_;            // rgba16f: the reduced-resolution rays, or 1 x 1 (never written)
    gpu::Image* boundDepth_ = nullptr;
    bool hitOutput_ = false, refine_ = true;
    gpu::Image hitImage_;        // r32f: the frame's size with hitOutput_, else 1 x 1 (never written)
    gpu::Buffer hitReadback_;
    uint64_t imagesVersion_ = 1;            // bumped when the cast image or the depth changes
    std::vector<uint64_t> setVersion_;      // per frame slot: the version its set names
};

}  // namespace orbis::layers
