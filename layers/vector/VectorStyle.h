#pragma once
// How a vector layer's features look: a default style plus rules matched on attributes, read
// from the layer's "style" object in the scene. No Vulkan.
//
//   "style": {
//     "color": [1, 0.8, 0], "opacity": 1, "width": 2,          lines, outlines, markers (px)
//     "dash": [8, 4] | 6,                 on and off along lines and outlines (px)
//     "fill": [0.2, 0.4, 1], "fillOpacity": 0.5, "outline": true,
//     "icon": "icons/city.png", "iconSize": 16,                  points (px)
//     "iconScale": {"near": 1e4, "far": 1e6, "scale": 0.5},      size x 1 nearer than near,
//                                            x scale past far, linear between (camera range, m)
//     "extrude": 30 | "height" | {"field": "levels", "scale": 3, "add": 0},   metres
//     "label": "{name} ({pop_est})", "labelColor": [1, 1, 1], "labelSize": 14,
//     "minRange": 0, "maxRange": 2e7,                            camera distance (m)
//     "rules": [
//       {"name": "capitals", "when": {"featurecla": "Admin-0 capital"}, "color": [1, 0, 0]},
//       {"when": {"pop_max": {"min": 1e6}}, "iconSize": 24},
//       {"when": {"continent": ["Asia", "Europe"]}, "visible": false, "enabled": true},
//       {"layer": "states_provinces", "color": [0.8, 0.8, 0.8], "maxRange": 5e6}
//     ]
//   }
//
// A colour is [r, g, b] from 0 to 1 (sRGB) or "#rrggbb". Rules apply in order: each rule whose
// conditions all hold sets the properties it names, over the defaults and the rules before it.
// A condition is an equality (a number, a string, a boolean as 1/0, or null), a list (any of
// its values), or a range {"min": a, "max": b} (min included, max excluded; numbers only). A
// label is a template: "{field}" is the field's value, "{{" and "}}" are braces. A rule with
// "enabled": false is skipped (the viewer's switch for each rule, saved with the scene). A
// rule with "layer" applies only to that layer of the source (its fields are checked there).
//
// A feature's own style (KML's styles, VectorLayer::styles) sits between the built-in defaults
// and the scene's: the scene overrides only what it names.
//
// The style is read without the data (VectorStyle::read), then bound to the layer's fields
// (bind): a rule, label or extrusion that names a field the layer does not have is an error
// naming the rule and the field.

#include "base/Result.h"
#include "layers/vector/VectorReader.h"

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orbis::vector {

/// Extruded height (m) = constant, or the field's number * scale + add.
struct Extrusion {
    double constant = 0.0;
    std::string field;   ///< empty: the constant
    double scale = 1.0, add = 0.0;
};

/// The look of one feature, every property resolved.
struct FeatureStyle {
    bool visible = true;
    glm::dvec3 color{1.0, 0.85, 0.0};
    double opacity = 1.0;
    double widthPx = 2.0;
    glm::dvec2 dashPx{0.0};    ///< on, off (px) along lines and outlines; 0: solid
    glm::dvec3 fill{0.2, 0.45, 0.9};
    double fillOpacity = 0.4;
    bool outline = true;
    std::string icon;          ///< a PNG's path (resolved against the scene's folder), empty: a marker
    double iconSizePx = 12.0;
    /// Icons and markers scale with the camera's range: x 1 up to iconNearM, x iconFarScale
    /// from iconFarM on, linear between (iconFarM 0: a constant size).
    double iconNearM = 0.0, iconFarM = 0.0, iconFarScale = 1.0;
    /// The icon's or marker's size (px) seen from `rangeM`.
    double iconSizeAt(double rangeM) const {
        if (!(iconFarM > iconNearM)) return iconSizePx;
        const double t = std::clamp((rangeM - iconNearM) / (iconFarM - iconNearM), 0.0, 1.0);
        return iconSizePx * (1.0 + t * (iconFarScale - 1.0));
    }
    std::optional<double> extrudeM;   ///< height of an extruded polygon; none: flat
    std::string label;         ///< the text, the template filled in; empty: no label
    glm::dvec3 labelColor{1.0, 1.0, 1.0};
    double labelSizePx = 14.0;
    double minRangeM = 0.0, maxRangeM = std::numeric_limits<double>::infinity();
    /// The last rule that applied (-1: none): ties between labels of the same rank go to the
    /// later rule, the more specific one.
    int32_t rule = -1;
};

class VectorStyle {
public:
    /// Reads `style` (may be null: the defaults). `path` is its JSON pointer for messages
    /// ("/layers/2/style").
    static Result<VectorStyle> read(const nlohmann::json* style, const std::string& file, const std::string& path);

    /// Resolves field names against the layer's fields.
    Result<void> bind(std::span<const FieldInfo> fields, const std::string& layerName);

    /// The style of a feature with these attributes (one per field, as bound) and, when the
    /// source gave it one (KML), its own style: the built-in defaults, then the feature's own
    /// style, then what the scene's style names, then the rules.
    FeatureStyle evaluate(std::span<const AttributeValue> attributes, const SourceStyle* own = nullptr) const;

    /// True when the defaults or any rule (enabled or not) give a label: the layer then builds
    /// its label renderer; a style without one builds nothing for labels.
    bool namesLabel() const;

    /// True when the defaults or any rule extrude (polygons become meshes).
    bool namesExtrusion() const;

    /// How far (screen px) a stroke, marker or icon of any feature can reach past the feature,
    /// whatever its attributes (a paged drape's margin; a source's own styles aside).
    double reachPx() const;
    /// The farthest camera range (m) from which any feature can show: past it, nothing does.
    double maxRangeM() const;

    size_t ruleCount() const { return rules_.size(); }
    const std::string& ruleName(size_t i) const { return rules_[i].name; }
    bool ruleEnabled(size_t i) const { return rules_[i].enabled; }
    /// A disabled rule is skipped (a live setting: "show this rule").
    void setRuleEnabled(size_t i, bool enabled) { rules_[i].enabled = enabled; }

private:
    /// A label template's pieces: literal text, or a field (index after bind).
    struct Piece {
        std::string text;
        bool isField = false;
        size_t index = 0;
    };
    /// The properties a rule sets (the defaults: the ones the style names).
    struct Patch {
        std::optional<bool> visible, outline;
        std::optional<glm::dvec3> color, fill, labelColor;
        std::optional<glm::dvec2> dash;
        std::optional<glm::dvec3> iconScale;   ///< near, far, scale
        std::optional<double> opacity, widthPx, fillOpacity, iconSizePx, labelSizePx, minRangeM, maxRangeM;
        std::optional<std::string> icon;
        std::optional<std::vector<Piece>> label;
        std::optional<Extrusion> extrude;
        size_t extrudeIndex = 0;   ///< the extrusion's field, after bind
        bool noExtrude = false;    ///< "extrude": null
    };
    struct Condition {
        std::string field;
        size_t index = 0;                       ///< after bind
        std::vector<AttributeValue> anyOf;      ///< equality or list
        std::optional<double> min, max;         ///< a range
    };
    struct Rule {
        std::string name, path;   ///< its name ("rule 3" when unnamed) and JSON pointer
        std::vector<Condition> when;
        Patch patch;
        bool enabled = true;
        std::string layer;      ///< the source layer it applies to; empty: every layer
        bool inLayer = true;    ///< after bind: it applies to the bound layer
    };

    static Result<Patch> readPatch(const nlohmann::json& object, const std::string& file, const std::string& path,
                                   Rule* rule);
    static bool matches(const Condition& c, std::span<const AttributeValue> attributes);
    void apply(const Patch& p, std::span<const AttributeValue> attributes, FeatureStyle& s) const;

    Patch defaults_;
    std::vector<Rule> rules_;
    std::string file_, path_;
};

/// How far (screen px) a feature of this style paints past the feature: half its widest
/// stroke, marker or icon (icons up to 4:1 wide), plus room for the highlight.
double featureReachPx(const FeatureStyle& style);

/// A field value as text (labels, the feature panel): integers as they are, reals with up to
/// 6 significant digits, null as "".
std::string attributeText(const AttributeValue& value);

}  // namespace orbis::vector
