#pragma once
// Which feature of a vector layer's content lies under a point of the ground: the click in the
// viewer, turned into a lon/lat by the ground pick, asks this. Markers first, then lines, then
// polygons (the reverse of the paint order, so what is drawn on top wins), each in the order
// it is painted, the last drawn first. No Vulkan.

#include "base/TimeFormat.h"
#include "layers/vector/VectorContent.h"

#include <cstddef>
#include <optional>

namespace orbis::vector {

struct PickQuery {
    double lonDeg = 0.0, latDeg = 0.0;
    /// Ground metres per screen pixel at the point: line widths, marker sizes and the slop are
    /// in pixels.
    double metresPerPixel = 1.0;
    double slopPx = 3.0;
    TimeNs time = 0;   ///< features not shown at this time are not picked
};

struct PickedFeature {
    size_t layer = 0;     ///< in VectorContent::layers
    size_t feature = 0;   ///< in that layer's features
};

/// The feature drawn at the query's point, if any: a marker within its radius plus the slop, a
/// line within half its width plus the slop, a polygon containing the point (holes excluded;
/// across the antimeridian and around the poles). Hidden features are not picked.
std::optional<PickedFeature> pickFeature(const VectorContent& content, const ContentStyles& styles, const PickQuery& query);

}  // namespace orbis::vector
