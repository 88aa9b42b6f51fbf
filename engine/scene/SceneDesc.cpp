#include "engine/scene/SceneDesc.h"

#include "base/FileText.h"
#include "engine/scene/JsonReader.h"

#include <cmath>
#include <system_error>

namespace orbis::scene {
namespace {

constexpr const char* kDefaultTime = "2026-03-20T08:00:00Z";

}  // namespace

std::filesystem::path SceneDesc::resolve(const std::filesystem::path& path) const {
    if (path.is_absolute() || path.empty()) return path;
    return (folder / path).lexically_normal();
}

std::optional<globe::Viewpoint> readViewpoint(const nlohmann::json& value, const std::string& file,
                                              const std::string& path, Error* error) {
    JsonReader r(value, file, path);
    globe::Viewpoint vp;
    vp.lonDeg = r.number("lon", 0.0, -540.0, 540.0).value_or(0.0);
    vp.latDeg = r.number("lat", 0.0, -90.0, 90.0).value_or(0.0);
    vp.height = r.number("height", 0.0, -1.2e4, 1.0e8).value_or(0.0);
    vp.headingDeg = r.number("heading", 0.0, -720.0, 720.0).value_or(0.0);
    vp.pitchDeg = r.number("pitch", -90.0, -90.0, 90.0).value_or(-90.0);
    vp.range = r.number("range", 1.0e7, 1.0e-3, 1.0e10).value_or(1.0e7);
    auto done = r.finish();
    if (!done) {
        if (error) *error = done.error();
        return std::nullopt;
    }
    return vp;
}

nlohmann::json viewpointToJson(const globe::Viewpoint& vp) {
    return {{"lon", vp.lonDeg}, {"lat", vp.latDeg}, {"height", vp.height},
            {"heading", vp.headingDeg}, {"pitch", vp.pitchDeg}, {"range", vp.range}};
}

Result<SceneDesc> parseSceneFile(const std::filesystem::path& file) {
    auto text = readTextFile(file, kMaxSceneFileBytes, "scene file");
    if (!text) return text.error();
    std::error_code ec;
    const auto absolute = std::filesystem::absolute(file, ec);
    return parseSceneText(*text, file, (ec ? file : absolute).parent_path());
}

Result<SceneDesc> parseSceneText(std::string_view text, const std::filesystem::path& file,
                                 const std::filesystem::path& folder) {
    const std::string name = file.empty() ? std::string("<memory>") : file.string();
    auto parsed = parseJsonText(text, name);
    if (!parsed) return parsed.error();
    const nlohmann::json& root = *parsed;

    SceneDesc scene;
    scene.file = file;
    scene.folder = folder;
    JsonReader r(root, name, "");
    if (!r.isObject()) return r.finish().error();

    if (auto version = r.number("orbis", 1.0); version && *version != 1.0)
        r.fail("orbis", "scene format version " + (std::floor(*version) == *version ? std::to_string(static_cast<long long>(*version)) : nlohmann::json(*version).dump()) + " is not supported (this build reads 1)");
    scene.name = r.string("name", file.stem().string()).value_or("");
    scene.fovDeg = r.number("fovDeg", 45.0, 1.0, 150.0).value_or(45.0);
    if (auto bg = r.numbers("background", 3, std::vector<double>{0.0, 0.0, 0.0})) {
        for (double c : *bg)
            if (c < 0.0 || c > 1.0) r.fail("background", "colour components must be in [0, 1]");
        if (bg->size() == 3) scene.background = {(*bg)[0], (*bg)[1], (*bg)[2]};
    }

    if (const auto* vp = r.object("viewpoint")) {
        Error err;
        if (auto v = readViewpoint(*vp, name, "/viewpoint", &err)) scene.viewpoint = *v;
        else if (r.ok()) return err;
    } else {
        scene.viewpoint = globe::Viewpoint{0.0, 20.0, 0.0, 0.0, -90.0, 2.0e7};
    }

    // Time range and the current time.
    const TimeNs defaultTime = parseIso8601(kDefaultTime).value();
    scene.time.start = scene.time.end = scene.time.current = defaultTime;
    if (const auto* t = r.object("time")) {
        JsonReader tr(*t, name, "/time");
        auto readTime = [&](const char* key, std::optional<TimeNs> fallback) -> std::optional<TimeNs> {
            auto text = tr.string(key, fallback ? std::optional<std::string>(formatIso8601(*fallback, 9)) : std::nullopt);
            if (!text) return std::nullopt;
            auto parsed = parseIso8601(*text);
            if (!parsed) {
                tr.fail(key, parsed.message());
                return std::nullopt;
            }
            return *parsed;
        };
        const auto start = readTime("start", defaultTime);
        const auto end = readTime("end", start.value_or(defaultTime));
        const auto current = readTime("current", start.value_or(defaultTime));
        scene.time.rate = tr.number("rate", 1.0, -1e9, 1e9).value_or(1.0);
        scene.time.loop = tr.boolean("loop", false).value_or(false);
        scene.time.playing = tr.boolean("playing", false).value_or(false);
        if (start && end && *end < *start) tr.fail("end", "the end time is before the start time");
        if (start && end && current && (*current < *start || *current > *end))
            tr.fail("current", "the current time is outside [start, end]");
        if (auto done = tr.finish(); !done) return done.error();
        scene.time.start = *start;
        scene.time.end = *end;
        scene.time.current = *current;
        scene.time.given = true;
    }

    // A camera mode that watches a moving layer (CameraMode.h).
    if (const auto* c = r.object("camera")) {
        JsonReader cr(*c, name, "/camera");
        CameraModeSettings& m = scene.camera;
        if (auto mode = cr.string("mode", std::string("free"))) {
            if (auto parsed = parseCameraMode(*mode)) m.mode = *parsed;
            else cr.fail("mode", "expected free, overview, follow, pilot, inside, above, aside or below, got \"" + *mode + "\"");
        }
        m.target = cr.string("target", std::string()).value_or("");
        if (cr.ok() && m.mode != CameraMode::Free && m.target.empty()) cr.fail("target", "name the layer the camera watches");
        m.distance = cr.number("distance", 0.0, 0.0, 1e8).value_or(0.0);
        m.headingDeg = cr.number("heading", 0.0, -360.0, 360.0).value_or(0.0);
        m.pitchDeg = cr.number("pitch", -15.0, -89.0, 89.0).value_or(-15.0);
        m.smoothingSeconds = cr.number("smoothing", 2.0, 0.0, 3600.0).value_or(2.0);
        if (auto e = cr.numbers("eye", 3, std::vector<double>{0.0, 0.0, 0.0}); e && e->size() == 3) m.eye = {(*e)[0], (*e)[1], (*e)[2]};
        if (auto done = cr.finish(); !done) return done.error();
    }

    if (const auto* list = r.array("annotations")) {
        for (size_t i = 0; i < list->size(); ++i) {
            JsonReader ar((*list)[i], name, "/annotations/" + std::to_string(i));
            Annotation a;
            a.name = ar.string("name").value_or("");
            if (ar.ok() && a.name.empty()) ar.fail("name", "must not be empty");
            a.lonDeg = ar.number("lon", std::nullopt, -180.0, 180.0).value_or(0.0);
            a.latDeg = ar.number("lat", std::nullopt, -90.0, 90.0).value_or(0.0);
            a.height = ar.number("height", 0.0, -1.2e4, 1.0e8).value_or(0.0);
            if (auto done = ar.finish(); !done) return done.error();
            scene.annotations.push_back(std::move(a));
        }
    }

    if (const auto* layers = r.array("layers", /*required=*/true)) {
        for (size_t i = 0; i < layers->size(); ++i) {
            const std::string path = "/layers/" + std::to_string(i);
            const auto& value = (*layers)[i];
            JsonReader lr(value, name, path);
            LayerDesc layer;
            layer.jsonPath = path;
            layer.type = lr.string("type").value_or("");
            layer.name = lr.string("name", layer.type + " " + std::to_string(i)).value_or("");
            layer.visible = lr.boolean("visible", true).value_or(true);
            if (const auto* vp = lr.object("viewpoint")) {
                Error err;
                layer.viewpoint = readViewpoint(*vp, name, path + "/viewpoint", &err);
                if (!layer.viewpoint && lr.ok()) return err;
            }
            if (lr.ok() && layer.type.empty()) lr.fail("type", "must not be empty");
            // The remaining keys belong to the layer type; its factory checks them.
            if (!lr.ok()) return lr.finish().error();
            layer.settings = value;
            scene.layers.push_back(std::move(layer));
        }
    }
    if (auto done = r.finish(); !done) return done.error();
    return scene;
}

}  // namespace orbis::scene
