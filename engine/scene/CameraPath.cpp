#include "engine/scene/CameraPath.h"

#include "base/FileText.h"
#include "engine/scene/JsonReader.h"
#include "engine/scene/SceneDesc.h"
#include "globe/EarthManipulator.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace orbis::scene {

Result<CameraPath> CameraPath::parseFile(const std::filesystem::path& file) {
    auto text = readTextFile(file, kMaxCameraPathFileBytes, "camera path file");
    if (!text) return text.error();
    return parseText(std::move(text).value(), file.string());
}

Result<CameraPath> CameraPath::parseText(std::string text, std::string fileNameForErrors) {
    const std::string name = fileNameForErrors.empty() ? std::string("<memory>") : std::move(fileNameForErrors);
    auto parsed = parseJsonText(text, name);
    if (!parsed) return parsed.error();
    const nlohmann::json& root = *parsed;

    JsonReader r(root, name, "");
    if (!r.isObject()) return r.finish().error();
    if (auto version = r.number("orbis-camera-path"); version && *version != 1.0)
        r.fail("orbis-camera-path", "camera path format version " + formatJsonNumber(*version) +
                                        " is not supported (this build reads 1)");

    CameraPath path;
    if (auto interp = r.string("interpolation", std::string("smooth"))) {
        if (*interp == "smooth") path.interpolation_ = Interpolation::Smooth;
        else if (*interp == "linear") path.interpolation_ = Interpolation::Linear;
        else r.fail("interpolation", "expected \"smooth\" or \"linear\", got \"" + *interp + "\"");
    }

    const nlohmann::json* keys = r.array("keys", true);
    if (keys && r.ok()) {
        if (keys->size() < 2)
            r.fail("keys", "a camera path needs at least 2 keys, got " + std::to_string(keys->size()));
        for (size_t i = 0; i < keys->size() && r.ok(); ++i) {
            const std::string keyPath = "/keys/" + std::to_string(i);
            JsonReader kr((*keys)[i], name, keyPath);
            Key key;
            if (auto t = kr.number("t", std::nullopt, 0.0, 1e12)) {
                key.t = *t;
                if (!path.keys_.empty() && key.t <= path.keys_.back().t)
                    kr.fail("t", "must be greater than the previous key's t (" + formatJsonNumber(path.keys_.back().t) + ")");
            }
            if (const nlohmann::json* vp = kr.object("viewpoint", true)) {
                Error err;
                if (auto v = readViewpoint(*vp, name, keyPath + "/viewpoint", &err)) key.viewpoint = *v;
                else if (kr.ok()) return err;
            }
            if (auto done = kr.finish(); !done) return done.error();
            path.keys_.push_back(key);
        }
    }
    if (auto done = r.finish(); !done) return done.error();
    return path;
}

globe::Viewpoint CameraPath::at(double seconds) const {
    if (keys_.empty()) return {};
    if (!(seconds > keys_.front().t)) return keys_.front().viewpoint;   // also NaN
    if (seconds >= keys_.back().t) return keys_.back().viewpoint;
    // The first key after `seconds`; the leg runs from the one before it.
    const auto next = std::upper_bound(keys_.begin(), keys_.end(), seconds,
                                       [](double s, const Key& k) { return s < k.t; });
    const Key& a = *(next - 1);
    const Key& b = *next;
    const double u = (seconds - a.t) / (b.t - a.t);
    return globe::interpolateFlight(a.viewpoint, b.viewpoint,
                                    interpolation_ == Interpolation::Smooth ? globe::easeInOut(u) : u);
}

}  // namespace orbis::scene
