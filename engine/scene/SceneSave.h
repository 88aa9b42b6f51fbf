#pragma once
// Saving a scene as it is now, as a scene file that loads back to the same picture
// (`orbis render` renders what the viewer showed). No Vulkan.
//
// The file starts from what was loaded (SceneDesc: the layers' whole JSON objects, so keys this
// build does not interpret survive) and writes over it the current state:
//   - "viewpoint": the camera's pose as a viewpoint about the ground under the screen centre
//     (EarthManipulator::viewpoint), "fovDeg", "background";
//   - "time": start, end, current, rate, loop, playing, from the TimeServer;
//   - "camera": the camera mode and its settings, when not free;
//   - each layer's "name", "visible" and every Layer::liveSettings() value under its key
//     (writeLiveSettings: three volume settings are elements of arrays);
//   - "annotations", when the scene has any.
// Relative file paths in the layers resolve against the scene's folder, so they are rewritten
// for the folder the file is saved into (rebasePath).

#include "base/Result.h"
#include "engine/scene/Layer.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace orbis::scene {

class Scene;

/// The scene file for `scene` as it is now, to be written at `saveTo` (its relative paths are
/// rewritten for that file's folder). Main thread only (reads the layers' live settings).
nlohmann::json sceneToJson(const Scene& scene, const std::filesystem::path& saveTo);

/// Writes sceneToJson(scene, file) to `file`: into a temporary file in the same folder, then
/// renamed over `file`, so that a failed save never leaves a half-written scene. The error
/// names the file and the problem (no such folder, not writable, disk full). Main thread only.
Result<void> saveScene(const Scene& scene, const std::filesystem::path& file);

/// Writes each setting into `layer` (a layer's object in a scene file) in the form the layer's
/// scene keys take: a setting's name is its key (Layer.h; Toggle as true/false, Integer as a
/// whole number, Choice as its text, Curve as [[x, y], ...]), except these, which are
/// elements of a key's array:
///   "rangeMin", "rangeMax"  ->  "range": [rangeMin, rangeMax]
///   "isovalue<i>"           ->  "isovalues"[i]
///   "slice<i>"              ->  "slices"[i]'s one value ({"lon" | "lat" | "height": value})
///   "imageryOpacity<i>"     ->  "imagery"[i]'s "opacity" (a file name becomes {"path": ...})
///   "imageryVisible<i>"     ->  "imagery"[i]'s "visible"
void writeLiveSettings(nlohmann::json& layer, const std::vector<LayerSetting>& settings);

/// `path` as written in a scene file in `fromFolder`, rewritten so that it names the same file
/// from a scene file in `toFolder` (both absolute): relative to `toFolder` when the two share a
/// folder below the root, else absolute. Absolute paths, URLs ("scheme://...") and empty
/// strings are returned unchanged.
std::string rebasePath(const std::string& path, const std::filesystem::path& fromFolder,
                       const std::filesystem::path& toFolder);

/// Rebases every file path in a layer's object (rebasePath). Paths are the string values of the
/// keys "path", "file", "poses", "cacheFolder" and "trajectory", at any depth, and the strings
/// listed under "elevation" and "imagery" (the layers' scene keys for files and folders).
void rebaseLayerPaths(nlohmann::json& layer, const std::filesystem::path& fromFolder,
                      const std::filesystem::path& toFolder);

}  // namespace orbis::scene
