#pragma once
// What a vector layer shows, on the CPU: the features read from the source (every layer it
// names), each feature's resolved style, and when each is shown on the scene's clock. Read
// once on a worker; then shared, read-only, by the threads that paint the terrain's tiles
// (VectorDrape). A restyle (a rule switched off) makes new styles and keeps the features. No
// Vulkan.

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "layers/vector/FeatureTime.h"
#include "layers/vector/VectorReader.h"
#include "layers/vector/VectorStyle.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::jobs {
class CancelToken;
}

namespace orbis::vector {

struct VectorContentOptions {
    VectorReadOptions read;
    VectorStyle style;            ///< as read from the scene; bound to each layer's fields on load
    FeatureTimeFields timeFields;
};

/// One source layer's features and their times.
struct ContentLayer {
    VectorLayer data;
    VectorStyle style;            ///< bound to this layer's fields
    FeatureTimes times;
};

struct VectorContent {
    std::string source;
    std::vector<ContentLayer> layers;
    uint64_t featureCount = 0, vertexCount = 0;
    /// Warnings from reading (skipped features, times that are not times), layer by layer.
    std::vector<std::string> warnings;
    /// The span of the features' times, when any feature has one.
    std::optional<TimeNs> firstTime, lastTime;
    /// Approximate bytes held (features, coordinates, attributes).
    uint64_t bytes = 0;
};

/// Each feature's style, per layer, in feature order.
using ContentStyles = std::vector<std::vector<FeatureStyle>>;

/// About the bytes a feature holds (coordinates, indices, attributes and their text).
uint64_t featureBytes(const Feature& feature);

/// Reads the source and binds the style to each layer's fields. Errors name the source, and
/// the layer and the rule or field where one is wrong.
Result<std::shared_ptr<VectorContent>> loadVectorContent(const VectorContentOptions& options);

/// The second half of loadVectorContent, for features already read (and perhaps clipped: a
/// feature tile's): the style bound to each layer's fields, the times worked out.
Result<std::shared_ptr<VectorContent>> contentFromData(VectorData data, const VectorContentOptions& options);

/// Every feature's style from its layer's bound style (and its own, a KML's).
ContentStyles styleContent(const VectorContent& content);

/// A number that changes whenever the set of features shown at `t` changes (the same number
/// at every time for content without times).
uint64_t shownAtSignature(const VectorContent& content, TimeNs t);

}  // namespace orbis::vector
