#include "layers/vector/VectorStyle.h"

#include "engine/scene/JsonReader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace orbis::vector {
namespace {

using nlohmann::json;

Error errorAt(const std::string& file, const std::string& path, const std::string& what) {
    return Error{file + ": " + path + ": " + what};
}

/// [r, g, b] from 0 to 1, or "#rrggbb".
std::optional<glm::dvec3> readColor(const json& v, std::string& problem) {
    if (v.is_string()) {
        const std::string s = v.get<std::string>();
        unsigned r = 0, g = 0, b = 0;
        int used = 0;
        if (s.size() == 7 && std::sscanf(s.c_str(), "#%2x%2x%2x%n", &r, &g, &b, &used) == 3 && used == 7)
            return glm::dvec3(r, g, b) / 255.0;
        problem = "a colour string is \"#rrggbb\", got \"" + s + "\"";
        return std::nullopt;
    }
    if (v.is_array() && v.size() == 3) {
        glm::dvec3 c;
        for (int i = 0; i < 3; ++i) {
            if (!v[size_t(i)].is_number() || !(v[size_t(i)].get<double>() >= 0.0 && v[size_t(i)].get<double>() <= 1.0)) {
                problem = "each channel is a number from 0 to 1";
                return std::nullopt;
            }
            c[i] = v[size_t(i)].get<double>();
        }
        return c;
    }
    problem = "expected a colour ([r, g, b] from 0 to 1, or \"#rrggbb\"), got " + scene::describeJsonType(v);
    return std::nullopt;
}

/// "{name} ({pop})" into pieces; "{{" and "}}" are braces.
std::optional<std::vector<std::string>> splitTemplate(const std::string& text, std::vector<bool>& isField, std::string& problem) {
    std::vector<std::string> pieces;
    std::string literal;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if ((c == '{' || c == '}') && i + 1 < text.size() && text[i + 1] == c) {
            literal += c;
            ++i;
        } else if (c == '{') {
            const size_t close = text.find('}', i + 1);
            if (close == std::string::npos || close == i + 1) {
                problem = "the label \"" + text + "\" has a '{' without a field name and '}'";
                return std::nullopt;
            }
            if (!literal.empty()) pieces.push_back(std::move(literal)), isField.push_back(false);
            literal.clear();
            pieces.push_back(text.substr(i + 1, close - i - 1));
            isField.push_back(true);
            i = close;
        } else if (c == '}') {
            problem = "the label \"" + text + "\" has a '}' without its '{' (write \"}}\" for a brace)";
            return std::nullopt;
        } else {
            literal += c;
        }
    }
    if (!literal.empty()) pieces.push_back(std::move(literal)), isField.push_back(false);
    return pieces;
}

std::optional<AttributeValue> scalarValue(const json& v) {
    if (v.is_null()) return AttributeValue{};
    if (v.is_boolean()) return AttributeValue{int64_t(v.get<bool>() ? 1 : 0)};
    if (v.is_number_integer()) return AttributeValue{v.get<int64_t>()};
    if (v.is_number()) return AttributeValue{v.get<double>()};
    if (v.is_string()) return AttributeValue{v.get<std::string>()};
    return std::nullopt;
}

std::optional<double> numeric(const AttributeValue& v) {
    if (const auto* i = std::get_if<int64_t>(&v)) return double(*i);
    if (const auto* d = std::get_if<double>(&v)) return *d;
    return std::nullopt;
}

bool equal(const AttributeValue& a, const AttributeValue& b) {
    if (std::holds_alternative<std::monostate>(a) || std::holds_alternative<std::monostate>(b))
        return std::holds_alternative<std::monostate>(a) && std::holds_alternative<std::monostate>(b);
    if (const auto* sa = std::get_if<std::string>(&a)) {
        const auto* sb = std::get_if<std::string>(&b);
        return sb && *sa == *sb;
    }
    if (std::holds_alternative<std::string>(b)) return false;
    if (std::holds_alternative<int64_t>(a) && std::holds_alternative<int64_t>(b)) return std::get<int64_t>(a) == std::get<int64_t>(b);
    return *numeric(a) == *numeric(b);
}

}  // namespace

std::string attributeText(const AttributeValue& value) {
    if (const auto* i = std::get_if<int64_t>(&value)) return std::to_string(*i);
    if (const auto* s = std::get_if<std::string>(&value)) return *s;
    if (const auto* d = std::get_if<double>(&value)) {
        if (!std::isfinite(*d)) return std::isnan(*d) ? "NaN" : (*d > 0 ? "inf" : "-inf");
        char text[32];
        std::snprintf(text, sizeof text, "%.6g", *d);
        return text;
    }
    return "";
}

Result<VectorStyle::Patch> VectorStyle::readPatch(const json& object, const std::string& file, const std::string& path,
                                                  Rule* rule) {
    scene::JsonReader r(object, file, path);
    if (!r.isObject()) return r.finish().error();
    Patch p;
    std::optional<Error> error;
    const auto fail = [&](const std::string& key, const std::string& what) {
        if (!error) error = errorAt(file, path + "/" + key, what);
    };
    const auto color = [&](const char* key, std::optional<glm::dvec3>& out) {
        if (!r.has(key)) return;
        r.accept(key);
        std::string problem;
        out = readColor(object[key], problem);
        if (!out) fail(key, problem);
    };
    const auto number = [&](const char* key, std::optional<double>& out, double min, double max) {
        if (r.has(key)) out = r.number(key, std::nullopt, min, max);
    };
    if (r.has("visible")) p.visible = r.boolean("visible");
    if (r.has("outline")) p.outline = r.boolean("outline");
    color("color", p.color);
    color("fill", p.fill);
    color("labelColor", p.labelColor);
    number("opacity", p.opacity, 0.0, 1.0);
    number("fillOpacity", p.fillOpacity, 0.0, 1.0);
    number("width", p.widthPx, 0.0, 256.0);
    if (const json* scale = r.has("iconScale") ? r.object("iconScale") : nullptr) {
        scene::JsonReader x(*scale, file, path + "/iconScale");
        const auto near = x.number("near", std::nullopt, 0.0, 1e12), far = x.number("far", std::nullopt, 0.0, 1e12);
        const auto factor = x.number("scale", std::nullopt, 0.01, 100.0);
        if (auto done = x.finish(); !done) {
            if (!error) error = done.error();
        } else if (near && far && factor) {
            if (*far > *near) p.iconScale = glm::dvec3(*near, *far, *factor);
            else fail("iconScale/far", "far must be beyond near");
        }
    }
    if (r.has("dash")) {
        // [on, off] or one length for both, in pixels; 0 or null: solid.
        r.accept("dash");
        const json& d = object["dash"];
        const auto length = [](const json& v) { return v.is_number() && v.get<double>() >= 0.0 && v.get<double>() <= 1024.0; };
        if (d.is_null()) p.dash = glm::dvec2(0.0);
        else if (length(d)) p.dash = glm::dvec2(d.get<double>());
        else if (d.is_array() && d.size() == 2 && length(d[0]) && length(d[1])) p.dash = glm::dvec2(d[0].get<double>(), d[1].get<double>());
        else fail("dash", "expected [on, off] in pixels (0 to 1024 each), one length for both, or null; got " + d.dump());
        if (p.dash && ((*p.dash)[0] == 0.0) != ((*p.dash)[1] == 0.0))
            fail("dash", "a dash needs both lengths above 0 (or both 0: solid), got " + d.dump());
    }
    number("iconSize", p.iconSizePx, 1.0, 1024.0);
    number("labelSize", p.labelSizePx, 1.0, 512.0);
    number("minRange", p.minRangeM, 0.0, 1e12);
    number("maxRange", p.maxRangeM, 0.0, 1e12);
    if (r.has("icon")) {
        // A PNG, relative to the scene's folder.
        p.icon = r.string("icon");
        if (p.icon && !p.icon->empty() && std::filesystem::path(*p.icon).is_relative())
            p.icon = (std::filesystem::path(file).parent_path() / *p.icon).lexically_normal().string();
    }
    if (r.has("label")) {
        if (auto text = r.string("label")) {
            std::vector<bool> isField;
            std::string problem;
            if (auto pieces = splitTemplate(*text, isField, problem)) {
                p.label.emplace();
                for (size_t i = 0; i < pieces->size(); ++i) p.label->push_back({(*pieces)[i], isField[i]});
            } else {
                fail("label", problem);
            }
        }
    }
    if (r.has("extrude")) {
        r.accept("extrude");
        const json& e = object["extrude"];
        if (e.is_null()) {
            p.noExtrude = true;
        } else if (e.is_number()) {
            if (e.get<double>() >= 0.0 && std::isfinite(e.get<double>())) p.extrude = Extrusion{.constant = e.get<double>()};
            else fail("extrude", "a height is a number of metres, 0 or more");
        } else if (e.is_string()) {
            p.extrude = Extrusion{.field = e.get<std::string>()};
        } else if (e.is_object()) {
            scene::JsonReader x(e, file, path + "/extrude");
            Extrusion ex;
            ex.field = x.string("field").value_or("");
            ex.scale = x.number("scale", 1.0, -1e6, 1e6).value_or(1.0);
            ex.add = x.number("add", 0.0, -1e6, 1e6).value_or(0.0);
            if (auto done = x.finish(); !done) {
                if (!error) error = done.error();
            } else if (ex.field.empty()) {
                fail("extrude/field", "the field to extrude by is empty");
            }
            p.extrude = ex;
        } else {
            fail("extrude", "expected metres, a field name or {\"field\", \"scale\", \"add\"}, got " + scene::describeJsonType(e));
        }
    }
    if (rule) {
        rule->name = r.string("name", std::string()).value_or("");
        rule->enabled = r.boolean("enabled", true).value_or(true);
        rule->layer = r.string("layer", std::string()).value_or("");
        if (const json* when = r.object("when")) {
            for (const auto& [field, value] : when->items()) {
                Condition c{.field = field};
                const std::string at = "when/" + field;
                if (value.is_array()) {
                    for (const json& v : value) {
                        if (auto a = scalarValue(v)) c.anyOf.push_back(*a);
                        else fail(at, "a list holds numbers, strings, booleans or null");
                    }
                } else if (value.is_object()) {
                    scene::JsonReader range(value, file, path + "/" + at);
                    if (range.has("min")) c.min = range.number("min");
                    if (range.has("max")) c.max = range.number("max");
                    if (auto done = range.finish(); !done) {
                        if (!error) error = done.error();
                    } else if (!c.min && !c.max) {
                        fail(at, "a range has \"min\", \"max\" or both");
                    } else if (c.min && c.max && *c.min > *c.max) {
                        fail(at, "the range's min is above its max");
                    }
                } else if (auto a = scalarValue(value)) {
                    c.anyOf.push_back(*a);
                } else {
                    fail(at, "expected a value, a list of values or a range, got " + scene::describeJsonType(value));
                }
                rule->when.push_back(std::move(c));
            }
        }
    } else {
        r.accept("rules");   // read by VectorStyle::read
    }
    auto done = r.finish();
    if (error) return *error;
    if (!done) return done.error();
    if (p.minRangeM && p.maxRangeM && *p.minRangeM > *p.maxRangeM)
        return errorAt(file, path + "/minRange", "minRange is above maxRange");
    return p;
}

Result<VectorStyle> VectorStyle::read(const json* style, const std::string& file, const std::string& path) {
    VectorStyle out;
    out.file_ = file;
    out.path_ = path;
    if (!style) return out;
    auto defaults = readPatch(*style, file, path, nullptr);
    if (!defaults) return defaults.error();
    out.defaults_ = std::move(*defaults);
    if (style->contains("rules")) {
        const json& rules = (*style)["rules"];
        if (!rules.is_array()) return errorAt(file, path + "/rules", "expected an array of rules, got " + scene::describeJsonType(rules));
        for (size_t i = 0; i < rules.size(); ++i) {
            Rule rule;
            rule.path = path + "/rules/" + std::to_string(i);
            auto patch = readPatch(rules[i], file, rule.path, &rule);
            if (!patch) return patch.error();
            rule.patch = std::move(*patch);
            if (rule.name.empty()) rule.name = "rule " + std::to_string(i + 1);
            out.rules_.push_back(std::move(rule));
        }
    }
    return out;
}

Result<void> VectorStyle::bind(std::span<const FieldInfo> fields, const std::string& layerName) {
    const auto bindPatch = [&](Patch& p, const std::string& path) -> Result<void> {
        const auto missing = [&](const std::string& key, const std::string& field) {
            return errorAt(file_, path + "/" + key,
                           "layer '" + layerName + "' has no field '" + field + "' (its fields: " + fieldNames(fields) + ")");
        };
        if (p.label)
            for (Piece& piece : *p.label)
                if (piece.isField) {
                    auto i = findField(fields, piece.text);
                    if (!i) return missing("label", piece.text);
                    piece.index = *i;
                }
        if (p.extrude && !p.extrude->field.empty()) {
            auto i = findField(fields, p.extrude->field);
            if (!i) return missing("extrude", p.extrude->field);
            p.extrudeIndex = *i;
        }
        return {};
    };
    if (auto ok = bindPatch(defaults_, path_); !ok) return ok;
    for (Rule& rule : rules_) {
        // A rule for another layer of the source is left out of this layer's style.
        rule.inLayer = rule.layer.empty() || rule.layer == layerName;
        if (!rule.inLayer) continue;
        if (auto ok = bindPatch(rule.patch, rule.path); !ok) return ok;
        for (Condition& c : rule.when) {
            auto i = findField(fields, c.field);
            if (!i)
                return errorAt(file_, rule.path + "/when/" + c.field,
                               "layer '" + layerName + "' has no field '" + c.field + "' (its fields: " + fieldNames(fields) + ")");
            c.index = *i;
        }
    }
    return {};
}

bool VectorStyle::matches(const Condition& c, std::span<const AttributeValue> attributes) {
    if (c.index >= attributes.size()) return false;
    const AttributeValue& v = attributes[c.index];
    if (c.min || c.max) {
        const auto x = numeric(v);
        return x && (!c.min || *x >= *c.min) && (!c.max || *x < *c.max);
    }
    for (const AttributeValue& a : c.anyOf)
        if (equal(v, a)) return true;
    return false;
}

void VectorStyle::apply(const Patch& p, std::span<const AttributeValue> attributes, FeatureStyle& s) const {
    if (p.visible) s.visible = *p.visible;
    if (p.outline) s.outline = *p.outline;
    if (p.color) s.color = *p.color;
    if (p.fill) s.fill = *p.fill;
    if (p.labelColor) s.labelColor = *p.labelColor;
    if (p.opacity) s.opacity = *p.opacity;
    if (p.fillOpacity) s.fillOpacity = *p.fillOpacity;
    if (p.widthPx) s.widthPx = *p.widthPx;
    if (p.dash) s.dashPx = *p.dash;
    if (p.iconScale) s.iconNearM = p.iconScale->x, s.iconFarM = p.iconScale->y, s.iconFarScale = p.iconScale->z;
    if (p.iconSizePx) s.iconSizePx = *p.iconSizePx;
    if (p.labelSizePx) s.labelSizePx = *p.labelSizePx;
    if (p.minRangeM) s.minRangeM = *p.minRangeM;
    if (p.maxRangeM) s.maxRangeM = *p.maxRangeM;
    if (p.icon) s.icon = *p.icon;
    if (p.label) {
        s.label.clear();
        for (const Piece& piece : *p.label)
            s.label += piece.isField ? (piece.index < attributes.size() ? attributeText(attributes[piece.index]) : "") : piece.text;
    }
    if (p.noExtrude) s.extrudeM.reset();
    if (p.extrude) {
        if (p.extrude->field.empty()) {
            s.extrudeM = p.extrude->constant;
        } else {
            const auto x = p.extrudeIndex < attributes.size() ? numeric(attributes[p.extrudeIndex]) : std::nullopt;
            // A feature without a usable height stays flat.
            if (x && std::isfinite(*x)) s.extrudeM = std::max(0.0, *x * p.extrude->scale + p.extrude->add);
            else s.extrudeM.reset();
        }
    }
}

FeatureStyle VectorStyle::evaluate(std::span<const AttributeValue> attributes, const SourceStyle* own) const {
    FeatureStyle s;
    if (own) {
        const FeatureStyle builtIn;
        if (own->lineColor) s.color = glm::dvec3(*own->lineColor), s.opacity = own->lineColor->a;
        if (own->lineWidthPx) s.widthPx = *own->lineWidthPx;
        if (own->fillColor) s.fill = glm::dvec3(*own->fillColor), s.fillOpacity = own->fillColor->a;
        if (own->icon) s.icon = *own->icon;
        if (own->iconScale) s.iconSizePx = builtIn.iconSizePx * *own->iconScale;
        if (own->labelColor) s.labelColor = glm::dvec3(*own->labelColor);
        if (own->labelScale) s.labelSizePx = builtIn.labelSizePx * *own->labelScale;
    }
    apply(defaults_, attributes, s);
    for (size_t i = 0; i < rules_.size(); ++i) {
        const Rule& rule = rules_[i];
        if (!rule.enabled || !rule.inLayer) continue;
        bool all = true;
        for (const Condition& c : rule.when) all = all && matches(c, attributes);
        if (!all) continue;
        apply(rule.patch, attributes, s);
        s.rule = int32_t(i);
    }
    return s;
}

double featureReachPx(const FeatureStyle& s) { return 0.5 * std::max(s.widthPx, s.iconSizePx * (s.icon.empty() ? 1.0 : 4.0)) + 8.0; }

bool VectorStyle::namesExtrusion() const {
    return defaults_.extrude || std::any_of(rules_.begin(), rules_.end(), [](const Rule& r) { return r.patch.extrude.has_value(); });
}

double VectorStyle::reachPx() const {
    // Each property's largest value comes from the defaults or one rule: the largest reach
    // of the defaults alone and of each rule over them.
    FeatureStyle base;
    apply(defaults_, {}, base);
    double reach = featureReachPx(base);
    for (const Rule& rule : rules_) {
        FeatureStyle s = base;
        apply(rule.patch, {}, s);
        reach = std::max(reach, featureReachPx(s));
    }
    return reach;
}

double VectorStyle::maxRangeM() const {
    double range = defaults_.maxRangeM.value_or(FeatureStyle{}.maxRangeM);
    for (const Rule& rule : rules_)
        if (rule.enabled && rule.patch.maxRangeM) range = std::max(range, *rule.patch.maxRangeM);
    return range;
}

bool VectorStyle::namesLabel() const {
    const auto names = [](const Patch& p) { return p.label && !p.label->empty(); };
    if (names(defaults_)) return true;
    return std::any_of(rules_.begin(), rules_.end(), [&](const Rule& r) { return names(r.patch); });
}

}  // namespace orbis::vector
