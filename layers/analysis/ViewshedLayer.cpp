#include "layers/analysis/ViewshedLayer.h"

#include "base/Log.h"
#include "engine/render/RenderContext.h"
#include "engine/scene/JsonReader.h"
#include "globe/ElevationSampler.h"
#include "globe/GdalSetup.h"
#include "globe/RasterSource.h"
#include "globe/SyntheticTerrain.h"
#include "layers/analysis/ViewshedGpu.h"

#include <cmath>
#include <cstdio>

namespace orbis::layers {
namespace {

/// The grid reaches this many radii from its centre, so that the observer can move a little
/// without sampling again.
constexpr double kGridReach = 1.25;

std::array<uint8_t, 4> toBytes(const std::vector<double>& c) {
    std::array<uint8_t, 4> out{};
    for (size_t i = 0; i < 4; ++i) out[i] = uint8_t(std::lround(std::clamp(c[i], 0.0, 1.0) * 255.0));
    return out;
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> ViewshedLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    ViewshedSettings s;
    const auto dem = r.string("dem");
    if (r.has("synthetic")) {
        if (auto seed = r.number("synthetic", std::nullopt, 0.0, 4294967295.0)) {
            if (*seed != std::floor(*seed)) r.fail("synthetic", "the seed must be a whole number");
            s.synthetic = uint32_t(*seed);
        }
    }
    if (r.ok() && !!dem == !!s.synthetic) r.fail(dem ? "synthetic" : "dem", "give exactly one of \"dem\" (a DEM file) and \"synthetic\" (a seed)");
    if (dem) s.dem = scene.resolveSource(*dem);
    if (auto o = r.numbers("observer", 2)) {
        if (o->size() == 2) {
            if (std::abs((*o)[1]) > 90.0) r.fail("observer", "the latitude must be within -90..90");
            else if (std::abs((*o)[0]) > 540.0) r.fail("observer", "the longitude must be within -540..540");
            s.observer = {globe::wrapLongitude((*o)[0]), (*o)[1]};
        }
    } else if (r.ok()) {
        r.fail("observer", "the observer's place [lon, lat] is required");
    }
    s.height = r.number("height", s.height, kHeightRange.min, kHeightRange.max).value_or(s.height);
    s.target = r.number("target", s.target, kTargetRange.min, kTargetRange.max).value_or(s.target);
    s.radiusM = r.number("radius", s.radiusM, 1.0, 2000000.0).value_or(s.radiusM);
    s.cellM = r.number("cell", 0.0, 0.0, 100000.0).value_or(0.0);
    s.curvature = r.number("curvature", s.curvature, 0.0, 2.0).value_or(s.curvature);
    s.opacity = r.number("opacity", s.opacity, 0.0, 1.0).value_or(s.opacity);
    for (const char* key : {"seen", "hidden"}) {
        auto& target = std::string(key) == "seen" ? s.colors.seen : s.colors.hidden;
        if (!r.has(key)) continue;
        if (auto c = r.numbers(key, 4)) {
            if (c->size() == 4) {
                for (double v : *c)
                    if (v < 0.0 || v > 1.0) r.fail(key, "colour components must be in [0, 1]");
                target = toBytes(*c);
            }
        }
    }
    if (r.ok() && s.cellM > 0.0) {
        const double side = 2.0 * std::ceil(kGridReach * s.radiusM / s.cellM) + 1.0;
        if (s.cellM > s.radiusM) r.fail("cell", "the cell is larger than the radius");
        else if (side * side > double(kMaxCells))
            r.fail("cell", "a radius of " + std::to_string(s.radiusM) + " m at cells of " + std::to_string(s.cellM) + " m needs " +
                               std::to_string(size_t(side * side)) + " cells, more than " + std::to_string(kMaxCells) + ": use larger cells");
    }
    if (auto done = r.finish(); !done) return done.error();
    return std::unique_ptr<scene::Layer>(new ViewshedLayer(std::move(s)));
}

scene::LayerType ViewshedLayer::layerType() {
    return {"viewshed", "what an observer sees of the terrain, computed on the GPU and draped on the ground", &ViewshedLayer::create, {"/dem"}};
}

ViewshedLayer::ViewshedLayer(ViewshedSettings settings) : settings_(std::move(settings)) {}

ViewshedLayer::~ViewshedLayer() {
    if (sampling_.valid()) sampling_.cancel();
}

void ViewshedLayer::onPrepare(const render::RenderServices& services) {
    gpu_ = std::make_unique<ViewshedGpu>(*services.device);
    jobs_ = services.jobs;
    if (settings_.synthetic) {
        ground_ = globe::syntheticTerrain({.seed = *settings_.synthetic});
        if (settings_.cellM <= 0.0) settings_.cellM = 30.0;
    } else {
        globe::configureGdal();
        auto dem = globe::RasterSource::open({.path = settings_.dem, .role = globe::RasterRole::Elevation});
        if (!dem) {
            error_ = dem.message();
            log::error("viewshed: ", error_);
            return;
        }
        if (settings_.cellM <= 0.0)
            settings_.cellM = std::max(1.0, (*dem)->resolutionDeg() * 111320.0 * std::max(0.01, std::cos(settings_.observer.y * M_PI / 180.0)));
        ground_ = globe::ElevationSampler::function(std::make_shared<const globe::ElevationSampler>(*dem));
    }
    const double side = 2.0 * std::ceil(kGridReach * settings_.radiusM / settings_.cellM) + 1.0;
    if (side * side > double(kMaxCells)) {
        settings_.cellM *= std::sqrt(side * side / double(kMaxCells)) * 1.01;
        log::warn("viewshed: the DEM's pixel makes too large a grid for ", settings_.radiusM, " m around: cells of ", settings_.cellM,
                  " m instead");
    }
    startSampling();
}

void ViewshedLayer::startSampling() {
    if (sampling_.valid() && !sampling_.ready()) return;
    const globe::HeightAt ground = ground_;
    const globe::LonLat centre = settings_.observer;
    const double reach = kGridReach * settings_.radiusM, cell = settings_.cellM;
    sampling_ = jobs_().submit(0.0, jobs::CancelToken::create(), [ground, centre, reach, cell](const jobs::CancelToken&) {
        return globe::sampleViewshedGrid(ground, centre, reach, cell, kMaxCells);
    });
}

std::optional<std::pair<int, int>> ViewshedLayer::observerCell() const {
    if (!grid_) return std::nullopt;
    const auto cell = grid_->cellOf(settings_.observer.x, settings_.observer.y);
    if (!cell) return std::nullopt;
    const int need = int(std::ceil(settings_.radiusM / grid_->cellM));
    const int side = grid_->side();
    if (cell->first - need < 0 || cell->second - need < 0 || cell->first + need >= side || cell->second + need >= side) return std::nullopt;
    return cell;
}

void ViewshedLayer::poll() {
    if (!gpu_ || !error_.empty()) return;
    if (sampling_.valid() && sampling_.ready()) {
        auto grid = sampling_.get();
        sampling_ = {};
        if (!grid) {
            error_ = (settings_.dem.empty() ? std::string("synthetic terrain") : settings_.dem) + ": " + grid.message();
            log::error("viewshed: ", error_);
            return;
        }
        grid_ = std::make_shared<const globe::ViewshedGrid>(std::move(grid).value());
        uploaded_ = false;
        dirty_ = true;
        ++gridsSampled_;
    }
    if (!grid_ || !dirty_) return;
    auto cell = observerCell();
    if (!cell) {
        startSampling();   // the circle left the grid: sample around the observer again
        // Meanwhile, the old grid clipped, when the observer is still on it.
        cell = grid_->cellOf(settings_.observer.x, settings_.observer.y);
        if (!cell) return;
    }
    if (!uploaded_) {
        if (auto set = gpu_->setGrid(*grid_); !set) {
            error_ = set.message();
            return;
        }
        uploaded_ = true;
    }
    const globe::ViewshedOptions options{.observerCol = cell->first,
                                         .observerRow = cell->second,
                                         .observerHeight = settings_.height,
                                         .targetHeight = settings_.target,
                                         .radiusM = settings_.radiusM,
                                         .curvature = settings_.curvature};
    ViewshedTiming timing;
    auto v = gpu_->run(options, &timing);
    if (!v) {
        // No data under the observer: say so and wait for it to move.
        error_.clear();
        dirty_ = false;
        log::warn("viewshed: ", v.message());
        return;
    }
    lastGpuMs_ = timing.gpuMs > 0.0 ? timing.gpuMs : timing.submitMs;
    viewshed_ = std::make_shared<const globe::Viewshed>(std::move(v).value());
    auto drape = std::make_shared<const ViewshedDrape>("viewshed", grid_, viewshed_, settings_.colors);
    changed_.clear();
    if (drape_) changed_.push_back(drape_->bounds());
    changed_.push_back(drape->bounds());
    drape_ = std::move(drape);
    ++version_;
    ++computed_;
    dirty_ = false;
}

bool ViewshedLayer::busy() const {
    if (!gpu_ || !error_.empty()) return false;
    return sampling_.valid() || !grid_ || dirty_;
}

std::optional<std::vector<globe::GeoExtent>> ViewshedLayer::drapeChangedSince(uint64_t version) const {
    if (version + 1 != version_) return std::nullopt;
    return changed_;
}

std::string ViewshedLayer::status() const {
    if (!error_.empty()) return "error: " + error_;
    if (!viewshed_) return sampling_.valid() ? "sampling the ground" : "waiting";
    const size_t seen = viewshed_->count(globe::Sight::Visible), hidden = viewshed_->count(globe::Sight::Hidden);
    char s[160];
    std::snprintf(s, sizeof s, "%.1f %% of %zu cells seen, %.2f ms on the GPU, grid %d x %d of %.1f m%s",
                  seen + hidden ? 100.0 * double(seen) / double(seen + hidden) : 0.0, seen + hidden, lastGpuMs_, grid_->side(), grid_->side(),
                  grid_->cellM, sampling_.valid() ? ", sampling again" : "");
    return s;
}

std::vector<scene::LayerSetting> ViewshedLayer::liveSettings() const {
    using K = scene::LayerSetting::Kind;
    return {
        {.name = "observerLon", .label = "Observer longitude", .kind = K::Number, .value = settings_.observer.x, .min = -180.0, .max = 180.0,
         .pointer = "/observer/0"},
        {.name = "observerLat", .label = "Observer latitude", .kind = K::Number, .value = settings_.observer.y, .min = -90.0, .max = 90.0,
         .pointer = "/observer/1"},
        {.name = "height", .label = "Eye above the ground (m)", .kind = K::Number, .value = settings_.height, .min = 0.0, .max = 1000.0},
        {.name = "target", .label = "Target above the ground (m)", .kind = K::Number, .value = settings_.target, .min = kTargetRange.min,
         .max = 500.0},
        {.name = "opacity", .label = "Opacity", .kind = K::Number, .value = settings_.opacity, .min = 0.0, .max = 1.0},
    };
}

bool ViewshedLayer::setParameter(std::string_view name, double value) {
    if (!std::isfinite(value)) return false;
    if (name == "observerLon" && std::abs(value) <= 540.0) settings_.observer.x = globe::wrapLongitude(value);
    else if (name == "observerLat" && std::abs(value) <= 90.0) settings_.observer.y = value;
    else if (name == "height" && kHeightRange.contains(value)) settings_.height = value;
    else if (name == "target" && kTargetRange.contains(value)) settings_.target = value;
    else if (name == "opacity" && value >= 0.0 && value <= 1.0) {
        settings_.opacity = value;
        return true;   // the same drape, drawn lighter or darker
    } else return false;
    dirty_ = true;
    return true;
}

}  // namespace orbis::layers
