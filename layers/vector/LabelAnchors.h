#pragma once
// Where each feature's label stands, worked out once when the content is read (on the worker
// that read it), and how the labels rank. No Vulkan.
//
//   - a point: the point (a multi-point: its first); the label goes beside its icon;
//   - a polygon: an interior point of its largest polygon, the pole of inaccessibility (the
//     point farthest from every edge, holes included: polylabel's search over a quadtree of
//     cells), so the label sits in the thick of the shape, never in a hole or a bay. Rings are
//     taken in the lon/lat plane (x scaled by the cosine of the middle latitude) as the reader
//     unwrapped them across the antimeridian; a polygon whose outer ring winds around a pole
//     (Antarctica) is searched in a polar plane (distance from the pole, longitude), where
//     the ring closes around the pole;
//   - a line: the middle of its longest part by length, with a point a little further along
//     (the label's direction on screen) and points spread along the part (its length on
//     screen: a line label is drawn only where the line is longer than the label).
//
// Rank (labelPriority): points first, then polygons and lines by size (a polygon's square
// root of area, a line's length: bigger first), then the rule that styled them.

#include "layers/vector/VectorReader.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis::vector {

struct VectorContent;

struct LabelAnchor {
    /// Odd: the middle sample is the anchor (the labels follow the line's bends through them).
    static constexpr size_t kPathSamples = 65;

    bool valid = false;                 ///< false: no geometry to label (an empty feature)
    GeometryKind kind = GeometryKind::Points;
    glm::dvec2 lonLat{0.0};             ///< degrees; the longitude may lie outside [-180, 180]
    double sizeM = 0.0;                 ///< a polygon's sqrt(area), a line's length (m); 0 for points
    /// Lines: a point 0.001 degrees further along the line than the anchor.
    glm::dvec2 ahead{0.0};
    /// Lines: kPathSamples points along the labelled part, evenly by length, both ends included.
    std::vector<glm::dvec2> path;
};

/// One anchor per feature, layer by layer, in the content's order.
using ContentAnchors = std::vector<std::vector<LabelAnchor>>;

LabelAnchor labelAnchor(const Feature& feature);
ContentAnchors labelAnchors(const VectorContent& content);

/// The pole of inaccessibility of one polygon in a plane: `rings[0]` is the outer ring, the rest
/// its holes (closed or not). Within `precision` of the best point, and at most `maxCells`
/// cells evaluated (each costs a pass over every edge). A degenerate polygon gives its first
/// vertex.
glm::dvec2 poleOfInaccessibility(std::span<const std::vector<glm::dvec2>> rings, double precision, int maxCells = 4096);

/// The signed distance from `p` to the polygon's edges: positive inside (inside the outer
/// ring and outside every hole, by the even-odd rule), negative outside.
double signedDistanceToPolygon(glm::dvec2 p, std::span<const std::vector<glm::dvec2>> rings);

/// The label's rank for LabelPlacer (larger first): the kind, then the size in steps of 1/16
/// octave, then the rule (later first, -1 the defaults). Each tier outweighs the next.
double labelPriority(GeometryKind kind, double sizeM, int32_t rule);

}  // namespace orbis::vector
