// The scene-file side of the vector layer: its keys, checked, and the style read (its fields are
// checked against the data when it is read).
#include "base/Log.h"
#include "base/Secrets.h"
#include "engine/scene/JsonReader.h"
#include "layers/HttpAuthScene.h"
#include "layers/vector/VectorLayer.h"

#include <filesystem>

namespace orbis::layers {
namespace {

/// Sources that are not files: OGR's connection strings and URLs.
bool isConnection(const std::string& source) {
    for (const char* prefix : {"WFS:", "PG:", "http://", "https://", "/vsicurl/", "MySQL:", "OCI:", "MSSQL:"})
        if (source.rfind(prefix, 0) == 0) return true;
    return false;
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> VectorLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    VectorLayerSettings s;
    s.name = desc.name;
    const auto path = r.string("path");
    if (r.ok() && (!path || path->empty())) r.fail("path", "name the vector file (or an OGR connection such as \"WFS:http://...\")");
    vector::VectorReadOptions& read = s.content.read;
    if (path) read.source = isConnection(*path) ? *path : scene.resolve(*path).string();
    if (path && isConnection(*path) && withoutPasswords(*path) != *path)
        log::warn(scene.file.string(), ": ", desc.jsonPath, "/path: the connection holds a password; it is used, but a saved "
                  "scene leaves it out (PGPASSWORD or a pgpass file keep it out of scene files)");
    if (const nlohmann::json* layers = r.array("layers")) {
        for (const nlohmann::json& l : *layers) {
            if (!l.is_string()) {
                r.fail("layers", "expected layer names (strings), got " + scene::describeJsonType(l));
                break;
            }
            read.layers.push_back(l.get<std::string>());
        }
    }
    read.httpAuth = readHttpAuth(r, scene.file.string(), desc.jsonPath);
    read.where = r.string("where", std::string()).value_or("");
    read.sql = r.string("sql", std::string()).value_or("");
    if (!read.sql.empty() && (!read.where.empty() || !read.layers.empty()))
        r.fail("sql", "an SQL statement chooses its own layer and rows: give \"sql\" alone, without \"layers\" or \"where\"");
    if (const nlohmann::json* time = r.object("time")) {
        scene::JsonReader t(*time, scene.file.string(), desc.jsonPath + "/time");
        s.content.timeFields.begin = t.string("begin", std::string()).value_or("");
        s.content.timeFields.end = t.string("end", std::string()).value_or("");
        if (auto done = t.finish(); !done) return done.error();
    }
    if (auto altitude = r.string("altitude", std::string("clamped"))) {
        if (auto mode = vector::parseAltitudeMode(*altitude)) s.altitude = *mode;
        else r.fail("altitude", "expected \"clamped\" (on the terrain), \"relative\" (Z above the ground) or \"absolute\" (Z above the ellipsoid), got \"" + *altitude + "\"");
    }
    s.extrusionScale = r.number("extrusionScale", 1.0, kExtrusionScaleRange.min, kExtrusionScaleRange.max).value_or(1.0);
    s.opacity = r.number("opacity", 1.0, kOpacityRange.min, kOpacityRange.max).value_or(1.0);
    s.maxLevel = uint32_t(r.number("maxLevel", 18.0, kMaxLevelRange.min, kMaxLevelRange.max).value_or(18.0));
    s.simplifyPx = r.number("simplifyPx", 0.5, kSimplifyRange.min, kSimplifyRange.max).value_or(0.5);
    s.labels = r.boolean("labels", true).value_or(true);
    if (const nlohmann::json* paging = desc.settings.contains("paging") ? &desc.settings["paging"] : nullptr) {
        r.accept("paging");
        if (paging->is_boolean()) s.paging = paging->get<bool>() ? Paging::On : Paging::Off;
        else if (!(paging->is_string() && paging->get<std::string>() == "auto"))
            r.fail("paging", "expected \"auto\" (page a source of more than 100 000 features), true or false, got " + paging->dump());
    }
    s.pageLevel = uint32_t(r.number("pageLevel", 12.0, 0.0, 18.0).value_or(12.0));
    s.pageBudgetBytes = uint64_t(r.number("pageBudgetMB", 256.0, 1.0, 65536.0).value_or(256.0) * double(1 << 20));
    if (const nlohmann::json* refresh = r.object("refresh")) {
        scene::JsonReader f(*refresh, scene.file.string(), desc.jsonPath + "/refresh");
        RefreshSettings& live = s.refresh;
        live.listen = f.string("listen", std::string()).value_or("");
        live.everySeconds = f.number("everySeconds", 0.0, 0.0, 86400.0).value_or(0.0);
        if (refresh->contains("glide")) {
            const nlohmann::json& glide = (*refresh)["glide"];
            f.accept("glide");
            if (glide.is_string() && glide.get<std::string>() == "auto") live.glideSeconds = -1.0;
            else if (glide.is_boolean() && !glide.get<bool>()) live.glideSeconds = 0.0;
            else if (glide.is_number() && glide.get<double>() >= 0.0 && glide.get<double>() <= 60.0) live.glideSeconds = glide.get<double>();
            else
                f.fail("glide", "expected \"auto\" (each point's time between moves), seconds from 0 to 60, or false (points jump), got " +
                                    glide.dump());
        }
        if (const nlohmann::json* trigger = f.object("trigger")) {
            scene::JsonReader t(*trigger, scene.file.string(), desc.jsonPath + "/refresh/trigger");
            live.triggerTable = t.string("table").value_or("");
            live.triggerGeometry = t.string("geometry", std::string("geom")).value_or("geom");
            if (t.ok() && live.triggerTable.empty()) t.fail("table", "name the table Orbis installs its trigger on");
            if (auto done = t.finish(); !done) return done.error();
            if (live.listen.empty()) f.fail("trigger", "the trigger notifies a channel: give \"listen\" too");
        }
        if (!live.listen.empty()) {
            if (auto connection = vector::libpqConnection(read.source); !connection)
                f.fail("listen", "LISTEN/NOTIFY needs a PostgreSQL source: " + connection.message());
        }
        if (f.ok() && !live.enabled())
            f.fail("listen", "give \"listen\" (a PostgreSQL channel) or \"everySeconds\" (read again on a clock), or leave \"refresh\" out");
        if (auto done = f.finish(); !done) return done.error();
        if (s.paging == Paging::Off)
            r.fail("paging", "a layer with \"refresh\" reads the changed feature tiles again: it needs \"paging\" (true or \"auto\"), not false");
        s.paging = Paging::On;
    }
    const nlohmann::json* style = r.object("style");
    if (auto done = r.finish(); !done) return done.error();

    auto parsed = vector::VectorStyle::read(style, scene.file.string(), desc.jsonPath + "/style");
    if (!parsed) return parsed.error();
    s.content.style = std::move(*parsed);
    if (!isConnection(read.source) && !std::filesystem::exists(read.source))
        return makeError(scene.file.string() + ": " + desc.jsonPath + "/path: " + read.source + ": no such file");
    return std::unique_ptr<scene::Layer>(std::make_unique<VectorLayer>(std::move(s)));
}

scene::LayerType VectorLayer::layerType() {
    return {"vector", "vector features (OGR: Shapefile, GeoPackage, GeoJSON, KML, WFS...) styled by rules, on the terrain",
            &VectorLayer::create, {"/path"}};
}

}  // namespace orbis::layers
