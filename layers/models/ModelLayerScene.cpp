// The "model" layer's scene settings (ModelLayer.h) and where its motion comes from.
#include "base/Log.h"
#include "engine/scene/JsonReader.h"
#include "layers/models/MeshModel.h"
#include "layers/models/ModelLayer.h"
#include "globe/Geoid.h"
#include "formats/motion/TrajectoryFile.h"

#include <cmath>

namespace orbis::layers {
namespace {

std::optional<glm::dvec3> color(scene::JsonReader& r, const char* key, glm::dvec3 fallback) {
    auto c = r.numbers(key, 3, std::vector<double>{fallback.r, fallback.g, fallback.b});
    if (!c || c->size() != 3) return std::nullopt;
    for (double v : *c)
        if (!(v >= 0.0 && v <= 1.0)) {
            r.fail(key, "each channel is from 0 to 1");
            return std::nullopt;
        }
    return glm::dvec3((*c)[0], (*c)[1], (*c)[2]);
}

std::optional<motion::AltitudeRef> altitudeRef(scene::JsonReader& r, const char* key, bool allowMsl) {
    const auto text = r.string(key, std::string());
    if (!text || text->empty()) return std::nullopt;
    if (*text == "ellipsoid") return motion::AltitudeRef::Ellipsoid;
    if (*text == "ground") return motion::AltitudeRef::Ground;
    if (allowMsl && *text == "msl") return motion::AltitudeRef::MeanSeaLevel;
    r.fail(key, std::string("expected \"ellipsoid\"") + (allowMsl ? ", \"msl\"" : "") + " or \"ground\", got \"" + *text + "\"");
    return std::nullopt;
}

Result<std::unique_ptr<models::ModelMotion>> trajectoryMotion(const nlohmann::json& json, const scene::LayerDesc& desc,
                                                              const scene::SceneDesc& scene) {
    const std::string path = desc.jsonPath + "/trajectory";
    motion::TrajectoryFileOptions o;
    std::string file;
    if (json.is_string()) {
        file = json.get<std::string>();
    } else {
        scene::JsonReader r(json, scene.file.string(), path);
        file = r.string("file").value_or("");
        if (r.ok() && file.empty()) r.fail("file", "name the trajectory file (.csv, .gpx, .klv/.bin)");
        if (auto i = r.string("interpolation", std::string("catmull-rom"))) {
            if (*i == "linear") o.trajectory.interpolation = motion::Interpolation::Linear;
            else if (*i == "catmull-rom") o.trajectory.interpolation = motion::Interpolation::CatmullRom;
            else r.fail("interpolation", "expected \"linear\" or \"catmull-rom\", got \"" + *i + "\"");
        }
        if (auto a = altitudeRef(r, "altitude", true)) o.csv.altitudeRef = *a;
        o.trajectory.clampToGround = r.boolean("clampToGround", false).value_or(false);
        if (auto e = r.string("extrapolate", std::string("hold"))) {
            if (*e == "hold") o.trajectory.before = o.trajectory.after = motion::Extrapolation::Hold;
            else if (*e == "linear") o.trajectory.before = o.trajectory.after = motion::Extrapolation::Linear;
            else if (*e == "hide") o.trajectory.before = o.trajectory.after = motion::Extrapolation::Hide;
            else r.fail("extrapolate", "expected \"hold\", \"linear\" or \"hide\", got \"" + *e + "\"");
        }
        if (auto s = r.string("start", std::string()); s && !s->empty()) {
            auto t = parseIso8601(*s);
            if (!t) r.fail("start", t.message());
            else o.csv.timeOffset = *t;
        }
        if (auto done = r.finish(); !done) return done.error();
    }
    o.trajectory.geoid = globe::egm96Geoid();
    auto trajectory = motion::readTrajectory(scene.resolve(file).string(), o);
    if (!trajectory) return makeError(scene.file.string() + ": " + path + ": " + trajectory.message());
    for (const std::string& w : trajectory->warnings()) log::warn("model '", desc.name, "': ", w);
    return models::makeTrajectoryMotion(std::move(*trajectory));
}

/// "animation": false (the rest pose), or {"name" | "index", "loop", "speed", "start"}.
struct AnimationChoice {
    bool given = false;       ///< an object was given
    bool off = false;         ///< false was given
    std::optional<std::string> name;
    std::optional<int> index;
    bool loop = true;
    double speed = 1.0;
    std::optional<TimeNs> start;
};

Result<AnimationChoice> animationChoice(const nlohmann::json& value, const std::string& file, const std::string& path) {
    AnimationChoice c;
    if (value.is_boolean()) {
        c.off = !value.get<bool>();
        return c;
    }
    if (!value.is_object()) {
        return makeError(file + ": " + path + ": expected false or an object with \"name\" or \"index\", \"loop\", \"speed\", \"start\"; got " +
                         scene::describeJsonType(value));
    }
    c.given = true;
    scene::JsonReader a(value, file, path);
    if (a.has("name")) c.name = a.string("name");
    if (a.has("index")) {
        if (auto i = a.number("index", std::nullopt, 0.0, 1e6)) {
            if (*i != std::floor(*i)) a.fail("index", "expected a whole number");
            c.index = int(*i);
        }
    }
    if (c.name && c.index) a.fail("index", "give \"name\" or \"index\", not both");
    c.loop = a.boolean("loop", true).value_or(true);
    c.speed = a.number("speed", 1.0, -1000.0, 1000.0).value_or(1.0);
    if (auto st = a.string("start", std::string()); st && !st->empty()) {
        auto t = parseIso8601(*st);
        if (!t) a.fail("start", t.message());
        else c.start = *t;
    }
    if (auto done = a.finish(); !done) return done.error();
    return c;
}

/// The animation the layer plays and its time origin (ModelLayer.h), or an error naming the
/// scene's field and the model's file.
Result<models::AnimationPlayback> resolveAnimation(const AnimationChoice& c, const models::ModelData& model,
                                                   const models::ModelMotion& motion, const scene::SceneDesc& scene,
                                                   const std::string& where) {
    models::AnimationPlayback p;
    p.loop = c.loop;
    p.speed = c.speed;
    const auto& anims = model.rig.animations;
    if (c.off) return p;
    if (anims.empty()) {
        if (c.given) return makeError(where + "/animation: " + model.file + " has no animations");
        return p;
    }
    if (c.name) {
        for (size_t i = 0; i < anims.size() && p.animation < 0; ++i)
            if (anims[i].name == *c.name) p.animation = int(i);
        if (p.animation < 0) {
            std::string names;
            for (size_t i = 0; i < anims.size(); ++i) {
                // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "literal" + a temporary.
                if (i) names += ", ";
                if (anims[i].name.empty()) names.append("#").append(std::to_string(i));
                else names.append("\"").append(anims[i].name).append("\"");
            }
            return makeError(where + "/animation/name: " + model.file + " has no animation \"" + *c.name + "\" (it has " + names + ")");
        }
    } else if (c.index) {
        if (size_t(*c.index) >= anims.size())
            return makeError(where + "/animation/index: " + std::to_string(*c.index) + " is past the " + std::to_string(anims.size()) +
                             " animations of " + model.file);
        p.animation = *c.index;
    } else {
        p.animation = 0;
    }
    if (c.start) p.origin = *c.start;
    else if (const auto range = motion.range()) p.origin = range->start;
    else if (scene.time.given) p.origin = scene.time.start;
    return p;
}

Result<void> readCopiesAndPath(scene::JsonReader& r, const scene::LayerDesc& desc, const scene::SceneDesc& scene, ModelSettings& s) {
    if (const auto* copies = r.object("copies")) {
        scene::JsonReader c(*copies, scene.file.string(), desc.jsonPath + "/copies");
        s.copies = uint32_t(c.number("count", 1.0, 1.0, 100000.0).value_or(1.0));
        s.copySpacingSeconds = c.number("spacing", 1.0, 0.0, 1e9).value_or(1.0);
        if (auto done = c.finish(); !done) return done.error();
    }
    if (const auto* path = r.object("path")) {
        scene::JsonReader p(*path, scene.file.string(), desc.jsonPath + "/path");
        s.path.show = p.boolean("show", true).value_or(true);
        s.path.trailSeconds = p.number("trail", 0.0, 0.0, 1e10).value_or(0.0);
        s.path.color = color(p, "color", s.path.color).value_or(s.path.color);
        s.path.opacity = p.number("opacity", 1.0, 0.0, 1.0).value_or(1.0);
        s.path.maxPoints = uint32_t(p.number("maxPoints", 4096.0, 2.0, 1e6).value_or(4096.0));
        if (auto done = p.finish(); !done) return done.error();
    }
    return {};
}

/// Where the model is: exactly one of "position" (with "attitude" and "altitude"),
/// "trajectory" and "live".
struct Placement {
    bool hasPosition = false, hasTrajectory = false, hasLive = false;
    std::optional<std::vector<double>> position, attitude;
    std::optional<motion::AltitudeRef> altitude;
};

Placement readPlacement(scene::JsonReader& r) {
    Placement p;
    p.hasPosition = r.has("position"), p.hasTrajectory = r.has("trajectory"), p.hasLive = r.has("live");
    if (int(p.hasPosition) + int(p.hasTrajectory) + int(p.hasLive) != 1 && r.ok()) {
        r.fail("position", "give exactly one of \"position\", \"trajectory\" or \"live\"");
    }
    if (p.hasPosition) {
        p.position = r.numbers("position", 3);
        p.attitude = r.numbers("attitude", 3, std::vector<double>{0, 0, 0});
        p.altitude = altitudeRef(r, "altitude", false);
        if (p.position && p.position->size() == 3 && (std::abs((*p.position)[1]) > 90.0 || std::abs((*p.position)[0]) > 360.0)) {
            r.fail("position", "expected [longitude, latitude, height] with latitude in [-90, 90]");
        }
    }
    if (p.hasTrajectory) r.accept("trajectory");
    if (p.hasLive) r.accept("live");
    return p;
}

/// The motion of a placement that passed its reader's checks.
Result<std::unique_ptr<models::ModelMotion>> makeMotion(const Placement& placement, const scene::LayerDesc& desc,
                                                        const scene::SceneDesc& scene) {
    if (placement.hasPosition) {
        const auto& p = *placement.position;
        const auto& a = *placement.attitude;
        return models::makeFixedMotion(p[0], p[1], p[2], placement.altitude == motion::AltitudeRef::Ground, a[0], a[1], a[2]);
    }
    if (placement.hasTrajectory) return trajectoryMotion(desc.settings["trajectory"], desc, scene);
    return models::makeLiveMotion(desc.settings["live"], scene.file.string(), desc.jsonPath + "/live");
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> ModelLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    ModelSettings s;
    s.name = desc.name;
    const auto file = r.string("file");
    if (r.ok() && (!file || file->empty())) r.fail("file", "name the model (.glb, .gltf, .obj, .fbx, .dae, .kmz, .3ds, .ply or .stl)");
    // Mesh formats other than glTF: the file's up axis and unit, where it does not say them.
    models::MeshImportOptions meshOptions;
    if (auto up = r.string("up", std::string()); up && !up->empty()) {
        if (*up == "y" || *up == "z") meshOptions.up = (*up)[0];
        else r.fail("up", "expected \"y\" or \"z\" (the model file's up axis), got \"" + *up + "\"");
    }
    if (r.has("unitMetres")) meshOptions.unitMetres = r.number("unitMetres", std::nullopt, 1e-6, 1e6);
    else r.accept("unitMetres");   // (named among the keys a mistake is told)
    s.scale = r.number("scale", 1.0, kScaleRange.min, kScaleRange.max).value_or(1.0);
    s.minimumPixelSize = r.number("minimumPixelSize", 0.0, kMinimumPixelSizeRange.min, kMinimumPixelSizeRange.max).value_or(0.0);
    s.opacity = r.number("opacity", 1.0, kOpacityRange.min, kOpacityRange.max).value_or(1.0);
    if (auto o = r.numbers("orientation", 3, std::vector<double>{0, 0, 0}); o && o->size() == 3) {
        s.orientationDeg = {(*o)[0], (*o)[1], (*o)[2]};
    }
    s.color = color(r, "color", s.color).value_or(s.color);
    if (auto l = r.string("lighting", std::string("sun"))) {
        if (*l == "sun") s.sunLighting = true;
        else if (*l == "headlight") s.sunLighting = false;
        else r.fail("lighting", "expected \"sun\" or \"headlight\", got \"" + *l + "\"");
    }
    if (auto done = readCopiesAndPath(r, desc, scene, s); !done) return done.error();
    if (r.has("label")) {
        const nlohmann::json& label = desc.settings["label"];
        r.accept("label");
        if (label.is_boolean()) s.label = label.get<bool>();
        else if (label.is_string()) s.label = true, s.labelText = label.get<std::string>();
        else r.fail("label", "expected true, false or the label's text");
    }
    s.labelColor = color(r, "labelColor", s.labelColor).value_or(s.labelColor);
    AnimationChoice animation;
    if (r.has("animation")) {
        r.accept("animation");
        auto a = animationChoice(desc.settings["animation"], scene.file.string(), desc.jsonPath + "/animation");
        if (!a) return a.error();
        animation = *a;
    }

    const Placement placement = readPlacement(r);
    if (auto done = r.finish(); !done) return done.error();

    const std::string where = scene.file.string() + ": " + desc.jsonPath;
    auto motion = makeMotion(placement, desc, scene);
    if (!motion) return motion.error();

    const std::string modelPath = scene.resolve(*file).string();
    if (!models::isMeshFormat(modelPath) && (meshOptions.up || meshOptions.unitMetres))
        return makeError(where + ": \"up\" and \"unitMetres\" are for mesh formats (OBJ, FBX, COLLADA, KMZ, 3DS, PLY, STL): glTF is +Y up in metres");
    auto model = models::isMeshFormat(modelPath) ? models::loadMesh(modelPath, meshOptions) : models::loadGltf(modelPath);
    if (!model) return makeError(where + ": " + model.message());
    for (const std::string& w : model->warnings) log::info("model '", desc.name, "': ", w);
    auto playback = resolveAnimation(animation, *model, **motion, scene, where);
    if (!playback) return playback.error();
    s.animation = *playback;
    if (model->animated()) {
        const models::PoseEvaluator e(*model, s.animation.animation);
        const uint64_t bytes = uint64_t(e.layout().vec4s) * sizeof(glm::vec4);
        if (bytes > kMaxPoseBytes)
            return makeError(where + ": " + model->file + ": one pose (" + std::to_string(model->draws.size()) + " drawn nodes, " +
                             std::to_string(model->rig.skins.size()) + " skins) needs " + std::to_string(bytes >> 20) +
                             " MiB, more than the " + std::to_string(kMaxPoseBytes >> 20) + " MiB a model's poses may use");
    }
    return std::unique_ptr<scene::Layer>(std::make_unique<ModelLayer>(std::move(s), std::move(*model), std::move(*motion)));
}

scene::LayerType ModelLayer::layerType() {
    return {"model", "3-D model (glTF 2.0, OBJ, FBX, COLLADA, KMZ, 3DS, PLY, STL), fixed or moving along a trajectory or a live position feed", &ModelLayer::create, {"/file", "/trajectory", "/trajectory/file"}};
}

}  // namespace orbis::layers
