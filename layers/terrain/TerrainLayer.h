#pragma once
// "terrain": the WGS84 globe streamed from DEMs and imagery that GDAL reads, as a quadtree of
// tiles selected by screen-space error. See DESIGN.md "Globe tiling".
//
//   {"type": "terrain", "name": "Earth",
//    "elevation": ["dem.tif", {"path": "other.tif", "band": 1, "noData": -32768}],
//    "imagery": [{"name": "Landsat", "path": "L7.tif", "bands": [3, 2, 1], "range": [0, 255],
//                 "opacity": 1.0, "visible": true},
//                {"name": "Lights", "path": "night.jpg", "bounds": [-180, -90, 180, 90], "night": true},
//                {"name": "OSM", "xyz": "http://127.0.0.1:8080/{z}/{x}/{y}.png"}],
//    "maxScreenSpaceError": 2, "gridSize": 65, "imageSize": 256, "maxLevel": 22,
//    "verticalExaggeration": 1, "color": [0.1, 0.24, 0.48], "lighting": "sun" | "headlight",
//    "sky": true, "cpuCacheMB": 256, "gpuCacheMB": 512, "uploadBudgetMB": 32, "tileBorders": false}
//
// "bounds" places a picture without georeferencing (plate carrée) on a lon/lat box. A source
// that cannot be opened is logged once and left out: the terrain still draws (the
// ellipsoid in the base colour stands in for it).
//
// Layers whose content lies on the ground (a vector layer, "clamped") drape it here: each is
// one more image layer after the scene's imagery (scene::DrapedContent, in FrameContext::drapes),
// its tiles painted by its source on the workers. At most kTerrainMaxImagery image layers in
// all; the pipeline is rebuilt when one is added.

#include "engine/gpu/Buffer.h"
#include "engine/gpu/Descriptors.h"
#include "engine/gpu/Handle.h"
#include "engine/gpu/Image.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "globe/RasterSource.h"
#include "globe/TerrainTiles.h"
#include "globe/TileSelector.h"
#include "globe/WmsTime.h"
#include "layers/terrain/TerrainGround.h"
#include "layers/terrain/TileSlotPool.h"
#include "shared/TerrainTypes.h"

#include <memory>
#include <string>
#include <vector>

namespace orbis::layers {

struct ImageryLayerSettings {
    std::string name;
    globe::RasterSourceOptions source;
    double opacity = 1.0;
    bool visible = true;
    /// Lights of the night side (city lights): shown where the sun is down, added after the
    /// lighting, not over the day imagery.
    bool night = false;
    /// A WMS layer's TIME values (scene key "time": its extent, as the server's capabilities
    /// give it): the layer shows the value in effect at the scene's time (TIME=... added to the
    /// request), its tiles painted again when the value changes, the old ones shown meanwhile.
    std::vector<globe::WmsTimeValue> times;
};

/// `source` asking its WMS for `time` (TIME=... added to the URL).
globe::RasterSourceOptions atWmsTime(const globe::RasterSourceOptions& source, const globe::WmsTimeValue& time);

struct TerrainSettings {
    std::vector<globe::RasterSourceOptions> elevation;
    std::vector<ImageryLayerSettings> imagery;
    double maxScreenSpaceError = 2.0;
    int gridSize = 65;
    int imageSize = 256;
    uint32_t maxLevel = 22;
    double verticalExaggeration = 1.0;
    glm::dvec3 color{0.10, 0.24, 0.48};   ///< sRGB, where no imagery
    bool sunLighting = true;
    bool sky = true;
    uint64_t cpuCacheBytes = 256ull << 20;
    uint64_t gpuCacheBytes = 512ull << 20;
    uint64_t uploadBudgetBytes = 32ull << 20;   ///< per frame, tile data (meshes are never held back)
    bool tileBorders = false;
};

struct TerrainStats {
    size_t tilesDrawn = 0;
    size_t tilesWithOwnElevation = 0;   ///< drawn with their own data (not an ancestor's)
    size_t uploadsThisFrame = 0;
    uint64_t uploadBytesThisFrame = 0;
    uint32_t deepestLevel = 0;
    globe::SelectionStats selection;
};

class TerrainLayer : public scene::Layer, public scene::LiveSettings, public scene::GroundSource, public scene::LayerStats {
public:
    /// The scene type: its name, description, factory (create) and the files its object names.
    static scene::LayerType layerType();
    /// The ranges its numeric settings may take, the same for the scene file (create), a live
    /// edit (setParameter) and the panel (liveSettings).
    static constexpr scene::SettingRange kScreenSpaceErrorRange{0.25, 1000.0};
    static constexpr scene::SettingRange kExaggerationRange{0.0, 1000.0};
    static constexpr scene::SettingRange kImageryOpacityRange{0.0, 1.0};

    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    explicit TerrainLayer(TerrainSettings settings);
    ~TerrainLayer() override;

    std::string_view type() const override { return "terrain"; }
    scene::LiveSettings* asLiveSettings() override { return this; }
    const scene::GroundSource* asGroundSource() const override { return this; }
    const scene::LayerStats* asStats() const override { return this; }
    void update(const scene::FrameContext& frame) override;
    bool drawsIn(scene::Pass pass) const override { return pass == scene::Pass::Opaque; }
    void recordTransfers(const render::RecordContext& context) override;
    void record(scene::Pass pass, const render::RecordContext& context) override;
    uint64_t gpuBytes() const override;
    /// The tiles the renderer keeps on the CPU and the ground-height cache (TerrainGround).
    uint64_t cacheBytes() const override;
    bool busy() const override;
    /// Live: "maxScreenSpaceError" (0.25 .. 1000 px), "verticalExaggeration" (0 .. 1000).
    bool setParameter(std::string_view name, double value) override;
    std::vector<scene::LayerSetting> liveSettings() const override;
    uint64_t itemsDrawn() const override { return stats_.tilesDrawn; }
    std::string status() const override;

    TerrainSettings& settings() { return settings_; }
    const TerrainSettings& settings() const { return settings_; }
    const TerrainStats& stats() const { return stats_; }
    /// The per-tile draw records of the last frame (shader::TileDraw each), for tests.
    const std::vector<uint8_t>& drawRecords() const { return drawData_; }
    /// The tiles selected for the last frame.
    const std::vector<globe::SelectedTile>& selection() const { return selector_->selection(); }
    /// The tiles on the CPU (sources, pager, cache, heights); null before prepare().
    globe::TerrainTiles* tiles() { return tiles_.get(); }
    const globe::TerrainTiles* tiles() const { return tiles_.get(); }
    /// Terrain height (metres above the ellipsoid, exaggerated as drawn) at a point, from the
    /// DEMs at their own resolution whatever has been streamed (TerrainGround.h): the same
    /// answer for the same point every time; nothing before prepare().
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    std::optional<double> groundHeightAt(double lonDeg, double latDeg) const override { return heightAt(lonDeg, latDeg); }
    /// The answers above change only with the vertical exaggeration.
    uint64_t groundVersion() const override { return groundChanges_; }
    /// The same heights from any thread (TerrainGround locks its cache), with the exaggeration
    /// of now.
    scene::GroundHeightFn groundSnapshot() const override;
    /// Problems met while opening sources and loading tiles.
    const std::vector<std::string>& errors() const { return errors_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    struct PendingUpload {
        TileSlotPool::Kind kind;
        uint32_t slot;
        globe::TileKey tile;
        uint32_t layer;
    };

    void openSources(const render::RenderServices& services);
    void createGpuObjects(const render::RenderServices& services);
    void buildPipelines(const render::RenderServices& services);
    /// A tile's height range as drawn (exaggerated, and the ellipsoid's 0 included).
    globe::TileHeightRange drawnHeights(const globe::TileKey& key) const;
    /// Takes what other layers drape on the ground this frame: new ones become image layers
    /// (the pipeline is rebuilt for the new count), changed ones are painted again.
    void syncDrapes(const std::vector<scene::Drape>& drapes);
    /// Image layers the surface blends: the scene's imagery, then the drapes.
    uint32_t imageLayerCount() const { return uint32_t(imageryIndex_.size() + drapes_.size()); }
    bool imageLayerVisible(uint32_t l) const;
    double imageLayerOpacity(uint32_t l) const;
    /// The residency of the selected tiles' data (uploads queued within the budget) and their draws.
    void buildDrawList(const scene::FrameContext& frame, const std::vector<globe::SelectedTile>& selected);
    shader::TileDraw tileDraw(const scene::Camera& camera, const glm::dmat4& proj, const globe::TileKey& key);
    /// The tile's mesh slot, its upload queued when new; nothing when no slot can be had.
    std::optional<uint32_t> meshSlot(const globe::TileKey& key);
    /// The deepest ready ancestor-or-self of `tile` whose data in `layer` is on the GPU or is
    /// queued to go there this frame, and its slot.
    std::optional<std::pair<globe::TileKey, uint32_t>> residentData(uint32_t layer, const globe::TileKey& tile);
    uint64_t fixedBytes() const;   ///< index and draw buffers
    void writeDescriptors(uint32_t frameSlot);
    /// The selected tiles, front to back (descriptor sets and push constants already set).
    void drawSurface(VkCommandBuffer cmd);
    /// Time-enabled imagery: a layer whose TIME value in effect at `t` changed gets the source
    /// for the new value.
    void followTime(TimeNs t);

    TerrainSettings settings_;
    std::vector<std::string> errors_;
    std::unique_ptr<globe::TerrainTiles> tiles_;
    std::shared_ptr<TerrainGround> ground_;   ///< heightAt's own DEM reads (shared with snapshots)
    uint64_t groundChanges_ = 0;
    std::unique_ptr<globe::TileSelector> selector_;
    render::RenderServices services_;
    uint64_t frame_ = 0;

    // GPU residency.
    std::unique_ptr<TileSlotPool> gpuSlots_;
    gpu::Buffer indices_;
    uint32_t indexCount_ = 0;
    std::vector<PendingUpload> uploads_;   // this frame's, queued by update()
    uint64_t uploadBytes_ = 0;

    // Per frame in flight: draw list and its descriptor set.
    std::vector<gpu::Buffer> drawBuffers_;
    std::vector<uint64_t> setVersion_;   // per set: the slot pool's version it names
    uint32_t maxDraws_ = 8192;
    struct DrawItem {
        uint32_t meshSlot;
        uint32_t drawIndex;
        double distance;
    };
    std::vector<DrawItem> drawItems_;
    std::vector<uint8_t> drawData_;   // TileDraw records for this frame

    gpu::DescriptorSets descriptors_;   // one set per frame in flight
    gpu::Sampler heightSampler_, imagerySampler_;
    gpu::PipelineLayout layout_;
    gpu::Pipeline surface_, sky_;

    TerrainStats stats_;
    bool warnedDrawCap_ = false;
    bool deferred_ = false;                 ///< ready data waited for upload budget this frame
    std::vector<size_t> imageryIndex_;      ///< model imagery layer i -> settings_.imagery index
    std::vector<size_t> timeShown_;         ///< model imagery layer i -> index of its TIME value shown
    struct DrapeLayer {
        const void* owner = nullptr;
        uint64_t version = 0;
        double opacity = 1.0;
        bool visible = false;   ///< named by this frame's drapes
    };
    std::vector<DrapeLayer> drapes_;        ///< image layers imageryIndex_.size() + i
    bool warnedDrapeCap_ = false;
};

}  // namespace orbis::layers
