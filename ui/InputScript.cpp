#include "ui/InputScript.h"

#include "base/FileText.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace orbis::ui {
namespace {

constexpr std::uintmax_t kMaxScriptBytes = 4u << 20;
constexpr size_t kMaxSteps = 100000;

/// The keys a script may press beyond the navigation keys (the viewer's shortcuts).
bool isShortcutKey(const std::string& name) {
    static const std::set<std::string> k{"F1", "F12", "Ctrl+S", "Escape"};
    return k.count(name) != 0;
}

/// A point [x, y]: finite and within 1e5 of the origin.
bool readPoint(const nlohmann::json& j, const char* key, std::array<double, 2>& out) {
    if (!j.contains(key)) return false;
    const auto& p = j[key];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) return false;
    out = {p[0].get<double>(), p[1].get<double>()};
    return std::isfinite(out[0]) && std::isfinite(out[1]) && std::abs(out[0]) < 1e5 && std::abs(out[1]) < 1e5;
}

/// A finite number in [lo, hi].
bool readNumber(const nlohmann::json& j, const char* key, double lo, double hi, double& out) {
    if (!j.contains(key)) return false;
    if (!j[key].is_number()) return false;
    out = j[key].get<double>();
    return std::isfinite(out) && out >= lo && out <= hi;
}

/// "frames": how many frames a drag takes or a key is held (1 to 1000).
Result<void> readFrames(const nlohmann::json& j, const std::string& where, double frames, ScriptStep& s) {
    if (j.contains("frames") && !readNumber(j, "frames", 1, 1000, frames)) return Error{where + ": \"frames\" is 1 to 1000"};
    s.frames = int(frames);
    return {};
}

Result<void> readDrag(const nlohmann::json& j, const std::string& where, ScriptStep& s) {
    s.kind = ScriptStep::Kind::Drag;
    if (!readPoint(j, "from", s.from) || !readPoint(j, "to", s.to))
        return Error{where + ": drag needs \"from\" and \"to\": [x, y] pixels"};
    if (j.contains("item")) {
        if (!j["item"].is_string()) return Error{where + ": \"item\" is a panel item's label"};
        s.item = j["item"].get<std::string>();
        for (double v : {s.from[0], s.from[1], s.to[0], s.to[1]})
            if (v < 0.0 || v > 1.0)
                return Error{where + ": with \"item\", \"from\" and \"to\" are fractions of the item (0 to 1)"};
    }
    if (j.contains("button")) {
        if (!j["button"].is_string()) return Error{where + ": \"button\" is left, right or middle"};
        s.button = j["button"].get<std::string>();
        if (s.button != "left" && s.button != "right" && s.button != "middle")
            return Error{where + ": \"button\" is left, right or middle, not \"" + s.button + "\""};
    }
    if (j.contains("shift")) {
        if (!j["shift"].is_boolean()) return Error{where + ": \"shift\" is true or false"};
        s.shift = j["shift"].get<bool>();
    }
    return readFrames(j, where, 8, s);
}

Result<void> readKey(const nlohmann::json& j, const std::string& where, ScriptStep& s) {
    s.kind = ScriptStep::Kind::Key;
    if (!j.contains("key") || !j["key"].is_string() ||
        (!navigationKey(j["key"].get<std::string>()) && !isShortcutKey(j["key"].get<std::string>())))
        return Error{where + ": \"key\" is one of W A S D Q E R F Up Down Left Right PageUp PageDown Home F1 F12 Ctrl+S Escape"};
    s.key = j["key"].get<std::string>();
    return readFrames(j, where, 1, s);
}

/// The steps with no fields to speak of, and those with one or two.
Result<void> readSimpleStep(const nlohmann::json& j, const std::string& op, const std::string& where,
                            const std::filesystem::path& folder, ScriptStep& s) {
    if (op == "scroll") {
        s.kind = ScriptStep::Kind::Scroll;
        if (!readPoint(j, "at", s.from)) return Error{where + ": scroll needs \"at\": [x, y] pixels"};
        if (!readNumber(j, "lines", -100, 100, s.lines)) return Error{where + ": scroll needs \"lines\" from -100 to 100"};
    } else if (op == "doubleClick") {
        s.kind = ScriptStep::Kind::DoubleClick;
        if (!readPoint(j, "at", s.from)) return Error{where + ": doubleClick needs \"at\": [x, y] pixels"};
    } else if (op == "click") {
        s.kind = ScriptStep::Kind::Click;
        if (j.contains("item") && j["item"].is_string()) s.item = j["item"].get<std::string>();
        else if (!readPoint(j, "at", s.from)) return Error{where + ": click needs \"at\": [x, y] pixels or \"item\": a label"};
    } else if (op == "settle") {
        s.kind = ScriptStep::Kind::Settle;
    } else if (op == "screenshot") {
        s.kind = ScriptStep::Kind::Screenshot;
        if (!j.contains("file") || !j["file"].is_string() || j["file"].get<std::string>().empty())
            return Error{where + ": screenshot needs \"file\""};
        s.file = folder / j["file"].get<std::string>();
    } else if (op == "idle") {
        s.kind = ScriptStep::Kind::Idle;
        if (!readNumber(j, "seconds", 0.1, 600, s.seconds)) return Error{where + ": idle needs \"seconds\" from 0.1 to 600"};
    } else if (op == "quit") {
        s.kind = ScriptStep::Kind::Quit;
    } else {
        return Error{where + ": unknown \"do\": \"" + op +
                     "\" (drag, scroll, key, doubleClick, click, settle, screenshot, idle, quit)"};
    }
    return {};
}

/// One step; `where` is "FILE: step N" for messages, `folder` the script's (screenshot files).
Result<ScriptStep> readStep(const nlohmann::json& j, const std::string& where, const std::filesystem::path& folder) {
    if (!j.is_object() || !j.contains("do") || !j["do"].is_string())
        return Error{where + ": each step is an object with \"do\""};
    ScriptStep s;
    const std::string op = j["do"].get<std::string>();
    Result<void> ok = op == "drag"  ? readDrag(j, where, s)
                      : op == "key" ? readKey(j, where, s)
                                    : readSimpleStep(j, op, where, folder, s);
    if (!ok) return ok.error();
    return s;
}

}  // namespace

std::optional<Key> navigationKey(const std::string& name) {
    static const std::pair<const char*, Key> names[] = {
        {"W", Key::W},       {"A", Key::A},         {"S", Key::S},           {"D", Key::D},
        {"Q", Key::Q},       {"E", Key::E},         {"R", Key::R},           {"F", Key::F},
        {"Up", Key::Up},     {"Down", Key::Down},   {"Left", Key::Left},     {"Right", Key::Right},
        {"PageUp", Key::PageUp}, {"PageDown", Key::PageDown}, {"Home", Key::Home}};
    for (const auto& [n, k] : names)
        if (name == n) return k;
    return std::nullopt;
}

Result<std::vector<ScriptStep>> readInputScript(const std::filesystem::path& file) {
    const std::string name = file.string();
    auto text = readTextFile(file, kMaxScriptBytes, "input script");
    if (!text) return text.error();
    nlohmann::json doc = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
    if (doc.is_discarded()) return Error{name + ": not valid JSON"};
    if (!doc.is_array()) return Error{name + ": expected a list of steps ([{\"do\": ...}, ...])"};
    if (doc.size() > kMaxSteps) return Error{name + ": more than 100000 steps"};
    const std::filesystem::path folder = file.parent_path();
    std::vector<ScriptStep> steps;
    for (size_t i = 0; i < doc.size(); ++i) {
        auto step = readStep(doc[i], name + ": step " + std::to_string(i + 1), folder);
        if (!step) return step.error();
        steps.push_back(std::move(step).value());
    }
    return steps;
}

}  // namespace orbis::ui
