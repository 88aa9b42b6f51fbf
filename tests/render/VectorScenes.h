#pragma once
// Scene JSON for the vector layer's render tests (VectorRenderTest, VectorLabelTest,
// VectorMeshTest): GeoJSON files written into the test's output folder, the mountain and world
// terrains, a vector layer.
#include "tests/render/TerrainFixtures.h"
#include "tests/support/GoldenImage.h"

#include "base/Png.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace orbis::test {

inline std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

/// A GeoJSON FeatureCollection of `features` (comma-separated Feature objects) written as
/// `folder`/`name` under the tests' output folder (never the source tree); its path.
inline std::string writeGeoJson(const std::string& folder, const std::string& name, const std::string& features) {
    const auto dir = std::filesystem::path(testOutputDir()) / folder;
    std::filesystem::create_directories(dir);
    const auto path = (dir / name).string();
    std::ofstream(path) << R"({"type": "FeatureCollection", "features": [)" << features << "]}";
    return path;
}

/// A PNG icon of `width` x `height` pixels written as `folder`/`name` under the tests' output
/// folder, each pixel (RGBA, transparent black to start with) set by `paint(x, y, pixel)`;
/// its path.
template <typename Paint>
std::filesystem::path writeIcon(const std::string& folder, const std::string& name, uint32_t width, uint32_t height, Paint paint) {
    const auto dir = std::filesystem::path(testOutputDir()) / folder;
    std::filesystem::create_directories(dir);
    ImageRgba8 icon{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 0)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) paint(x, y, &icon.pixels[(size_t(y) * width + x) * 4]);
    const auto path = dir / name;
    if (!writePng(path, icon)) return {};
    return path;
}

/// A scene at one instant (the sun's place), on a near-black background.
inline std::string vectorSceneJson(const std::string& viewpoint, const std::string& layers, const std::string& time) {
    return R"({"viewpoint": )" + viewpoint + R"(, "time": {"start": ")" + time + R"(", "end": ")" + time +
           R"("}, "background": [0, 0, 0.012], "layers": [)" + layers + "]}";
}

/// The fixture mountain (TerrainFixtures), grey, without sky; `extra` adds keys (", ...").
inline std::string mountainTerrain(const std::string& extra = "") {
    return R"({"type": "terrain", "name": "Mountain", "elevation": [)" + jsonString(terrainFixtures().dem) +
           R"(], "sky": false, "color": [0.55, 0.55, 0.5])" + extra + "}";
}

/// The generated world (assets/generated: relief and colour).
inline std::string worldTerrain() {
    const std::string dir = std::string(ORBIS_SOURCE_DIR) + "/assets/generated/";
    return R"({"type": "terrain", "name": "World", "elevation": [)" + jsonString(dir + "world-relief.tif") +
           R"(], "imagery": [{"path": )" + jsonString(dir + "world-colour.tif") + R"(}], "sky": false})";
}

inline std::string vectorLayerJson(const std::string& name, const std::string& path, const std::string& extra) {
    return R"({"type": "vector", "name": )" + jsonString(name) + R"(, "path": )" + jsonString(path) + extra + "}";
}

}  // namespace orbis::test
