#pragma once
// What a scene file says, parsed and checked, before anything is built from it. No Vulkan.
//
// {
//   "orbis": 1,
//   "name": "Default",
//   "viewpoint": {"lon": 10, "lat": 30, "height": 0, "heading": 0, "pitch": -90, "range": 2.2e7},
//   "fovDeg": 45,
//   "time": {"start": "2026-03-20T00:00:00Z", "end": "2026-03-21T00:00:00Z",
//            "current": "2026-03-20T08:00:00Z", "rate": 1, "loop": true, "playing": false},
//            (no "time": the range of the layers' data, e.g. trajectories, from its start)
//   "background": [0.0, 0.0, 0.01],
//   "camera": {"mode": "follow", "target": "Train"},          (CameraMode.h; optional)
//   "annotations": [{"name": "Summit", "lon": 7, "lat": 46, "height": 4000}],   (optional)
//   "layers": [{"type": "globe", "name": "Earth", "visible": true, "viewpoint": {...}, ...}]
// }

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "engine/scene/Annotation.h"
#include "engine/scene/CameraMode.h"
#include "globe/Viewpoint.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace orbis::scene {

struct LayerDesc {
    std::string type;
    std::string name;
    bool visible = true;
    std::optional<globe::Viewpoint> viewpoint;
    nlohmann::json settings;   ///< the layer's whole object but "provenance"; its factory reads its own keys
    std::string jsonPath;      ///< e.g. "/layers/2", for messages
    /// Where a layer made by the viewer came from ("provenance": an object, e.g. the processing
    /// job whose result it shows: server, process, inputs, the result's reference). Kept and
    /// saved with the scene, never read by the layer; null when the file has none.
    nlohmann::json provenance;
};

struct TimeDesc {
    TimeNs start = 0, end = 0, current = 0;
    double rate = 1.0;
    bool loop = false;
    bool playing = false;
    bool given = false;   ///< the file has a "time" object; else the layers' data give the range
};

struct SceneDesc {
    std::filesystem::path file;     ///< for messages ("<memory>" when parsed from text)
    std::filesystem::path folder;   ///< relative paths in layers resolve against it
    std::string name;
    globe::Viewpoint viewpoint;
    double fovDeg = 45.0;
    TimeDesc time;
    CameraModeSettings camera;      ///< "camera": a mode watching a moving layer (free by default)
    glm::dvec3 background{0.0, 0.0, 0.0};
    std::vector<LayerDesc> layers;
    std::vector<Annotation> annotations;

    /// `path` made absolute against the scene's folder when relative.
    std::filesystem::path resolve(const std::filesystem::path& path) const;
    /// A data source named in the scene: a file resolved as resolve() does; a connection string
    /// or URL ("WMS:http://...", "PG:...", "https://..."), a GDAL virtual path ("/vsicurl/...")
    /// or an inline GDAL XML description ("<GDAL_WMS>...") as it is.
    std::string resolveSource(const std::string& source) const;
};

/// Largest scene file accepted: a scene lists layers, it does not carry data.
constexpr std::uintmax_t kMaxSceneFileBytes = 16u << 20;

Result<SceneDesc> parseSceneFile(const std::filesystem::path& file);
Result<SceneDesc> parseSceneText(std::string_view text, const std::filesystem::path& file,
                                 const std::filesystem::path& folder);

/// Reads a viewpoint object; shared by the scene, layers and camera paths.
std::optional<globe::Viewpoint> readViewpoint(const nlohmann::json& value, const std::string& file,
                                              const std::string& path, Error* error);

/// Writes a viewpoint in the form readViewpoint reads.
nlohmann::json viewpointToJson(const globe::Viewpoint& vp);

}  // namespace orbis::scene
