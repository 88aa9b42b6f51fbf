#pragma once
// "viewshed": what an observer sees of the terrain around it, computed on the GPU
// (ViewshedGpu) and draped on the ground (ViewshedDrape: seen cells green, hidden ones red).
//
//   {"type": "viewshed", "name": "From the mast",
//    "dem": "hills.tif",            // or "synthetic": SEED (globe/SyntheticTerrain.h)
//    "observer": [8.52, 46.51],     // lon, lat
//    "height": 10,                  // the eye above the ground, metres
//    "target": 0,                   // what must be seen above the ground at each cell
//    "radius": 5000,                // metres
//    "cell": 30,                    // grid cell, metres (default: the DEM's pixel)
//    "curvature": 0.85714,          // gdal_viewshed's -cc (0: a flat Earth)
//    "opacity": 0.8,
//    "seen": [0.27, 0.9, 0.35, 0.6], "hidden": [0.9, 0.2, 0.15, 0.45]}   // sRGB + alpha
//
// The ground comes from the DEM at its own resolution (ElevationSampler), not from the tiles
// the view has streamed, sampled on the worker pool into a grid 1.25 radii around the observer.
// Moving the observer (live settings observerLon / observerLat, the viewer's drag) computes the
// viewshed again on the same grid while the circle fits in it; past that the grid is sampled
// again around the new place (the old one is used meanwhile). The layer needs a ground layer
// (terrain) to drape on. Nothing is built, sampled or started for a scene without one.

#include "base/Result.h"
#include "base/ThreadPool.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "globe/Viewshed.h"
#include "layers/analysis/ViewshedDrape.h"

#include <memory>
#include <optional>
#include <string>

namespace orbis::layers {

class ViewshedGpu;

struct ViewshedSettings {
    std::string dem;                  ///< resolved path; empty with a synthetic seed
    std::optional<uint32_t> synthetic;
    globe::LonLat observer{0.0};
    double height = 2.0, target = 0.0, radiusM = 5000.0, cellM = 0.0, curvature = 0.85714, opacity = 0.8;
    ViewshedColors colors;
};

class ViewshedLayer : public scene::Layer, public scene::DrapedContent, public scene::LiveSettings {
public:
    static scene::LayerType layerType();
    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);
    static constexpr scene::SettingRange kHeightRange{-100.0, 100000.0};
    static constexpr scene::SettingRange kTargetRange{0.0, 10000.0};
    /// Grid cells at most (a side of about 4000).
    static constexpr size_t kMaxCells = size_t(16) << 20;

    explicit ViewshedLayer(ViewshedSettings settings);
    ~ViewshedLayer() override;

    std::string_view type() const override { return "viewshed"; }
    bool drawsIn(scene::Pass) const override { return false; }
    void record(scene::Pass, const render::RecordContext&) override {}
    void poll() override;
    bool busy() const override;
    std::string status() const override;

    const scene::DrapedContent* asDrapedContent() const override { return this; }
    std::shared_ptr<const globe::TileImageSource> drapeSource() const override { return drape_; }
    uint64_t drapeVersion() const override { return version_; }
    double drapeOpacity() const override { return settings_.opacity; }
    std::optional<std::vector<globe::GeoExtent>> drapeChangedSince(uint64_t version) const override;
    double drapeReach() const override { return 0.0; }

    scene::LiveSettings* asLiveSettings() override { return this; }
    std::vector<scene::LayerSetting> liveSettings() const override;
    bool setParameter(std::string_view name, double value) override;

    /// The last viewshed computed and its grid (none yet: null).
    const globe::Viewshed* viewshed() const { return viewshed_.get(); }
    const globe::ViewshedGrid* grid() const { return grid_.get(); }
    const std::string& error() const { return error_; }
    /// Grids sampled and viewsheds computed so far, and the last one's GPU time.
    int gridsSampled() const { return gridsSampled_; }
    int computed() const { return computed_; }
    double lastGpuMs() const { return lastGpuMs_; }

private:
    void onPrepare(const render::RenderServices& services) override;
    void startSampling();
    /// The observer's cell in the current grid when the circle fits in it.
    std::optional<std::pair<int, int>> observerCell() const;

    ViewshedSettings settings_;
    globe::HeightAt ground_;
    std::function<jobs::ThreadPool&()> jobs_;
    std::unique_ptr<ViewshedGpu> gpu_;
    jobs::Job<Result<globe::ViewshedGrid>> sampling_;
    std::shared_ptr<const globe::ViewshedGrid> grid_;
    std::shared_ptr<const globe::Viewshed> viewshed_;
    std::shared_ptr<const ViewshedDrape> drape_;
    std::vector<globe::GeoExtent> changed_;   ///< the previous and the current drape's boxes
    bool uploaded_ = false, dirty_ = true;
    uint64_t version_ = 0;
    std::string error_;
    int gridsSampled_ = 0, computed_ = 0;
    double lastGpuMs_ = 0.0;
};

}  // namespace orbis::layers
