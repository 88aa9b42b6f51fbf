// The scene-file side of the terrain layer: its keys and its sources' keys, checked.
#include "engine/scene/JsonReader.h"
#include "layers/HttpAuthScene.h"
#include "layers/terrain/TerrainLayer.h"
#include "shared/TerrainTypes.h"

#include <cctype>
#include <cmath>
#include <filesystem>

namespace orbis::layers {
namespace {

bool startsWithNoCase(const std::string& s, const char* prefix) {
    for (size_t i = 0; prefix[i]; ++i)
        if (i >= s.size() || std::toupper(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
    return true;
}

Result<globe::RasterSourceOptions> readSource(const nlohmann::json& value, const scene::SceneDesc& scene,
                                              const std::string& path, globe::RasterRole role, scene::JsonReader* outer,
                                              std::string* name, double* opacity, bool* visible, bool* night = nullptr,
                                              std::vector<globe::WmsTimeValue>* times = nullptr) {
    globe::RasterSourceOptions o;
    o.role = role;
    if (value.is_string()) {
        o.path = scene.resolveSource(value.get<std::string>());
        if (name) *name = std::filesystem::path(o.path).filename().string();
        return o;
    }
    (void)outer;
    scene::JsonReader r(value, scene.file.string(), path);
    if (!r.isObject())
        return makeError(scene.file.string() + ": " + path + ": expected a file name or an object, got " +
                         scene::describeJsonType(value));
    const auto file = r.string("path", std::string());
    const auto xyz = r.string("xyz", std::string());
    if (file && !file->empty()) o.path = scene.resolveSource(*file);
    if (xyz && !xyz->empty()) o.xyzUrl = *xyz;
    if (auto maxZoom = r.number("maxZoom", 18.0, 0.0, 30.0)) {
        if (*maxZoom != std::floor(*maxZoom)) r.fail("maxZoom", "must be an integer zoom level");
        o.xyzMaxZoom = int(*maxZoom);
    }
    if (r.ok() && r.has("maxZoom") && o.xyzUrl.empty()) r.fail("maxZoom", "only applies to an \"xyz\" source");
    if (r.ok() && o.path.empty() == o.xyzUrl.empty())
        r.fail(o.path.empty() ? "path" : "xyz", "give exactly one of \"path\" and \"xyz\"");
    if (role == globe::RasterRole::Elevation) {
        if (auto band = r.number("band", 1.0, 1.0, 65535.0)) o.bands = {int(*band)};
    } else if (auto bands = r.numbers("bands", 0, std::vector<double>{})) {
        if (!bands->empty() && bands->size() != 1 && bands->size() != 3 && bands->size() != 4)
            r.fail("bands", "give 1 (grey), 3 (RGB) or 4 (RGBA) band numbers");
        for (double b : *bands) {
            if (b < 1 || b != std::floor(b)) r.fail("bands", "band numbers are integers from 1");
            o.bands.push_back(int(b));
        }
    }
    if (r.has("noData")) o.noData = r.number("noData");
    if (!r.has("range")) {
    } else if (auto range = r.numbers("range", 2)) {
        if (range->size() == 2) {
            if (!((*range)[1] > (*range)[0])) r.fail("range", "must be [low, high] with low < high");
            o.scaleRange = std::make_pair((*range)[0], (*range)[1]);
        }
    }
    if (auto resampling = r.string("resampling", std::string())) o.resampling = *resampling;
    o.httpAuth = readHttpAuth(r, scene.file.string(), path);
    if (auto cache = r.string("cacheDir", std::string()); cache && !cache->empty()) o.cacheDir = scene.resolve(*cache).string();
    if (r.has("bounds")) {
        if (auto b = r.numbers("bounds", 4); b && b->size() == 4) {
            const globe::GeoExtent e{(*b)[0], (*b)[1], (*b)[2], (*b)[3]};
            if (!(e.west < e.east && e.south < e.north && e.south >= -90.0 && e.north <= 90.0 && e.west >= -540.0 && e.east <= 540.0))
                r.fail("bounds", "must be [west, south, east, north] in degrees, west < east, south < north, within -90..90");
            else if (!o.xyzUrl.empty())
                r.fail("bounds", "georeferences a file, not an \"xyz\" source");
            o.bounds = e;
        }
    }
    if (name) *name = r.string("name", std::filesystem::path(o.path.empty() ? o.xyzUrl : o.path).filename().string()).value_or("");
    else r.accept("name");
    if (opacity) *opacity = r.number("opacity", 1.0, TerrainLayer::kImageryOpacityRange.min, TerrainLayer::kImageryOpacityRange.max).value_or(1.0);
    if (visible) *visible = r.boolean("visible", true).value_or(true);
    if (night) *night = r.boolean("night", false).value_or(false);
    if (times && r.has("time")) {
        // The TIME extent, as a string (what `orbis info URL` prints) or a list of values.
        std::string extent;
        const nlohmann::json& t = value["time"];
        if (t.is_string()) {
            extent = t.get<std::string>();
            r.accept("time");
        } else if (t.is_array()) {
            for (const auto& v : t) {
                if (!v.is_string()) {
                    r.fail("time", "expected time values as strings, got " + scene::describeJsonType(v));
                    break;
                }
                if (!extent.empty()) extent += ',';
                extent += v.get_ref<const std::string&>();
            }
            r.accept("time");
        } else {
            r.fail("time", "expected a WMS time extent (\"2026-01-01/2026-03-01/P1M\") or a list of values, got " +
                               scene::describeJsonType(t));
        }
        if (r.ok() && (o.path.size() < 4 || !startsWithNoCase(o.path, "WMS:")))
            r.fail("time", "applies to a WMS source (a path starting with \"WMS:\")");
        if (r.ok()) {
            if (auto values = globe::parseWmsTimeExtent(extent)) *times = std::move(*values);
            else r.fail("time", values.message());
        }
    }
    if (auto done = r.finish(); !done) return done.error();
    return o;
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> TerrainLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    TerrainSettings s;
    if (const nlohmann::json* list = r.array("elevation")) {
        for (size_t i = 0; i < list->size(); ++i) {
            auto o = readSource((*list)[i], scene, desc.jsonPath + "/elevation/" + std::to_string(i),
                                globe::RasterRole::Elevation, &r, nullptr, nullptr, nullptr);
            if (!o) return o.error();
            s.elevation.push_back(std::move(*o));
        }
    }
    if (const nlohmann::json* list = r.array("imagery")) {
        if (list->size() > shader::kTerrainMaxImagery)
            r.fail("imagery", "at most " + std::to_string(shader::kTerrainMaxImagery) + " imagery layers");
        for (size_t i = 0; i < list->size() && i < shader::kTerrainMaxImagery; ++i) {
            ImageryLayerSettings layer;
            auto o = readSource((*list)[i], scene, desc.jsonPath + "/imagery/" + std::to_string(i),
                                globe::RasterRole::Imagery, &r, &layer.name, &layer.opacity, &layer.visible, &layer.night,
                                &layer.times);
            if (!o) return o.error();
            layer.source = std::move(*o);
            s.imagery.push_back(std::move(layer));
        }
    }
    s.maxScreenSpaceError = r.number("maxScreenSpaceError", s.maxScreenSpaceError, kScreenSpaceErrorRange.min, kScreenSpaceErrorRange.max).value_or(s.maxScreenSpaceError);
    s.gridSize = int(r.number("gridSize", s.gridSize, 3.0, 257.0).value_or(s.gridSize));
    s.imageSize = int(r.number("imageSize", s.imageSize, 16.0, 1024.0).value_or(s.imageSize));
    if (s.imageSize & (s.imageSize - 1)) r.fail("imageSize", "must be a power of two (16 ... 1024)");
    s.maxLevel = uint32_t(r.number("maxLevel", s.maxLevel, 0.0, 28.0).value_or(s.maxLevel));
    s.verticalExaggeration = r.number("verticalExaggeration", 1.0, kExaggerationRange.min, kExaggerationRange.max).value_or(1.0);
    if (auto c = r.numbers("color", 3, std::vector<double>{s.color.r, s.color.g, s.color.b})) {
        for (double v : *c)
            if (v < 0.0 || v > 1.0) r.fail("color", "colour components must be in [0, 1]");
        if (c->size() == 3) s.color = {(*c)[0], (*c)[1], (*c)[2]};
    }
    if (auto lighting = r.string("lighting", std::string("sun"))) {
        if (*lighting == "sun") s.sunLighting = true;
        else if (*lighting == "headlight") s.sunLighting = false;
        else r.fail("lighting", "expected \"sun\" or \"headlight\", got \"" + *lighting + "\"");
    }
    s.sky = r.boolean("sky", s.sky).value_or(s.sky);
    const auto mb = [&](const char* key, uint64_t fallback, double min) {
        return uint64_t(r.number(key, double(fallback >> 20), min, 1 << 20).value_or(double(fallback >> 20))) << 20;
    };
    s.cpuCacheBytes = mb("cpuCacheMB", s.cpuCacheBytes, 16);
    s.gpuCacheBytes = mb("gpuCacheMB", s.gpuCacheBytes, 32);
    s.uploadBudgetBytes = mb("uploadBudgetMB", s.uploadBudgetBytes, 1);
    s.tileBorders = r.boolean("tileBorders", false).value_or(false);
    if (auto done = r.finish(); !done) return done.error();
    return std::unique_ptr<scene::Layer>(new TerrainLayer(std::move(s)));
}

scene::LayerType TerrainLayer::layerType() {
    return {"terrain", "WGS84 quadtree terrain streaming DEMs and imagery through GDAL", &TerrainLayer::create, {"/elevation/*", "/elevation/*/path", "/elevation/*/cacheDir", "/imagery/*", "/imagery/*/path", "/imagery/*/cacheDir"}};
}

}  // namespace orbis::layers
