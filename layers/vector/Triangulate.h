#pragma once
// Triangles of a polygon with holes, in a plane (the caller projects lon/lat first: a local
// tangent plane, or a polar projection for a ring around a pole), for filled polygons and the
// roofs of extruded ones. No Vulkan.
//
// Ear clipping on a linked ring: each hole is joined to the outer ring by a bridge to a vertex
// it can see, then ears are cut. Only reflex vertices can lie in an ear, so they are kept in
// a uniform grid and an ear test looks at the grid cells its box covers: close to O(n) for the
// polygons of real data instead of O(n^2). Repeated and collinear points are dropped. A ring
// with no clean ear left (a self-intersecting polygon) has one ear cut without the containment
// test and the search goes on; past a work budget (8 ear tests a point) every remaining ear is
// cut that way. So bad input gives overlapping triangles, counted in the stats, never a hang.

#include "base/Result.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace orbis::vector {

struct TriangulateStats {
    size_t clean = 0;    ///< ears cut with every test passed
    size_t forced = 0;   ///< ears cut in a ring that had no clean ear (self-intersecting input)
};

/// The triangles (indices into `points`, counter-clockwise) of the polygon whose rings start at
/// `ringStarts` (the first ring is the outer one, the rest holes; each ring runs to the next
/// start or the end, not closed: the last point is not the first again). Either orientation is
/// accepted for any ring. Errors: more than `maxPoints` points, a ring start out of order or out
/// of range, a point that is not finite.
Result<std::vector<uint32_t>> triangulate(std::span<const glm::dvec2> points, std::span<const uint32_t> ringStarts,
                                          size_t maxPoints, TriangulateStats* stats = nullptr);

/// Twice the signed area of a ring (counter-clockwise positive).
double ringArea2(std::span<const glm::dvec2> ring);

}  // namespace orbis::vector
