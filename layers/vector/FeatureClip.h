#pragma once
// Cutting features to the tiles of the globe's quadtree (globe/TileKey): the pieces of each
// feature inside a tile's lon/lat rectangle, so that a large source is kept as feature tiles
// and only what a view needs is loaded and drawn. No Vulkan, no GDAL.
//
// Clipping is in the lon/lat plane. Points are kept when inside; lines are cut where they cross
// the rectangle into several parts; each polygon ring is clipped on its own against the four
// edges (Sutherland-Hodgman), which keeps its signed area exact: a concave ring may come out
// with zero-width seams along the tile's edge, which triangulation drops. A part whose
// longitudes run past 180 (unwrapped across the antimeridian) is matched with the tiles on both
// sides, shifted by a whole turn. A ring around a pole is first closed through the pole (two
// corners at +-90) so that it bounds the polar cap in the lon/lat plane.

#include "globe/TileKey.h"
#include "layers/vector/VectorReader.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace orbis::vector {

/// The part of `feature` inside `extent` (attributes, fid, style kept); nothing when no part of
/// it is inside. Longitudes of the result are within the extent (shifted by whole turns).
std::optional<Feature> clipFeature(const Feature& feature, const globe::GeoExtent& extent);

/// The tiles of `level` whose extent meets the feature's bounds (wrapping across 180).
std::vector<globe::TileKey> tilesCovering(const Feature& feature, uint32_t level);

/// A ring around a pole (containsPole != 0) closed through the pole in the lon/lat plane: if its
/// last longitude differs from its first by a whole turn, two corners at the pole are added.
void closeThroughPole(std::vector<glm::dvec3>& ring, int8_t pole);

}  // namespace orbis::vector
