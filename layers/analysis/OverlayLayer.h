#pragma once
// "overlay": a raster draped on the ground as a picture over the terrain's own imagery: a
// processing job's result (slope, hillshade, a viewshed as a GeoTIFF), a scanned map, any file
// GDAL reads in any CRS (RasterSource warps it to the tiles).
//
//   {"type": "overlay", "name": "Slope", "path": "slope.tif",
//    "opacity": 0.8,
//    "bands": [1],                // 1-based; default 1,2,3 or the single band (grey / colour table)
//    "scale": [0, 60],            // values mapped to 0..255 (default: Byte as is, else min..max)
//    "noData": -9999}             // overrides the file's
//
// The file is opened on the worker pool when the layer is first shown; the terrain paints it
// into its tiles like any drape. Needs a ground layer (terrain) to drape on; nothing is opened
// for a scene without one that shows it.

#include "base/Result.h"
#include "base/ThreadPool.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/LayerSetting.h"
#include "engine/scene/SceneDesc.h"
#include "globe/RasterSource.h"

#include <functional>
#include <memory>
#include <string>

namespace orbis::layers {

class OverlayLayer : public scene::Layer, public scene::DrapedContent, public scene::LiveSettings {
public:
    static scene::LayerType layerType();
    static Result<std::unique_ptr<scene::Layer>> create(const scene::LayerDesc& desc, const scene::SceneDesc& scene);

    OverlayLayer(globe::RasterSourceOptions options, double opacity);
    ~OverlayLayer() override;

    std::string_view type() const override { return "overlay"; }
    bool drawsIn(scene::Pass) const override { return false; }
    void record(scene::Pass, const render::RecordContext&) override {}
    void poll() override;
    bool busy() const override { return opening_.valid(); }
    std::string status() const override;

    const scene::DrapedContent* asDrapedContent() const override { return this; }
    std::shared_ptr<const globe::TileImageSource> drapeSource() const override { return source_; }
    uint64_t drapeVersion() const override { return source_ ? 1 : 0; }
    double drapeOpacity() const override { return opacity_; }
    double drapeReach() const override { return 0.0; }

    scene::LiveSettings* asLiveSettings() override { return this; }
    std::vector<scene::LayerSetting> liveSettings() const override;
    bool setParameter(std::string_view name, double value) override;

    /// The opened raster (null while opening or after an error).
    const globe::RasterSource* source() const { return source_.get(); }
    const std::string& error() const { return error_; }

private:
    void onPrepare(const render::RenderServices& services) override;

    globe::RasterSourceOptions options_;
    double opacity_ = 1.0;
    jobs::Job<Result<std::shared_ptr<globe::RasterSource>>> opening_;
    std::shared_ptr<const globe::RasterSource> source_;
    std::string error_;
};

}  // namespace orbis::layers
