#include "ui/input/Sketch.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace orbis::ui {
namespace {

/// `lon` moved by whole turns to lie within half a turn of `from`.
double continued(double lon, double from) { return lon + 360.0 * std::round((from - lon) / 360.0); }

std::string number(double v, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, v);
    return text;
}

}  // namespace

const char* toString(SketchTool tool) {
    switch (tool) {
        case SketchTool::Point: return "point";
        case SketchTool::Path: return "path";
        case SketchTool::Polygon: return "polygon";
        case SketchTool::Box: return "box";
        case SketchTool::Sight: return "line of sight";
        case SketchTool::None: break;
    }
    return "none";
}

void Sketch::setTool(SketchTool tool) {
    if (tool == tool_) return;
    tool_ = tool;
    points_.clear();
    ++revision_;
}

void Sketch::add(const globe::Geodetic& at) {
    if (tool_ == SketchTool::None || !std::isfinite(at.lonDeg) || !std::isfinite(at.latDeg) || !std::isfinite(at.height)) return;
    const size_t keep = tool_ == SketchTool::Point ? 1 : (tool_ == SketchTool::Box || tool_ == SketchTool::Sight) ? 2 : kMaxPoints;
    if (points_.size() >= keep) {
        if (keep == kMaxPoints) return;
        points_.clear();
    }
    points_.push_back(at);
    ++revision_;
}

void Sketch::removeLast() {
    if (points_.empty()) return;
    points_.pop_back();
    ++revision_;
}

void Sketch::clear() {
    if (points_.empty()) return;
    points_.clear();
    ++revision_;
}

bool Sketch::complete() const {
    switch (tool_) {
        case SketchTool::Point: return points_.size() == 1;
        case SketchTool::Path: return points_.size() >= 2;
        case SketchTool::Polygon: return points_.size() >= 3;
        case SketchTool::Box:
            return points_.size() == 2 && points_[0].latDeg != points_[1].latDeg &&
                   continued(points_[1].lonDeg, points_[0].lonDeg) != points_[0].lonDeg;
        case SketchTool::Sight: return points_.size() == 2;
        case SketchTool::None: break;
    }
    return false;
}

std::vector<globe::LonLat> Sketch::outline() const {
    std::vector<globe::LonLat> out;
    if (points_.empty()) return out;
    if (tool_ == SketchTool::Box && points_.size() == 2) {
        const auto b = *bounds();
        // Counter-clockwise from the south-west corner.
        out = {{b.west, b.south}, {b.east, b.south}, {b.east, b.north}, {b.west, b.north}, {b.west, b.south}};
        return out;
    }
    double from = points_.front().lonDeg;
    for (const auto& p : points_) {
        from = continued(p.lonDeg, from);
        out.emplace_back(from, p.latDeg);
    }
    if (tool_ == SketchTool::Polygon && points_.size() >= 3) out.push_back(out.front());
    return out;
}

double Sketch::lengthM() const {
    if (tool_ == SketchTool::None || tool_ == SketchTool::Point) return 0.0;
    const auto line = outline();
    return globe::geodesicLength(line).metres;
}

std::vector<double> Sketch::along() const {
    const auto line = outline();
    return globe::geodesicLength(line).along;
}

std::optional<globe::PolygonMeasure> Sketch::area() const {
    if ((tool_ != SketchTool::Polygon && tool_ != SketchTool::Box) || !complete()) return std::nullopt;
    const auto ring = outline();
    return globe::geodesicPolygon(ring);
}

std::optional<globe::GeoExtent> Sketch::bounds() const {
    if (points_.empty()) return std::nullopt;
    globe::GeoExtent b{1e9, 1e9, -1e9, -1e9};
    double from = points_.front().lonDeg;
    for (const auto& p : points_) {
        const double lon = continued(p.lonDeg, from);
        if (tool_ != SketchTool::Box) from = lon;   // a path walks on; a box's corners face the first
        b.west = std::min(b.west, lon);
        b.east = std::max(b.east, lon);
        b.south = std::min(b.south, p.latDeg);
        b.north = std::max(b.north, p.latDeg);
    }
    return b;
}

std::string Sketch::geoJson() const {
    if (!complete()) return {};
    const auto coordinate = [](const globe::LonLat& p) {
        char text[96];
        std::snprintf(text, sizeof text, "[%.8f, %.8f]", p.x, p.y);
        return std::string(text);
    };
    auto line = outline();
    std::string geometry;
    if (tool_ == SketchTool::Point) {
        geometry = R"({"type": "Point", "coordinates": )" + coordinate(line.front()) + "}";
    } else if (tool_ == SketchTool::Path || tool_ == SketchTool::Sight) {
        geometry = R"({"type": "LineString", "coordinates": [)";
        for (size_t i = 0; i < line.size(); ++i) geometry += (i ? ", " : "") + coordinate(line[i]);
        geometry += "]}";
    } else {
        // Counter-clockwise (RFC 7946): the shoelace sign on the continued longitudes.
        double twice = 0.0;
        for (size_t i = 0; i + 1 < line.size(); ++i) twice += line[i].x * line[i + 1].y - line[i + 1].x * line[i].y;
        if (twice < 0.0) std::reverse(line.begin(), line.end());
        geometry = R"({"type": "Polygon", "coordinates": [[)";
        for (size_t i = 0; i < line.size(); ++i) geometry += (i ? ", " : "") + coordinate(line[i]);
        geometry += "]]}";
    }
    return std::string(R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"tool": ")") + toString(tool_) +
           R"("}, "geometry": )" + geometry + "}]}";
}

std::string formatLength(double metres) {
    if (!std::isfinite(metres)) return "?";
    if (std::abs(metres) >= 10000.0) return number(metres / 1000.0, 1) + " km";
    if (std::abs(metres) >= 1000.0) return number(metres / 1000.0, 2) + " km";
    if (std::abs(metres) >= 10.0) return number(metres, 0) + " m";
    return number(metres, 2) + " m";
}

std::string formatArea(double squareMetres) {
    if (!std::isfinite(squareMetres)) return "?";
    if (squareMetres >= 1e6) return number(squareMetres / 1e6, 2) + " km\u00b2";
    if (squareMetres >= 1e4) return number(squareMetres / 1e4, 2) + " ha";
    return number(squareMetres, 0) + " m\u00b2";
}

}  // namespace orbis::ui
