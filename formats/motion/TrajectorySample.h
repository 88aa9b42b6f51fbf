#pragma once
// One time-stamped 6-DOF sample of a vehicle's trajectory, as the readers (CSV, GPX, KLV) give
// it. Angles follow Attitude.h (ST 0601: heading clockwise from north, pitch nose up, roll right
// wing down). Pure data: no Vulkan, no I/O.

#include "base/TimeFormat.h"

#include <cstddef>
#include <optional>

namespace orbis::motion {

/// What a sample's altitude is measured from.
enum class AltitudeRef {
    Ellipsoid,      ///< the WGS84 ellipsoid (GPS "height above ellipsoid", HAE)
    MeanSeaLevel,   ///< the geoid (orthometric height, "MSL"): needs a geoid model, see TrajectoryOptions
    Ground,         ///< the terrain under the sample ("AGL"); 0 = on the ground
};

/// "ellipsoid", "mean sea level", "ground".
const char* toString(AltitudeRef ref);

struct TrajectorySample {
    TimeNs t = 0;
    double lonDeg = 0.0, latDeg = 0.0;
    double alt = 0.0;   ///< metres above `altRef`
    AltitudeRef altRef = AltitudeRef::Ellipsoid;
    /// Attitude (Attitude.h). An absent angle is derived by the Trajectory from the motion:
    /// heading from the course over ground, pitch from the climb angle, roll 0.
    std::optional<double> headingDeg, pitchDeg, rollDeg;
    std::size_t line = 0;   ///< 1-based line (or record) of the source, for messages; 0 when none
};

}  // namespace orbis::motion
