#pragma once
// One live setting of a layer: what the viewer's panel shows, what live edits and benchmark
// sweeps set by name, and where a saved scene writes it. No Vulkan.

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace orbis::scene {

struct LayerSetting {
    enum class Kind {
        Number,    ///< LiveSettings::setParameter(name, value), value in [min, max]
        Integer,   ///< the same, whole numbers
        Toggle,    ///< setParameter(name, 0 or 1); written to the scene as true/false
        Choice,    ///< setOption(name, one of choices)
        Curve,     ///< setCurve(name, points): piecewise linear, x over [min, max], y in 0..1
    };
    /// The name setParameter/setOption/setCurve take ("steps", "isovalue1", "imageryOpacity0").
    std::string name;
    std::string label;         ///< for the panel ("Screen-space error (px)")
    Kind kind = Kind::Number;
    double value = 0.0;        ///< Number, Integer, Toggle
    double min = 0.0, max = 1.0;
    bool logarithmic = false;  ///< a slider over orders of magnitude (budgets, errors)
    std::string choice;        ///< Choice: the current one
    std::vector<std::string> choices;
    std::vector<glm::dvec2> points;   ///< Curve: its control points, sorted by x
    std::vector<glm::vec3> gradient;  ///< Curve: linear RGB along [min, max] to draw behind it
    /// Where the setting lives in the layer's object of a scene file, as a JSON pointer
    /// (RFC 6901): "/steps", "/range/0", "/slices/1/lat", "/imagery/0/opacity". Empty: "/" + name.
    /// Loading the saved file gives the layer this value back (tests/unit/SettingPointerTest).
    std::string pointer;

    /// The pointer, or "/" + name when none is given.
    std::string jsonPointer() const { return pointer.empty() ? "/" + name : pointer; }
};

/// A numeric setting's fixed description, written once and used by the scene reader (the
/// range a file may give), by setParameter (the range a live edit may set) and by the panel.
struct SettingRange {
    double min = 0.0, max = 1.0;
    bool contains(double v) const { return v >= min && v <= max; }   // false for NaN
    double clamp(double v) const { return v < min ? min : v > max ? max : v; }
};

}  // namespace orbis::scene
