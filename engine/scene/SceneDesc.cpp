#include "engine/scene/SceneDesc.h"

#include "base/FileText.h"
#include "base/Secrets.h"
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

std::string SceneDesc::resolveSource(const std::string& source) const {
    if (isConnectionString(source) || source.rfind("<", 0) == 0) return source;
    return resolve(source).string();
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

namespace {

/// "orbis", "name", "fovDeg" and "background"; problems are recorded in `r`.
void readGeneral(JsonReader& r, const std::filesystem::path& file, SceneDesc& scene) {
    if (auto version = r.number("orbis", 1.0); version && *version != 1.0)
        r.fail("orbis", "scene format version " + formatJsonNumber(*version) + " is not supported (this build reads 1)");
    scene.name = r.string("name", file.stem().string()).value_or("");
    scene.fovDeg = r.number("fovDeg", 45.0, 1.0, 150.0).value_or(45.0);
    if (auto bg = r.numbers("background", 3, std::vector<double>{0.0, 0.0, 0.0})) {
        for (double c : *bg)
            if (c < 0.0 || c > 1.0) r.fail("background", "colour components must be in [0, 1]");
        if (bg->size() == 3) scene.background = {(*bg)[0], (*bg)[1], (*bg)[2]};
    }
}

/// "viewpoint", or the whole Earth from above. An error in it is returned only when `r` has
/// none of its own (the first error wins).
Result<void> readSceneViewpoint(JsonReader& r, const std::string& name, SceneDesc& scene) {
    if (const auto* vp = r.object("viewpoint")) {
        Error err;
        if (auto v = readViewpoint(*vp, name, "/viewpoint", &err)) scene.viewpoint = *v;
        else if (r.ok()) return err;
    } else {
        scene.viewpoint = globe::Viewpoint{0.0, 20.0, 0.0, 0.0, -90.0, 2.0e7};
    }
    return {};
}

/// "time": the time range and the current time.
Result<void> readTime(const nlohmann::json& object, const std::string& name, TimeNs defaultTime, TimeDesc& time) {
    JsonReader tr(object, name, "/time");
    auto readInstant = [&](const char* key, std::optional<TimeNs> fallback) -> std::optional<TimeNs> {
        auto text = tr.string(key, fallback ? std::optional<std::string>(formatIso8601(*fallback, 9)) : std::nullopt);
        if (!text) return std::nullopt;
        auto parsed = parseIso8601(*text);
        if (!parsed) {
            tr.fail(key, parsed.message());
            return std::nullopt;
        }
        return *parsed;
    };
    const auto start = readInstant("start", defaultTime);
    const auto end = readInstant("end", start.value_or(defaultTime));
    const auto current = readInstant("current", start.value_or(defaultTime));
    time.rate = tr.number("rate", 1.0, -1e9, 1e9).value_or(1.0);
    time.loop = tr.boolean("loop", false).value_or(false);
    time.playing = tr.boolean("playing", false).value_or(false);
    if (start && end && *end < *start) tr.fail("end", "the end time is before the start time");
    if (start && end && current && (*current < *start || *current > *end))
        tr.fail("current", "the current time is outside [start, end]");
    if (auto done = tr.finish(); !done) return done.error();
    time.start = *start;
    time.end = *end;
    time.current = *current;
    time.given = true;
    return {};
}

/// "camera": a camera mode that watches a moving layer (CameraMode.h).
Result<void> readCamera(const nlohmann::json& object, const std::string& name, CameraModeSettings& m) {
    JsonReader cr(object, name, "/camera");
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
    return cr.finish();
}

Result<void> readAnnotations(const nlohmann::json& list, const std::string& name, std::vector<Annotation>& out) {
    for (size_t i = 0; i < list.size(); ++i) {
        JsonReader ar(list[i], name, "/annotations/" + std::to_string(i));
        Annotation a;
        a.name = ar.string("name").value_or("");
        if (ar.ok() && a.name.empty()) ar.fail("name", "must not be empty");
        a.lonDeg = ar.number("lon", std::nullopt, -180.0, 180.0).value_or(0.0);
        a.latDeg = ar.number("lat", std::nullopt, -90.0, 90.0).value_or(0.0);
        a.height = ar.number("height", 0.0, -1.2e4, 1.0e8).value_or(0.0);
        if (auto done = ar.finish(); !done) return done.error();
        out.push_back(std::move(a));
    }
    return {};
}

/// The keys every layer has; the rest belong to the layer type, whose factory checks them.
Result<LayerDesc> readLayer(const nlohmann::json& value, const std::string& name, size_t i) {
    const std::string path = "/layers/" + std::to_string(i);
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
    if (const auto* provenance = lr.object("provenance")) layer.provenance = *provenance;
    if (lr.ok() && layer.type.empty()) lr.fail("type", "must not be empty");
    if (!lr.ok()) return lr.finish().error();
    layer.settings = value;
    layer.settings.erase("provenance");
    return layer;
}

}  // namespace

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
    readGeneral(r, file, scene);
    if (auto done = readSceneViewpoint(r, name, scene); !done) return done.error();
    const TimeNs defaultTime = parseIso8601(kDefaultTime).value();
    scene.time.start = scene.time.end = scene.time.current = defaultTime;
    if (const auto* t = r.object("time"))
        if (auto done = readTime(*t, name, defaultTime, scene.time); !done) return done.error();
    if (const auto* c = r.object("camera"))
        if (auto done = readCamera(*c, name, scene.camera); !done) return done.error();
    if (const auto* list = r.array("annotations"))
        if (auto done = readAnnotations(*list, name, scene.annotations); !done) return done.error();
    if (const auto* layers = r.array("layers", /*required=*/true)) {
        for (size_t i = 0; i < layers->size(); ++i) {
            auto layer = readLayer((*layers)[i], name, i);
            if (!layer) return layer.error();
            scene.layers.push_back(std::move(layer).value());
        }
    }
    if (auto done = r.finish(); !done) return done.error();
    return scene;
}

}  // namespace orbis::scene
