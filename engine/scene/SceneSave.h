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
//   - each layer's "name", "visible" and every live setting (LiveSettings::liveSettings) at the
//     JSON pointer the setting names (writeLiveSettings);
//   - "annotations", when the scene has any.
// Relative file paths in the layers resolve against the scene's folder, so they are rewritten
// for the folder the file is saved into (rebasePath), at the pointers the layer's type names
// (LayerType::filePaths). Nothing here knows a layer's keys.

#include "base/Result.h"
#include "engine/scene/LayerSetting.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <span>
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

/// Writes each setting into `layer` (a layer's object in a scene file) at its JSON pointer
/// (LayerSetting::jsonPointer), in the form scene files take it: Toggle as true/false, Integer
/// as a whole number, Choice as its text, Curve as [[x, y], ...], Number as a number. On the
/// way to the value, missing objects and arrays are made; a file name given as a string where
/// the pointer goes into an object ("imagery": ["a.tif"] for "/imagery/0/opacity") becomes the
/// long form of a file entry, {"path": "a.tif"}; an array grows by at most one element (a
/// pointer past its end writes nothing: a setting never invents a list entry).
void writeLiveSettings(nlohmann::json& layer, const std::vector<LayerSetting>& settings);

/// `path` as written in a scene file in `fromFolder`, rewritten so that it names the same file
/// from a scene file in `toFolder` (both absolute): relative to `toFolder` when the two share a
/// folder below the root, else absolute. Absolute paths and empty strings are returned
/// unchanged; URLs ("scheme://...") and connection strings ("PG:dbname=gis", "WFS:https://...")
/// too, less any password (withoutPasswords: a saved scene never holds one; the client reads
/// it from PGPASSWORD or a pgpass file).
std::string rebasePath(const std::string& path, const std::filesystem::path& fromFolder,
                       const std::filesystem::path& toFolder);

/// Rebases the file paths in a layer's object (rebasePath): the string values at `filePaths`,
/// JSON pointers in which "*" stands for every element of an array (LayerType::filePaths).
/// Pointers that lead nowhere, or to something other than a string, are skipped.
void rebaseLayerPaths(nlohmann::json& layer, const std::filesystem::path& fromFolder,
                      const std::filesystem::path& toFolder, std::span<const std::string> filePaths);

/// The reference tokens of a JSON pointer (RFC 6901: "/a~1b/0" -> "a/b", "0"); "" has none.
std::vector<std::string> jsonPointerTokens(std::string_view pointer);

}  // namespace orbis::scene
