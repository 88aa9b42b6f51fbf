// The scene-file side of the points layer: its keys, checked, and the file opened.
#include "engine/scene/JsonReader.h"
#include "layers/points/PointsLayer.h"

namespace orbis::layers {

Result<std::unique_ptr<scene::Layer>> PointsLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    PointsSettings s;
    const auto path = r.string("path");
    if (r.ok() && (!path || path->empty())) r.fail("path", "name the LAS file to show");
    points::PointPlacement placement;
    placement.crs = r.string("crs", std::string()).value_or("");
    if (const nlohmann::json* origin = r.object("origin")) {
        scene::JsonReader o(*origin, scene.file.string(), desc.jsonPath + "/origin");
        globe::Geodetic g;
        g.lonDeg = o.number("lon", std::nullopt, -360.0, 360.0).value_or(0.0);
        g.latDeg = o.number("lat", std::nullopt, -90.0, 90.0).value_or(0.0);
        g.height = o.number("height", 0.0, -1e6, 1e8).value_or(0.0);
        if (auto done = o.finish(); !done) return done.error();
        placement.origin = g;
        if (!placement.crs.empty()) r.fail("origin", "give either \"crs\" or \"origin\", not both");
    }
    std::optional<std::string> color = r.has("color") ? r.string("color") : std::nullopt;
    const auto constant = r.numbers("constantColor", 3, std::vector<double>{1.0, 1.0, 1.0});
    if (constant)
        for (double c : *constant)
            if (!(c >= 0.0 && c <= 1.0)) r.fail("constantColor", "each channel is from 0 to 1");
    if (constant && constant->size() == 3) s.constantColor = {(*constant)[0], (*constant)[1], (*constant)[2]};
    if (auto range = r.numbers("heightRange", 2, std::vector<double>{0.0, 1.0}); range && range->size() == 2) {
        if (!((*range)[0] < (*range)[1])) r.fail("heightRange", "must be [low, high] with low < high (fractions of the cloud's heights)");
        s.heightRange = {(*range)[0], (*range)[1]};
    }
    s.pointSize = int(r.number("pointSize", 1.0, kPointSizeRange.min, kPointSizeRange.max).value_or(1.0));
    s.opacity = r.number("opacity", 1.0, kOpacityRange.min, kOpacityRange.max).value_or(1.0);
    s.edl = r.boolean("edl", false).value_or(false);
    s.adaptiveSize = r.boolean("adaptiveSize", false).value_or(false);
    s.edlStrength = r.number("edlStrength", 1.0, kEdlStrengthRange.min, kEdlStrengthRange.max).value_or(1.0);
    s.edlRadius = r.number("edlRadius", 1.4, kEdlRadiusRange.min, kEdlRadiusRange.max).value_or(1.4);
    s.pointBudget = uint64_t(r.number("pointBudget", 3e6, kPointBudgetRange.min, kPointBudgetRange.max).value_or(3e6));
    s.gpuMemoryBytes = uint64_t(r.number("gpuMemoryMB", 1024.0, 0.0625, 65536.0).value_or(1024.0) * 1048576.0);
    s.gpuPageBytes = uint64_t(r.number("gpuPageMB", 0.0, 0.0, 65536.0).value_or(0.0) * 1048576.0);
    if (s.gpuPageBytes > 0 && s.gpuPageBytes < 65536) r.fail("gpuPageMB", "must be 0 (the device's limit) or at least 0.0625 (64 KB)");
    s.cpuMemoryBytes = uint64_t(r.number("cpuMemoryMB", 512.0, 1.0, 1048576.0).value_or(512.0) * 1048576.0);
    if (auto order = r.string("pointOrder", std::string("morton"))) {
        if (*order == "morton") s.mortonOrder = true;
        else if (*order == "random") s.mortonOrder = false;
        else r.fail("pointOrder", "expected \"morton\" or \"random\"");
    }
    if (auto folder = r.string("cacheFolder", std::string()); folder && !folder->empty())
        s.cacheFolder = scene.resolve(*folder).string();
    if (auto renderer = r.string("renderer", std::string("compute"))) {
        if (*renderer == "compute") s.renderer = PointsSettings::Renderer::Compute;
        else if (*renderer == "pointList") s.renderer = PointsSettings::Renderer::PointList;
        else r.fail("renderer", "expected \"compute\" or \"pointList\"");
    }
    if (auto done = r.finish(); !done) return done.error();

    const std::string where = scene.file.string() + ": " + desc.jsonPath;
    const bool url = path->rfind("http://", 0) == 0 || path->rfind("https://", 0) == 0;
    auto file = points::LasFile::open(url ? *path : scene.resolve(*path).string());
    if (!file) return makeError(where + ": " + file.message());
    // A LAZ chunk that is damaged costs its points, not the cloud (named in the log and the status).
    (*file)->setSkipDamagedChunks(true);
    auto georef = points::PointGeoreference::create(**file, placement);
    if (!georef) return makeError(where + ": " + georef.message());
    // Colour: what the scene asks for, else the file's colours when it has them, else height.
    s.color = (*file)->header().hasRgb() ? PointsSettings::Color::Rgb : PointsSettings::Color::Height;
    if (color) {
        auto layer = std::make_unique<PointsLayer>(std::move(*file), std::move(*georef), s);
        if (!layer->setOption("color", *color))
            return makeError(where + "/color: expected \"rgb\", \"intensity\", \"classification\", \"height\" or \"constant\"");
        return std::unique_ptr<scene::Layer>(std::move(layer));
    }
    return std::unique_ptr<scene::Layer>(std::make_unique<PointsLayer>(std::move(*file), std::move(*georef), s));
}

scene::LayerType PointsLayer::layerType() {
    return {"points", "LAS point cloud, splatted by compute shaders with eye-dome lighting", &PointsLayer::create, {"/path", "/cacheFolder"}};
}

}  // namespace orbis::layers
