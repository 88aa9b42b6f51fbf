#include "layers/analysis/OverlayLayer.h"

#include "base/Log.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/JsonReader.h"
#include "globe/GdalSetup.h"

#include <cmath>
#include <cstdio>

namespace orbis::layers {

Result<std::unique_ptr<scene::Layer>> OverlayLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    globe::RasterSourceOptions options;
    options.role = globe::RasterRole::Imagery;
    if (const auto path = r.string("path")) {
        if (path->empty()) r.fail("path", "must name a raster file");
        options.path = scene.resolveSource(*path);
    }
    const double opacity = r.number("opacity", 1.0, 0.0, 1.0).value_or(1.0);
    if (r.has("bands")) {
        if (auto bands = r.numbers("bands", 0)) {
            if (bands->empty() || bands->size() > 4) r.fail("bands", "give 1 to 4 band numbers");
            for (double b : *bands) {
                if (b < 1.0 || b > 65535.0 || b != std::floor(b)) r.fail("bands", "band numbers are whole numbers from 1");
                else options.bands.push_back(int(b));
            }
        }
    }
    if (r.has("scale")) {
        if (auto scale = r.numbers("scale", 2)) {
            if (scale->size() == 2 && !((*scale)[0] < (*scale)[1])) r.fail("scale", "the first value must be below the second");
            else if (scale->size() == 2) options.scaleRange = std::pair((*scale)[0], (*scale)[1]);
        }
    }
    if (r.has("noData")) options.noData = r.number("noData");
    if (auto done = r.finish(); !done) return done.error();
    return std::unique_ptr<scene::Layer>(new OverlayLayer(std::move(options), opacity));
}

scene::LayerType OverlayLayer::layerType() {
    return {"overlay", "a raster (any CRS GDAL reads) draped on the ground over the terrain's imagery", &OverlayLayer::create, {"/path"}};
}

OverlayLayer::OverlayLayer(globe::RasterSourceOptions options, double opacity) : options_(std::move(options)), opacity_(opacity) {}

OverlayLayer::~OverlayLayer() {
    if (opening_.valid()) opening_.cancel();
}

void OverlayLayer::onPrepare(const render::RenderServices& services) {
    globe::configureGdal();
    const globe::RasterSourceOptions options = options_;
    opening_ = services.jobs().submit(0.0, jobs::CancelToken::create(),
                                      [options](const jobs::CancelToken&) { return globe::RasterSource::open(options); });
}

void OverlayLayer::poll() {
    if (!opening_.valid() || !opening_.ready()) return;
    auto opened = opening_.get();
    opening_ = {};
    if (!opened) {
        error_ = opened.message();
        log::error("overlay: ", error_);
        return;
    }
    source_ = std::move(opened).value();
}

std::string OverlayLayer::status() const {
    if (!error_.empty()) return "error: " + error_;
    if (!source_) return "opening " + options_.path;
    const globe::GeoExtent c = source_->coverage();
    char s[200];
    std::snprintf(s, sizeof s, "lon %.4f..%.4f, lat %.4f..%.4f, pixels of %.2f m", c.west, c.east, c.south, c.north,
                  source_->resolutionDeg() * 111320.0);
    return s;
}

std::vector<scene::LayerSetting> OverlayLayer::liveSettings() const {
    using K = scene::LayerSetting::Kind;
    return {{.name = "opacity", .label = "Opacity", .kind = K::Number, .value = opacity_, .min = 0.0, .max = 1.0}};
}

bool OverlayLayer::setParameter(std::string_view name, double value) {
    if (name != "opacity" || !std::isfinite(value) || value < 0.0 || value > 1.0) return false;
    opacity_ = value;
    return true;
}

}  // namespace orbis::layers
