#pragma once
// Scene JSON for the vector layer's render tests (VectorRenderTest, VectorLabelTest,
// VectorMeshTest): GeoJSON files written into the test's output folder, the mountain and world
// terrains, a vector layer.
#include "tests/render/TerrainFixtures.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace orbis::test {

inline std::string jsonString(const std::string& s) { return nlohmann::json(s).dump(); }

/// A GeoJSON FeatureCollection of `features` (comma-separated Feature objects) written as
/// `folder`/`name` under the current directory; its path.
inline std::string writeGeoJson(const std::string& folder, const std::string& name, const std::string& features) {
    const auto dir = std::filesystem::current_path() / folder;
    std::filesystem::create_directories(dir);
    const auto path = (dir / name).string();
    std::ofstream(path) << R"({"type": "FeatureCollection", "features": [)" << features << "]}";
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
