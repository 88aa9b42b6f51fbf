#include "engine/scene/SceneSave.h"

#include "base/Secrets.h"
#include "engine/scene/Scene.h"
#include "globe/EarthManipulator.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>
#include <system_error>

namespace orbis::scene {
namespace fs = std::filesystem;
namespace {

/// The camera's pose as the viewpoint a scene file gives: about the ground under the screen
/// centre where the scene knows the ground (else the ellipsoid), as the viewer's manipulator
/// sees it. poseFromViewpoint gives the pose back (up to rounding; roll is not kept).
globe::Viewpoint currentViewpoint(const Scene& scene) {
    globe::EarthManipulator manipulator;
    manipulator.setHeightQuery([&scene](double lonDeg, double latDeg) { return scene.heightAt(lonDeg, latDeg); });
    // The pose as it is, never lifted above the ground.
    manipulator.setMinClearance(-std::numeric_limits<double>::infinity());
    manipulator.setPose(scene.camera().pose());
    return manipulator.viewpoint();
}

/// An instant in ISO 8601 with as many fractional digits as it needs (0, 3, 6 or 9): exact.
std::string exactIso8601(TimeNs t) {
    const TimeNs fraction = ((t % 1'000'000'000) + 1'000'000'000) % 1'000'000'000;
    const int digits = fraction == 0 ? 0 : fraction % 1'000'000 == 0 ? 3 : fraction % 1'000 == 0 ? 6 : 9;
    return formatIso8601(t, digits);
}

nlohmann::json timeToJson(const TimeServer& time) {
    return {{"start", exactIso8601(time.start())}, {"end", exactIso8601(time.end())},
            {"current", exactIso8601(time.now())}, {"rate", time.rate()},
            {"loop", time.loop()}, {"playing", time.playing()}};
}

nlohmann::json cameraModeToJson(const CameraModeSettings& m) {
    return {{"mode", toString(m.mode)}, {"target", m.target}, {"distance", m.distance},
            {"heading", m.headingDeg}, {"pitch", m.pitchDeg}, {"smoothing", m.smoothingSeconds},
            {"eye", {m.eye.x, m.eye.y, m.eye.z}}};
}

nlohmann::json settingValue(const LayerSetting& s) {
    switch (s.kind) {
        case LayerSetting::Kind::Integer: return static_cast<long long>(std::llround(s.value));
        case LayerSetting::Kind::Toggle: return s.value != 0.0;
        case LayerSetting::Kind::Choice: return s.choice;
        case LayerSetting::Kind::Curve: {   // [[x, y], ...]
            nlohmann::json points = nlohmann::json::array();
            for (const glm::dvec2& p : s.points) points.push_back({p.x, p.y});
            return points;
        }
        case LayerSetting::Kind::Number: break;
    }
    return s.value;
}

/// `path` made absolute and normal, without a trailing separator ("/a/b/." -> "/a/b").
fs::path normalAbsolute(const fs::path& path) {
    std::error_code ec;
    fs::path folder = fs::absolute(path, ec);
    if (ec) folder = path;
    folder = folder.lexically_normal();
    while (!folder.has_filename() && folder != folder.root_path()) folder = folder.parent_path();
    return folder;
}

/// The array index a token names (digits only, no leading zero but "0"), if it is one.
std::optional<size_t> arrayIndex(std::string_view token) {
    if (token.empty() || token.size() > 9 || (token.size() > 1 && token[0] == '0')) return std::nullopt;
    size_t i = 0;
    for (char c : token) {
        if (c < '0' || c > '9') return std::nullopt;
        i = i * 10 + size_t(c - '0');
    }
    return i;
}

/// The value at `tokens` under `node`, made on the way (writeLiveSettings' rules); null when
/// the pointer runs past the end of an array.
nlohmann::json* makePath(nlohmann::json& node, const std::vector<std::string>& tokens) {
    nlohmann::json* at = &node;
    for (const std::string& token : tokens) {
        if (at->is_array()) {
            const auto i = arrayIndex(token);
            if (!i || *i > at->size()) return nullptr;
            if (*i == at->size()) at->push_back(nullptr);
            at = &(*at)[*i];
            continue;
        }
        if (at->is_string()) *at = nlohmann::json{{"path", *at}};   // a file entry's long form
        else if (!at->is_object()) *at = arrayIndex(token) ? nlohmann::json::array() : nlohmann::json::object();
        if (at->is_array()) {   // made just now: the token is an index
            if (*arrayIndex(token) != 0) return nullptr;
            at->push_back(nullptr);
            at = &(*at)[0];
        } else {
            at = &(*at)[token];
        }
    }
    return at;
}

void rebaseAt(nlohmann::json& node, const std::vector<std::string>& tokens, size_t k, const fs::path& fromFolder,
              const fs::path& toFolder) {
    if (k == tokens.size()) {
        if (node.is_string()) node = rebasePath(node.get<std::string>(), fromFolder, toFolder);
        return;
    }
    const std::string& token = tokens[k];
    if (token == "*") {
        if (node.is_array())
            for (nlohmann::json& item : node) rebaseAt(item, tokens, k + 1, fromFolder, toFolder);
    } else if (node.is_object()) {
        if (const auto it = node.find(token); it != node.end()) rebaseAt(*it, tokens, k + 1, fromFolder, toFolder);
    } else if (node.is_array()) {
        if (const auto i = arrayIndex(token); i && *i < node.size()) rebaseAt(node[*i], tokens, k + 1, fromFolder, toFolder);
    }
}

}  // namespace

std::vector<std::string> jsonPointerTokens(std::string_view pointer) {
    std::vector<std::string> tokens;
    if (pointer.empty()) return tokens;
    size_t at = pointer[0] == '/' ? 1 : 0;
    for (;;) {
        const size_t slash = pointer.find('/', at);
        std::string token(pointer.substr(at, slash == std::string_view::npos ? std::string_view::npos : slash - at));
        for (size_t i = 0; (i = token.find('~', i)) != std::string::npos; ++i)   // ~1 is "/", ~0 is "~"
            if (i + 1 < token.size() && (token[i + 1] == '1' || token[i + 1] == '0'))
                token.replace(i, 2, token[i + 1] == '1' ? "/" : "~");
        tokens.push_back(std::move(token));
        if (slash == std::string_view::npos) break;
        at = slash + 1;
    }
    return tokens;
}

void writeLiveSettings(nlohmann::json& layer, const std::vector<LayerSetting>& settings) {
    for (const LayerSetting& s : settings) {
        const std::vector<std::string> tokens = jsonPointerTokens(s.jsonPointer());
        if (tokens.empty()) continue;   // the whole object is no setting's place
        if (nlohmann::json* at = makePath(layer, tokens)) *at = settingValue(s);
    }
}

std::string rebasePath(const std::string& path, const fs::path& fromFolder, const fs::path& toFolder) {
    // A URL or a driver's connection string ("PG:dbname=...", "WFS:https://..."): no file, and
    // its password, if the scene had one, stays out of the saved file.
    if (isConnectionString(path) || path.find("://") != std::string::npos) return withoutPasswords(path);
    if (path.empty() || fs::path(path).is_absolute()) return path;
    const fs::path target = (normalAbsolute(fromFolder) / path).lexically_normal();
    const fs::path to = normalAbsolute(toFolder);
    // A path climbing up to the root and down again breaks as soon as either tree moves:
    // relative only when the two share a folder below the root.
    size_t common = 0;
    for (auto t = target.begin(), f = to.begin(); t != target.end() && f != to.end() && *t == *f; ++t, ++f) ++common;
    const fs::path relative = common >= 2 ? target.lexically_relative(to) : fs::path();
    return relative.empty() ? target.generic_string() : relative.generic_string();
}

void rebaseLayerPaths(nlohmann::json& layer, const fs::path& fromFolder, const fs::path& toFolder,
                      std::span<const std::string> filePaths) {
    for (const std::string& pointer : filePaths) rebaseAt(layer, jsonPointerTokens(pointer), 0, fromFolder, toFolder);
}

nlohmann::json sceneToJson(const Scene& scene, const fs::path& saveTo) {
    const SceneDesc& desc = scene.desc();
    nlohmann::json root;
    root["orbis"] = 1;
    root["name"] = desc.name;
    root["viewpoint"] = viewpointToJson(currentViewpoint(scene));
    // The file's own number when the camera still has it (radians and back would add noise).
    const double fovRad = scene.camera().verticalFovRad();
    root["fovDeg"] = glm::radians(desc.fovDeg) == fovRad ? desc.fovDeg : glm::degrees(fovRad);
    root["time"] = timeToJson(scene.time());
    root["background"] = {desc.background.r, desc.background.g, desc.background.b};
    if (scene.cameraMode().mode != CameraMode::Free) root["camera"] = cameraModeToJson(scene.cameraMode());
    if (!scene.annotations().empty()) {
        nlohmann::json pins = nlohmann::json::array();
        for (const Annotation& a : scene.annotations())
            pins.push_back({{"name", a.name}, {"lon", a.lonDeg}, {"lat", a.latDeg}, {"height", a.height}});
        root["annotations"] = std::move(pins);
    }

    // Resources are in the order of desc.layers (Scene::build, Scene::addLayer), with the pins'
    // layer, which the file does not list, among them.
    const fs::path toFolder = normalAbsolute(saveTo).parent_path();
    nlohmann::json layers = nlohmann::json::array();
    size_t i = 0;
    for (const Resource& resource : scene.resources()) {
        if (resource.type == kAnnotationLayerType && (i >= desc.layers.size() || desc.layers[i].type != kAnnotationLayerType)) continue;
        if (i >= desc.layers.size()) break;
        const LayerDesc& from = desc.layers[i++];
        nlohmann::json layer = from.settings;
        layer["name"] = resource.name;
        // A layer that could not be built keeps what its file said.
        layer["visible"] = resource.error.empty() ? resource.visible : from.visible;
        if (const LiveSettings* live = resource.layer->asLiveSettings()) writeLiveSettings(layer, live->liveSettings());
        rebaseLayerPaths(layer, desc.folder, toFolder, resource.filePaths);
        if (!from.provenance.is_null()) layer["provenance"] = from.provenance;
        layers.push_back(std::move(layer));
    }
    root["layers"] = std::move(layers);
    return root;
}

Result<void> saveScene(const Scene& scene, const fs::path& file) {
    if (file.empty()) return makeError("cannot save the scene: no file name given");
    const std::string name = file.string();
    const fs::path target = normalAbsolute(file);
    const fs::path folder = target.parent_path();
    std::error_code ec;
    if (fs::is_directory(target, ec)) return makeError(name + ": cannot save the scene: this is a folder; give a file name");
    if (!fs::exists(folder, ec))
        return makeError(name + ": cannot save the scene: the folder " + folder.string() + " does not exist");
    if (!fs::is_directory(folder, ec))
        return makeError(name + ": cannot save the scene: " + folder.string() + " is not a folder");

    std::string text;
    try {
        text = sceneToJson(scene, target).dump(2) + "\n";
    } catch (const nlohmann::json::exception& e) {   // text that is not UTF-8 (a layer's name, a path)
        return makeError(name + ": cannot save the scene: " + e.what());
    }
    // What is written must load again: better an error now than a scene that fails when reopened.
    if (auto check = parseSceneText(text, file, folder); !check)
        return makeError(name + ": cannot save the scene: it would not load again (" + check.message() + ")");

    const fs::path temporary = folder / ("." + target.filename().string() + ".saving");
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) {
            const int error = errno;
            return makeError(name + ": cannot save the scene: cannot create a file in " + folder.string() + " (" +
                             std::strerror(error) + ")");
        }
        out << text;
        out.close();
        if (!out) {
            const int error = errno;
            fs::remove(temporary, ec);
            return makeError(name + ": cannot save the scene: writing " + temporary.string() + " failed (" +
                             std::strerror(error) + ")");
        }
    }
    fs::rename(temporary, target, ec);
    if (ec) {
        const std::string why = ec.message();
        fs::remove(temporary, ec);
        return makeError(name + ": cannot save the scene: cannot replace the file (" + why + ")");
    }
    return {};
}

}  // namespace orbis::scene
