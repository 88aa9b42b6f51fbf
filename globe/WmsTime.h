#pragma once
// The TIME dimension of a WMS layer (WMS 1.3.0 Annex C, as `orbis info URL` prints it from the
// capabilities): the values a server has, so that a layer follows the scene's virtual time by
// asking for the value in effect (TIME=...). No Vulkan, no GDAL.
//
//   auto values = parseWmsTimeExtent("2026-01-01/2026-03-01/P1M");   // 3 values
//   const WmsTimeValue& v = (*values)[wmsTimeIndexAt(*values, sceneTime)];
//   url += "&TIME=" + v.text;

#include "base/Result.h"
#include "base/TimeFormat.h"

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::globe {

struct WmsTimeValue {
    std::string text;   ///< as the server spells it (what TIME= sends)
    TimeNs at = 0;      ///< the instant it starts
    bool operator==(const WmsTimeValue&) const = default;
};

/// Most values one extent may expand to (a period of seconds over years is a mistake).
inline constexpr size_t kMaxWmsTimeValues = 100000;

/// The values of an extent: a comma-separated list of instants ("2026-01-01", "2026-01-01T06:00Z")
/// and intervals "start/end/period" with an ISO 8601 period (P1M, P1D, PT6H, P1Y2M10DT2H30M),
/// expanded from the start by whole periods up to the end (months and years by the calendar, the
/// day of the month kept, or the month's last day when it is shorter). Values are sorted and
/// unique; generated ones are written in the start's form (a date, or a full UTC instant).
/// Errors quote the part that is wrong: a bad instant or period, an end before the start, an
/// interval without a period, more than kMaxWmsTimeValues values, nothing at all.
Result<std::vector<WmsTimeValue>> parseWmsTimeExtent(std::string_view extent);

/// The value in effect at `t`: the last that starts at or before `t`, else the first (`values`
/// sorted, not empty).
size_t wmsTimeIndexAt(std::span<const WmsTimeValue> values, TimeNs t);

}  // namespace orbis::globe
