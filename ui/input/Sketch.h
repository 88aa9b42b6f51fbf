#pragma once
// The viewer's drawing tools: a point, a path, a polygon, a box (two corners) or a line of sight
// (two points) drawn by clicks on the globe, with their geodesic measures (GeographicLib through
// globe/Geodesic.h), their bounds and their GeoJSON: what the Measure panel shows and what the
// Processes panel's geometry inputs take. No window library, no ImGui, no Vulkan. Main thread.

#include "globe/Ellipsoid.h"
#include "globe/Geodesic.h"
#include "globe/TileKey.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace orbis::ui {

enum class SketchTool { None, Point, Path, Polygon, Box, Sight };
const char* toString(SketchTool tool);

class Sketch {
public:
    SketchTool tool() const { return tool_; }
    /// Another tool starts an empty sketch; the same one keeps it.
    void setTool(SketchTool tool);
    /// A click on the ground: a point replaces the point; a box and a line of sight keep two (a
    /// third click starts again from it); a path and a polygon grow (at most kMaxPoints).
    /// Nothing with no tool.
    void add(const globe::Geodetic& at);
    void removeLast();
    void clear();
    const std::vector<globe::Geodetic>& points() const { return points_; }
    /// Enough points for its kind: 1 point, 2 for a path, a box or a sight, 3 for a polygon.
    bool complete() const;
    /// Changes with every edit (the panels compute profiles and sight lines again on it).
    uint64_t revision() const { return revision_; }

    /// The vertices as drawn, in order: a box's four corners; a polygon's and a box's ring
    /// closed (the first again at the end).
    std::vector<globe::LonLat> outline() const;
    /// Geodesic length: along a path or a sight, round a polygon or a box; 0 otherwise.
    double lengthM() const;
    /// Distance from the first vertex to each vertex of the outline.
    std::vector<double> along() const;
    /// Polygons and boxes: geodesic area and perimeter.
    std::optional<globe::PolygonMeasure> area() const;
    /// West, south, east, north of the points (a box: its corners), longitudes continued across
    /// the antimeridian from the first point's (east may pass 180). Nothing without points.
    std::optional<globe::GeoExtent> bounds() const;
    /// A GeoJSON FeatureCollection of one feature (EPSG:4326, lon lat): a Point, a LineString
    /// (path, sight) or a Polygon (polygon, box; the ring closed, counter-clockwise). Empty
    /// while incomplete.
    std::string geoJson() const;

    static constexpr size_t kMaxPoints = 10000;

private:
    SketchTool tool_ = SketchTool::None;
    std::vector<globe::Geodetic> points_;
    uint64_t revision_ = 0;
};

/// "850 m", "12.40 km", "0.25 m".
std::string formatLength(double metres);
/// "420 m²", "3.20 ha", "12.50 km²".
std::string formatArea(double squareMetres);

}  // namespace orbis::ui
