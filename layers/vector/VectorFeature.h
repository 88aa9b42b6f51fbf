#pragma once
// One OGR feature to Orbis's Feature (internal to layers/vector): the geometry flattened into
// parts of one kind, transformed to WGS84 lon/lat, unwrapped across the antimeridian, with pole
// rings flagged and bounds; the attributes typed.

#include "layers/vector/VectorReader.h"

#include <ogrsf_frmts.h>

#include <cstdint>
#include <string>
#include <vector>

namespace orbis::vector::detail {

/// A converted feature: one Feature per geometry kind it holds (usually one; none for a feature
/// without geometry), or the reason it was skipped.
struct ConvertedFeature {
    std::vector<Feature> features;
    std::string skipped;   ///< empty when the feature was read
};

/// `transform` null: the coordinates are lon/lat already. A feature with more than
/// `maxVertices` vertices is skipped before its coordinates are copied.
ConvertedFeature convertFeature(const OGRFeature& feature, OGRCoordinateTransformation* transform,
                                uint64_t maxVertices);

/// The layer's fields with OGR's type names.
std::vector<FieldInfo> readFields(const OGRFeatureDefn& definition);

/// One value per field: integers, reals, text, ISO 8601 dates and times, null.
std::vector<AttributeValue> readAttributes(const OGRFeature& feature);

}  // namespace orbis::vector::detail
