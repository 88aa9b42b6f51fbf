#pragma once
// When each feature of a layer is shown on the scene's clock: from a begin and an end time
// (KML's TimeSpan), from a single time on (KML's TimeStamp), or always. The times come from the
// layer's fields: the ones the scene names, else KML's own ("timestamp", "begin", "end", as
// OGR's KML drivers expose them). No Vulkan, no GDAL.

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "layers/vector/VectorReader.h"

#include <optional>
#include <string>
#include <vector>

namespace orbis::vector {

/// Shown while begin <= t < end; a missing bound is open.
struct FeatureTimeSpan {
    std::optional<TimeNs> begin, end;
    bool hidden = false;   ///< a time that could not be read: never shown

    bool shows(TimeNs t) const { return !hidden && (!begin || t >= *begin) && (!end || t < *end); }
    bool always() const { return !hidden && !begin && !end; }
};

/// The fields that hold the times. Both empty: KML's, when the layer has them ("begin" and "end"
/// of a TimeSpan, else "timestamp" of a TimeStamp, feature by feature); else none.
struct FeatureTimeFields {
    std::string begin;   ///< e.g. "date", or KML's "timestamp" / "begin"
    std::string end;     ///< optional
};

struct FeatureTimes {
    std::vector<FeatureTimeSpan> spans;   ///< one per feature; empty when the layer has no times
    std::vector<std::string> warnings;    ///< a value that is not a time (the feature is hidden), at most 20
    std::optional<TimeNs> first, last;    ///< the earliest begin and the latest end or begin

    bool timed() const { return !spans.empty(); }
};

/// The layer's features' spans. A field the scene names that the layer lacks is an error naming
/// the field and the layer's fields. A value may be an ISO 8601 text (what the reader gives for
/// Date and DateTime fields) or a number of seconds since 1970 (Unix time, a number or text that
/// is one); null leaves that bound open. A TimeStamp shows its feature from that time on.
Result<FeatureTimes> featureTimes(const VectorLayer& layer, const FeatureTimeFields& fields);

}  // namespace orbis::vector
