#pragma once
// Fewer vertices for features seen from afar: Douglas-Peucker in the lon/lat plane, with a
// tolerance in degrees (a tile's texel: its size in degrees over its pixels). Every dropped
// vertex lies within the tolerance of the simplified line; endpoints stay; a ring keeps at
// least a triangle, and a ring that would fold below that is dropped (a polygon whose outer
// ring goes, goes with its holes). No Vulkan, no GDAL.

#include "layers/vector/VectorReader.h"

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <vector>

namespace orbis::vector {

/// The vertices of `part` to keep (indices into it, in order) for `toleranceDeg`. A ring (the
/// first vertex repeated last or not) keeps at least 3 distinct vertices, else nothing.
std::vector<uint32_t> simplifyPart(std::span<const glm::dvec3> part, double toleranceDeg, bool ring);

/// The feature with every part simplified; nothing when no part survives.
std::optional<Feature> simplifyFeature(const Feature& feature, double toleranceDeg);

}  // namespace orbis::vector
