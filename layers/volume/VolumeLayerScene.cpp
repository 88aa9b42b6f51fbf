// The volume layer's scene-file side: its settings read from JSON (with errors that name the key
// and the problem), the data read from netCDF with every time step, and the synthetic fields.
#include "layers/volume/VolumeLayer.h"

#include "engine/scene/JsonReader.h"
#include "shared/VolumeTypes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace orbis::layers {

// ---------------------------------------------------------------------------------------------
// Synthetic fields

VolumeField makeSyntheticVolume(const SyntheticVolume& s) {
    VolumeField f;
    f.variable = "synthetic ";
    f.variable += s.field;
    const auto axis = [](double a, double b, size_t n) {
        std::vector<double> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = n > 1 ? a + (b - a) * double(i) / double(n - 1) : a;
        return v;
    };
    f.lonDeg = axis(s.west, s.east, s.nx);
    f.latDeg = axis(s.south, s.north, s.ny);
    f.heightM = axis(s.bottom, s.top, s.nz);
    f.verticalRaw = f.heightM;
    f.verticalUnits.assign(1, 'm');   // (not = "m": GCC 12 -Wrestrict false positive)
    f.values.resize(s.nx * s.ny * s.nz);
    const double cx = 0.5 * double(s.nx - 1), cy = 0.5 * double(s.ny - 1), cz = 0.5 * double(s.nz - 1);
    for (size_t k = 0; k < s.nz; ++k)
        for (size_t j = 0; j < s.ny; ++j)
            for (size_t i = 0; i < s.nx; ++i) {
                double v;
                if (s.field == "constant") v = 1.0;
                else if (s.field == "empty") v = std::numeric_limits<double>::quiet_NaN();
                else if (s.field == "peer") {
                    const double x = -1.0 + 2.0 * double(i) / double(s.nx - 1), y = -1.0 + 2.0 * double(j) / double(s.ny - 1),
                                 z = -1.0 + 2.0 * double(k) / double(s.nz - 1);
                    const double r2 = (x - 0.3) * (x - 0.3) + (y + 0.2) * (y + 0.2) + (z - 0.2) * (z - 0.2);
                    v = std::sin(3.0 * x) * std::cos(2.0 * y) * z + 1.5 * std::exp(-r2 / (2.0 * 0.3 * 0.3));
                } else if (s.field == "waves")
                    v = std::sin(6.0 * double(i) / double(s.nx)) * std::sin(5.0 * double(j) / double(s.ny)) *
                        std::cos(4.0 * double(k) / double(s.nz));
                else
                    v = std::sqrt((i - cx) * (i - cx) + (j - cy) * (j - cy) + (k - cz) * (k - cz));
                f.values[(k * s.ny + j) * s.nx + i] = float(v);
            }
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (float v : f.values)
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v), ++f.validCount;
    if (f.validCount) f.minValue = lo, f.maxValue = hi;
    return f;
}

// ---------------------------------------------------------------------------------------------
// Scene file

namespace {

/// The data a volume shows: the field (time step 0, or the fixed one) with its grid, and the
/// values of the other time steps when virtual time animates it.
struct LoadedVolume {
    std::optional<VolumeField> field;
    std::vector<std::vector<float>> moreTimeSteps;
    std::vector<TimeNs> timeStepTimes;
};

/// "synthetic": {"field", "size", "lon", "lat", "height", "times"}.
SyntheticVolume readSyntheticKeys(scene::JsonReader& sr) {
    SyntheticVolume sv;
    sv.field = sr.string("field", sv.field).value_or(sv.field);
    if (sv.field != "sphere" && sv.field != "waves" && sv.field != "constant" && sv.field != "empty" && sv.field != "peer")
        sr.fail("field", "expected \"sphere\", \"waves\", \"constant\", \"empty\" (all no data) or \"peer\"");
    if (auto size = sr.numbers("size", 3, std::vector<double>{64, 64, 64}); size && size->size() == 3) {
        for (double n : *size)
            if (n < 2 || n > 1024 || n != std::floor(n)) sr.fail("size", "each size is an integer from 2 to 1024");
        sv.nx = size_t((*size)[0]), sv.ny = size_t((*size)[1]), sv.nz = size_t((*size)[2]);
    }
    const auto pair = [&](const char* key, double& lo, double& hi, double min, double max) {
        if (auto v = sr.numbers(key, 2, std::vector<double>{lo, hi}); v && v->size() == 2) {
            if (!((*v)[0] < (*v)[1]) || (*v)[0] < min || (*v)[1] > max)
                sr.fail(key, "must be [low, high] with low < high within " + std::to_string(int(min)) + " .. " +
                                 std::to_string(int(max)));
            lo = (*v)[0], hi = (*v)[1];
        }
    };
    pair("lon", sv.west, sv.east, -360, 360);
    pair("lat", sv.south, sv.north, -90, 90);
    pair("height", sv.bottom, sv.top, -1e6, 1e7);
    if (sv.east - sv.west > 360.0) sr.fail("lon", "spans more than 360 degrees");
    if (const nlohmann::json* times = sr.array("times")) {
        for (const auto& t : *times) {
            auto parsed = t.is_string() ? parseIso8601(t.get<std::string>()) : Result<TimeNs>(makeError("not a string"));
            if (!parsed) {
                sr.fail("times", "each time is an ISO 8601 instant");
                break;
            }
            if (!sv.times.empty() && *parsed <= sv.times.back()) sr.fail("times", "times must increase");
            sv.times.push_back(*parsed);
        }
    }
    return sv;
}

/// A synthetic field; time step s holds the field plus s.
Result<LoadedVolume> loadSynthetic(const nlohmann::json& synthetic, const scene::LayerDesc& desc,
                                   const scene::SceneDesc& scene) {
    scene::JsonReader sr(synthetic, scene.file.string(), desc.jsonPath + "/synthetic");
    const SyntheticVolume sv = readSyntheticKeys(sr);
    if (auto done = sr.finish(); !done) return done.error();
    LoadedVolume out;
    out.field = makeSyntheticVolume(sv);
    for (size_t ts = 1; ts < sv.times.size(); ++ts) {
        std::vector<float> v = out.field->values;
        for (float& x : v) x += float(ts);
        out.moreTimeSteps.push_back(std::move(v));
    }
    if (sv.times.size() > 1) out.field->maxValue += float(sv.times.size() - 1);
    out.timeStepTimes = sv.times;
    return out;
}

/// A variable of a file ("path", "variable", "timeStep", "pressureToHeight"): one time step, or
/// all of them when virtual time animates it. An empty field when a key is wrong (r holds why).
Result<LoadedVolume> loadFile(scene::JsonReader& r, const std::string& path, const scene::SceneDesc& scene,
                              const std::string& where, VolumeSettings::TimeMode timeMode) {
    VolumeReadOptions o;
    o.path = scene.resolve(path).string();
    o.variable = r.string("variable", std::string()).value_or("");
    if (r.ok() && o.variable.empty()) r.fail("variable", "name the variable to show");
    o.timeIndex = size_t(r.number("timeStep", 0.0, 0.0, 1e9).value_or(0.0));
    if (auto p = r.string("pressureToHeight", std::string("standard"))) {
        if (*p == "standard") o.pressureToHeight = PressureToHeight::StandardAtmosphere;
        else if (*p == "scaleHeight") o.pressureToHeight = PressureToHeight::ScaleHeight;
        else r.fail("pressureToHeight", "expected \"standard\" or \"scaleHeight\"");
    }
    LoadedVolume out;
    if (!r.ok()) return out;
    // Animated by virtual time: every step, when they fit, read through one open of the file (a
    // file replaced meanwhile cannot mix two grids); step 0 in out.field, the others after it.
    auto animate = [&](const VolumeField& grid) -> Result<bool> {
        if (timeMode == VolumeSettings::TimeMode::Fixed || grid.times.size() <= 1) return false;
        const size_t timeSteps = grid.timeSteps;
        const uint64_t timeStepBytes = uint64_t(grid.nx()) * grid.ny() * grid.nz() * sizeof(float);
        if (timeStepBytes * timeSteps > o.maxBytes || grid.nz() * timeSteps > 2048)
            return makeError(std::to_string(timeSteps) + " time steps of " + std::to_string(timeStepBytes >> 20) +
                             " MB do not fit (memory budget " + std::to_string(o.maxBytes >> 20) +
                             " MB, 2048 levels in all): set \"time\": \"fixed\" and pick a \"timeStep\"");
        return true;
    };
    auto read = readVolumeTimeSteps(o, animate);
    if (!read) return makeError(where + ": " + read.message());
    out.field = std::move(read->field);
    if (!read->more.empty()) {
        out.moreTimeSteps = std::move(read->more);
        out.timeStepTimes = out.field->times;
    }
    return out;
}

/// "time", then the data: "path" (with "variable") or "synthetic".
Result<LoadedVolume> loadData(scene::JsonReader& r, const scene::LayerDesc& desc, const scene::SceneDesc& scene,
                              const std::string& where, VolumeSettings& s) {
    if (auto mode = r.string("time", std::string("blend"))) {
        if (*mode == "blend") s.timeMode = VolumeSettings::TimeMode::Blend;
        else if (*mode == "nearest") s.timeMode = VolumeSettings::TimeMode::Nearest;
        else if (*mode == "fixed") s.timeMode = VolumeSettings::TimeMode::Fixed;
        else r.fail("time", "expected \"blend\", \"nearest\" or \"fixed\"");
    }
    const auto path = r.string("path", std::string());
    const nlohmann::json* synthetic = r.object("synthetic");
    if (path && !path->empty() && synthetic) r.fail("synthetic", "give either \"path\" or \"synthetic\", not both");
    if (synthetic && r.ok()) return loadSynthetic(*synthetic, desc, scene);
    if (path && !path->empty() && r.ok()) return loadFile(r, *path, scene, where, s.timeMode);
    if (r.ok()) r.fail("path", "give the data: \"path\" (with \"variable\") or \"synthetic\"");
    return LoadedVolume{};
}

/// "slices": [{"lon": deg}, {"lat": deg}, {"height": m}] (mode "slice").
void readSlices(scene::JsonReader& r, VolumeSettings& s) {
    const nlohmann::json* list = r.array("slices", true);
    if (!list) return;
    for (const auto& item : *list) {
        VolumeSettings::Slice sl;
        const bool one = item.is_object() && item.size() == 1 && item.begin().value().is_number();
        const std::string key = one ? item.begin().key() : std::string();
        if (key == "lon") sl.axis = VolumeSettings::Slice::Axis::Lon;
        else if (key == "lat") sl.axis = VolumeSettings::Slice::Axis::Lat;
        else if (key == "height") sl.axis = VolumeSettings::Slice::Axis::Height;
        else {
            r.fail("slices", "each slice is {\"lon\": deg}, {\"lat\": deg} or {\"height\": m}");
            break;
        }
        sl.value = item.begin().value().get<double>();
        if (sl.axis == VolumeSettings::Slice::Axis::Lat && !kSliceLatitudeRange.contains(sl.value))
            r.fail("slices", "a latitude slice must be within " + std::to_string(int(kSliceLatitudeRange.min)) + " .. " +
                                 std::to_string(int(kSliceLatitudeRange.max)) + " degrees");
        s.slices.push_back(sl);
    }
    if (r.ok() && (s.slices.empty() || s.slices.size() > shader::kVolumeMaxSlices))
        r.fail("slices", "mode \"slice\" needs 1 to " + std::to_string(shader::kVolumeMaxSlices) + " slices");
}

/// "mode" and what the modes use: "isovalues" (iso), "slices" (slice).
void readModes(scene::JsonReader& r, VolumeSettings& s) {
    bool iso = false, slice = false;
    if (const nlohmann::json* modes = r.array("mode")) {
        s.dvr = false;
        for (const auto& m : *modes) {
            const std::string mode = m.is_string() ? m.get<std::string>() : std::string();
            if (mode == "dvr") s.dvr = true;
            else if (mode == "iso") iso = true;
            else if (mode == "slice") slice = true;
            else r.fail("mode", "expected \"dvr\", \"iso\" or \"slice\"");
        }
        if (r.ok() && !s.dvr && !iso && !slice) r.fail("mode", "name at least one mode");
    }
    if (iso) {
        if (auto values = r.numbers("isovalues", 0); values) s.isovalues = *values;
        if (r.ok() && (s.isovalues.empty() || s.isovalues.size() > shader::kVolumeMaxIso))
            r.fail("isovalues", "mode \"iso\" needs 1 to " + std::to_string(shader::kVolumeMaxIso) + " isovalues");
    } else if (r.has("isovalues")) {
        r.fail("isovalues", "only used with mode \"iso\" (add \"iso\" to \"mode\")");
    }
    if (slice) readSlices(r, s);
    else if (r.has("slices")) r.fail("slices", "only used with mode \"slice\" (add \"slice\" to \"mode\")");
}

/// "colorMap", "range" and the "opacity" curve.
void readTransfer(scene::JsonReader& r, VolumeSettings& s) {
    s.transfer.colorMap = r.string("colorMap", s.transfer.colorMap).value_or(s.transfer.colorMap);
    if (!hasColorMap(s.transfer.colorMap)) {
        std::string names;
        for (const auto& n : colorMapNames()) names += (names.empty() ? "" : ", ") + n;
        r.fail("colorMap", "unknown colour map \"" + s.transfer.colorMap + "\" (known: " + names + ")");
    }
    if (r.has("range")) {
        if (auto range = r.numbers("range", 2); range && range->size() == 2) {
            if (!((*range)[1] > (*range)[0])) r.fail("range", "must be [low, high] with low < high");
            s.transfer.rangeMin = (*range)[0], s.transfer.rangeMax = (*range)[1];
            s.rangeFromData = false;
        }
    }
    if (const nlohmann::json* points = r.array("opacity")) {
        if (points->size() > kMaxOpacityPoints)
            r.fail("opacity", "at most " + std::to_string(kMaxOpacityPoints) + " points, got " + std::to_string(points->size()));
        for (const auto& p : *points) {
            if (points->size() > kMaxOpacityPoints) break;
            if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number() || p[1].get<double>() < 0.0 ||
                p[1].get<double>() > 1.0) {
                r.fail("opacity", "each point is [value, alpha] with alpha in 0..1");
                break;
            }
            s.transfer.opacity.push_back({p[0].get<double>(), p[1].get<double>()});
        }
    }
}

/// How the volume is drawn: opacities, steps, the transfer function, exaggeration, skipping,
/// the field's format.
void readLook(scene::JsonReader& r, VolumeSettings& s) {
    s.sliceOpacity = r.number("sliceOpacity", 1.0, kOpacityRange.min, kOpacityRange.max).value_or(1.0);
    s.isoOpacity = r.number("isoOpacity", 1.0, kOpacityRange.min, kOpacityRange.max).value_or(1.0);
    s.steps = int(r.number("steps", s.steps, kStepsRange.min, kStepsRange.max).value_or(s.steps));
    s.opacityUnit = r.number("opacityUnit", s.opacityUnit, kOpacityUnitRange.min, kOpacityUnitRange.max).value_or(s.opacityUnit);
    readTransfer(r, s);
    s.transfer.opacityScale = r.number("opacityScale", 1.0, kOpacityScaleRange.min, kOpacityScaleRange.max).value_or(1.0);
    s.verticalExaggeration = r.number("verticalExaggeration", 1.0, 0.001, 10000.0).value_or(1.0);
    s.emptySkipping = r.boolean("emptySkipping", true).value_or(true);
    s.preIntegration = r.boolean("preIntegration", false).value_or(false);
    s.rayResolution = r.number("rayResolution", 1.0, kRayResolutionRange.min, kRayResolutionRange.max).value_or(1.0);
    s.refineThreshold = r.number("refineThreshold", s.refineThreshold, kRefineThresholdRange.min, kRefineThresholdRange.max)
                            .value_or(s.refineThreshold);
    if (auto format = r.string("fieldFormat", std::string("float32"))) {
        if (*format == "float16") s.halfField = true;
        else if (*format != "float32") r.fail("fieldFormat", "expected \"float32\" or \"float16\"");
    }
}

/// Without "range": the data's (any range when there is no data to show).
void rangeFromData(VolumeSettings& s, const VolumeField& field) {
    if (!s.rangeFromData) return;
    if (field.validCount == 0) {
        s.transfer.rangeMin = 0.0, s.transfer.rangeMax = 1.0;
    } else {
        s.transfer.rangeMin = field.minValue;
        s.transfer.rangeMax = field.maxValue > field.minValue ? double(field.maxValue) : field.minValue + 1.0;
    }
}

}  // namespace

Result<std::unique_ptr<scene::Layer>> VolumeLayer::create(const scene::LayerDesc& desc, const scene::SceneDesc& scene) {
    scene::JsonReader r(desc.settings, scene.file.string(), desc.jsonPath);
    for (const char* common : {"type", "name", "visible", "viewpoint"}) r.accept(common);
    const std::string where = scene.file.string() + ": " + desc.jsonPath;
    VolumeSettings s;
    auto data = loadData(r, desc, scene, where, s);
    if (!data) return data.error();
    readModes(r, s);
    readLook(r, s);
    if (auto done = r.finish(); !done) return done.error();

    rangeFromData(s, *data->field);
    if (auto table = buildTransferTable(s.transfer); !table) return makeError(where + ": " + table.message());
    return std::unique_ptr<scene::Layer>(new VolumeLayer(std::move(*data->field), std::move(s),
                                                         std::move(data->moreTimeSteps), std::move(data->timeStepTimes)));
}

scene::LayerType VolumeLayer::layerType() {
    return {"volume", "netCDF scalar field in a curved geo-box, ray cast on the GPU", &VolumeLayer::create, {"/path"}};
}

}  // namespace orbis::layers
