#pragma once
// Longitudes on a circle: unwrapping lines and rings across the antimeridian, rings that wind
// around a pole, and the shortest longitude interval covering several boxes. Pure arithmetic,
// no GDAL; the vector reader's geometry rules live here so they are tested on their own.

#include "layers/vector/VectorReader.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace orbis::vector {

/// `lonDeg` moved by whole turns into [-180, 180).
double normalizeLonDeg(double lonDeg);

/// Makes a line's or ring's longitudes continuous: the first is moved into [-180, 180], each
/// next one by whole turns so that it differs from its predecessor by at most 180 degrees.
void unwrapLongitudes(std::span<glm::dvec3> part);

/// The middle of an unwrapped part's longitude range.
double lonMidpoint(std::span<const glm::dvec3> part);

/// Moves an unwrapped part by whole turns so that its first longitude is within 180 degrees of
/// `lonDeg`: a hole unwrapped on its own lands next to its outer ring (a polygon across 180 whose
/// hole lies at -179.5 gets the hole at 180.5).
void moveNextTo(std::span<glm::dvec3> part, double lonDeg);

/// For an unwrapped ring: +1 when it winds once around the North Pole, -1 around the South
/// Pole, 0 when it does not (its longitude, closed back to the start, changes by 0, not 360).
/// Which pole: the one a vertex touches (|lat| = 90), else the side of the equator its mean
/// latitude is on. A ring around a pole cannot say by itself which side it encloses; real data
/// (Antarctica in Natural Earth) runs along the pole, and a cap's ring lies near its pole.
int8_t ringPoleWinding(std::span<const glm::dvec3> ring);

/// The box of one unwrapped part: every longitude when the part spans a whole turn.
LonLatBounds partBounds(std::span<const glm::dvec3> part);

/// The box of a ring around a pole: every longitude, from the pole to the ring's far latitude.
LonLatBounds poleCapBounds(std::span<const glm::dvec3> ring, int8_t pole);

/// The smallest box covering all `boxes` (empty ones ignored): latitudes from the lowest to the
/// highest, longitudes the shortest interval on the circle that covers every box's interval
/// (the complement of the widest gap between them).
LonLatBounds coverBounds(std::span<const LonLatBounds> boxes);

/// Squared distance from p to the segment ab, in the plane the points are given in.
double segmentDistance2(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b);

}  // namespace orbis::vector
