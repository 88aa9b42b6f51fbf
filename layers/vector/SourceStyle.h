#pragma once
// A feature's own style as its source gives it (KML's LineStyle, PolyStyle, IconStyle and
// LabelStyle, MapInfo's pens and brushes): OGR's feature style string read into plain values.
// A layer keeps each distinct style once (VectorLayer::styles); a feature points at its own.

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace orbis::vector {

struct SourceStyle {
    std::optional<glm::dvec4> lineColor;    ///< RGBA from 0 to 1 (PEN's c)
    std::optional<double> lineWidthPx;      ///< PEN's w, in pixels
    std::optional<glm::dvec4> fillColor;    ///< BRUSH's fc
    std::optional<std::string> icon;        ///< SYMBOL's id: a file or URL of the icon
    std::optional<double> iconScale;        ///< SYMBOL's s: a factor of the icon's usual size
    std::optional<glm::dvec4> iconColor;    ///< SYMBOL's c
    std::optional<glm::dvec4> labelColor;   ///< LABEL's c
    std::optional<double> labelScale;       ///< LABEL's w (stretch, %) / 100: a factor of the usual text size

    bool empty() const {
        return !lineColor && !lineWidthPx && !fillColor && !icon && !iconScale && !iconColor && !labelColor && !labelScale;
    }
};

/// Reads an OGR style string ("PEN(c:#FF0000FF,w:4px);BRUSH(fc:#00FF007F)"). Unknown tools
/// and parameters are ignored; an unreadable string gives an empty style.
SourceStyle parseOgrStyle(const std::string& styleString);

}  // namespace orbis::vector
