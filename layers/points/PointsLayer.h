#pragma once
// "points": a LAS point cloud on the globe, drawn by compute rasterisation before the points
// pass and resolved inside it (or, as a fallback, as a point list).
//
//   {"type": "points", "name": "Survey", "path": "cloud.las",
//    "crs": "EPSG:2992",                                  -- overrides the file's CRS
//    "origin": {"lon": 9, "lat": 46, "height": 500},      -- instead: local metres east/north/up
//    "color": "rgb" | "intensity" | "classification" | "height" | "constant",
//    "constantColor": [1, 0.8, 0.2], "heightRange": [0, 1] (of the cloud's heights),
//    "pointSize": 1, "opacity": 1, "edl": true, "edlStrength": 1, "edlRadius": 1.4,
//    "pointBudget": 3000000, "gpuMemoryMB": 1024, "cpuMemoryMB": 512,
//    "gpuPageMB": 0 (the device's maxStorageBufferRange; smaller only to test the paging),
//    "cacheFolder": "cache/", "renderer": "compute" | "pointList"}
//
// The file is opened (and its header and CRS checked) when the scene loads; the octree is built
// on a worker thread when the layer is first drawn (PointStore: in memory for clouds that fit
// "cpuMemoryMB", else into a cache file next to the LAS file or in "cacheFolder", reused by
// later runs). Each frame wants the nodes with the largest screen size first until
// "pointBudget" points (0: all), culled by the view and the horizon; those not on the GPU are
// read (from the cache file, on workers) and uploaded within a per-frame budget into a buffer of
// "gpuMemoryMB", evicting the nodes wanted least recently (NodeResidency). A node is drawn once
// it and its ancestors are resident. That buffer is bound a page at a time (one splat dispatch
// per page): a device's maxStorageBufferRange (128 MB on lavapipe) can be less than the budget.
//
// Compute rasterisation: every point writes (depth << 32 | index) with a 64-bit atomic into a
// screen buffer, then a full-screen pass writes colour and depth, depth-tested against the
// opaque scene, with eye-dome lighting. The point-list pipeline is the fallback on devices
// without 64-bit buffer atomics, and the baseline the compute path is benchmarked against.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Pipeline.h"
#include "base/ThreadPool.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "layers/points/NodeResidency.h"
#include "layers/points/PointCloud.h"
#include "shared/PointTypes.h"

#include <glm/glm.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace orbis::layers {

struct PointsSettings {
    enum class Color { Rgb, Intensity, Classification, Height, Constant } color = Color::Rgb;
    glm::dvec3 constantColor{1.0, 1.0, 1.0};   ///< sRGB
    glm::dvec2 heightRange{0.0, 1.0};          ///< the ramp over this part of the cloud's heights
    int pointSize = 1;                         ///< pixels (a disc of this diameter), 1..15
    /// 0..1, the cloud over what is behind it: the compute path blends the one point each pixel
    /// keeps; the point list blends every point that passes the depth test (overlaps compound).
    double opacity = 1.0;
    bool edl = false;
    /// Level-aware sizes: each point as large as the spacing of the deepest level drawn at its
    /// place (at least pointSize), so that a point budget thins the cloud without holes.
    bool adaptiveSize = false;
    double edlStrength = 1.0, edlRadius = 1.4;   ///< radius in pixels
    uint64_t pointBudget = 3'000'000;            ///< points drawn per frame at most; 0: all
    uint64_t gpuMemoryBytes = uint64_t(1024) << 20;
    uint64_t gpuPageBytes = 0;   ///< what a shader sees at once; 0: the device's maxStorageBufferRange
    uint64_t cpuMemoryBytes = uint64_t(512) << 20;   ///< the octree build's working memory
    std::string cacheFolder;                         ///< empty: next to the file, else the user's cache
    bool mortonOrder = true;                         ///< points in a node along a Z-order curve (else in key order)
    enum class Renderer { Compute, PointList } renderer = Renderer::Compute;
};

class PointsLayer final : public scene::Layer, public scene::LiveSettings, public scene::FloatingContent, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    /// The ranges its numeric settings may take, the same for the scene file (create), a live
    /// edit (setParameter) and the panel (liveSettings).
    static constexpr scene::SettingRange kPointBudgetRange{0.0, 4e9};
    static constexpr scene::SettingRange kPointSizeRange{1.0, 15.0};
    static constexpr scene::SettingRange kOpacityRange{0.0, 1.0};
    static constexpr scene::SettingRange kEdlStrengthRange{0.0, 100.0};
    static constexpr scene::SettingRange kEdlRadiusRange{0.5, 8.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);
    PointsLayer(std::unique_ptr<points::LasFile> file, points::PointGeoreference georef, PointsSettings settings);
    ~PointsLayer() override;

    std::string_view type() const override { return "points"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::FloatingContent* asFloatingContent() const override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Points; }
    void recordTransfers(const render::RecordContext& context) override;
    bool computesBefore(scene::Pass pass) const override;
    void recordCompute(scene::Pass pass, const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    uint64_t cacheBytes() const override;
    uint64_t itemsDrawn() const override { return drawnPoints_; }
    bool busy() const override;
    std::optional<double> nearestContent(const glm::dvec3& eye) const override;
    std::string status() const override;
    /// Live: "pointBudget", "pointSize", "opacity", "edl" (0/1), "edlStrength", "edlRadius",
    /// "renderer" (0 compute, 1 point list; compute falls back to the point list on a device
    /// without 64-bit buffer atomics).
    bool setParameter(std::string_view name, double value) override;
    /// "color": rgb | intensity | classification | height | constant; "renderer": compute
    /// (false on a device without 64-bit buffer atomics) | pointList.
    bool setOption(std::string_view name, std::string_view value) override;
    /// The settings above under the scene file's keys (colour and renderer as choices).
    std::vector<scene::LayerSetting> liveSettings() const override;

    /// After loading: the octree (tests), or null while it loads or when loading failed.
    const points::PointStore* store() const { return store_.get(); }
    const points::NodeResidency* residency() const { return residency_.get(); }
    /// Loading's error, if it failed.
    const std::string& loadError() const { return loadError_; }
    const PointsSettings& settings() const { return settings_; }
    uint64_t pointsDrawn() const { return drawnPoints_; }
    size_t nodesDrawn() const { return drawList_.size(); }

private:
    void onPrepare(const render::RenderServices& services) override;
    void startLoading();
    void finishLoading();
    gpu::Pipeline& splatPipeline(int radius, bool quantised);
    gpu::Pipeline& pointListPipeline(bool quantised);
    gpu::Pipeline& resolvePipeline();
    /// The point-list or resolve pipeline for `spec`, made once per key.
    gpu::Pipeline& graphicsPipeline(std::map<int, gpu::Pipeline>& cache, int key, bool pointList,
                                    const gpu::Specialization& spec);
    void ensureScreen(uint32_t width, uint32_t height);
    void ensureFrameBuffers(uint32_t slot, size_t nodes, size_t batches);
    void writeDescriptors(uint32_t slot);
    void writeUniforms(const render::RecordContext& rc);
    bool computePath() const;
    /// False on a device (once prepared) without 64-bit buffer atomics.
    bool computeAvailable() const;
    uint32_t pageOffset(uint32_t page) const;   ///< dynamic offset of a page of data_

    std::shared_ptr<points::LasFile> file_;   // shared with the loading job
    points::PointGeoreference georef_;
    PointsSettings settings_;
    render::RenderServices services_;

    // Loading on a worker; the cloud once done.
    jobs::Job<Result<std::shared_ptr<points::PointStore>>> loadJob_;
    std::shared_ptr<std::atomic<double>> loadProgress_;
    std::shared_ptr<std::atomic<bool>> cancel_;
    std::shared_ptr<const points::PointStore> store_;
    std::unique_ptr<points::NodeResidency> residency_;
    std::string loadError_;
    uint64_t frame_ = 0, loadedFrame_ = 0;

    // This frame's selection: the nodes wanted (most important first) and those drawn.
    std::vector<int32_t> wanted_, drawList_;
    std::vector<uint64_t> drawnFrame_;   // per node: the last frame that drew it
    std::vector<uint8_t> levelsBelow_;   // per drawn node: the fewest levels drawn below it in any octant
    std::vector<shader::PointNode> nodeData_;   // the frame's drawn nodes and batches, as uploaded
    std::vector<shader::PointBatch> batchData_;
    std::vector<uint32_t> nodePage_;   // per drawn node: its page of data_
    struct Dispatch {                  // the batches of one position format and page
        bool quantised;
        uint32_t page, firstBatch, batches;
    };
    std::vector<Dispatch> dispatches_;
    uint64_t drawnPoints_ = 0;
    glm::dmat4 viewProj_{1.0};
    glm::dvec3 eye_{0.0};

    gpu::Buffer data_, screen_;   // the resident nodes' data; the compute rasteriser's screen
    struct Slot {
        gpu::Buffer uniforms, batches, nodes;
        VkDescriptorSet set = VK_NULL_HANDLE;
        uint64_t version = 0;   // of the buffers its set names
    };
    std::vector<Slot> slots_;
    uint64_t buffersVersion_ = 1;
    gpu::Sampler depthSampler_;
    gpu::DescriptorSets descriptors_;   // one set per frame in flight
    gpu::PipelineLayout layout_;
    std::map<int, gpu::Pipeline> splatPipelines_;   // by colour mode, splat radius and position format
    // By EDL, or colour mode and position format (specialisation constants: a CPU device pays
    // for every branch).
    std::map<int, gpu::Pipeline> resolvePipelines_, pointListPipelines_;
    gpu::Image* boundDepth_ = nullptr;
    bool gpuReady_ = false;
};

}  // namespace orbis::layers
