#pragma once
// The scripted UAV flight of the FMV fixtures (`orbis-make-fmv`, tests): a known terrain, a
// platform circling a target, its sensor tracking the target, so that tests know where every
// corner of every frame must land. CPU only.
//
// Terrain (heights above the WGS84 ellipsoid, metres), over lon 9.00..9.06, lat 46.00..46.04:
//   h = 600 + 80 sin(x / 400) cos(y / 300) + a ridge 500 m high (a Gaussian of sigma 80 m across,
//       running north-south 900 m east of the target)
// with x, y metres east and north of the target (lon 9.03, lat 46.02).
//
// Flight: a circle of radius 1800 m around the target at 1500 m above the ellipsoid,
// counter-clockwise seen from above, one lap in 240 s, starting due west of the target (flying
// south); pitch 2 degrees nose up, roll 0. The sensor points at the target; field of view
// 24 x 18 degrees; its relative roll 0. From about 90 s to 150 s the platform is east of the
// target and the ridge hides the target from it (every ray of the view ends on the ridge's
// east face): the occlusion case.

#include "layers/fmv/SensorModel.h"
#include "formats/fmv/St0601.h"

#include <cstdint>

namespace orbis::fmv {

struct SyntheticFlight {
    static constexpr double kTargetLon = 9.03, kTargetLat = 46.02;
    static constexpr double kWest = 9.0, kEast = 9.06, kSouth = 46.0, kNorth = 46.04;
    static constexpr double kRadius = 1800.0, kHeight = 1500.0, kLapSeconds = 240.0;
    static constexpr double kHfov = 24.0, kVfov = 18.0;
    /// 2026-06-21T09:00:00Z in µs since 1970 (the precision time stamp of frame 0).
    static constexpr uint64_t kStartUs = 1782032400ull * 1000000ull;

    /// Terrain height above the ellipsoid.
    static double height(double lonDeg, double latDeg);
    static TerrainHeights terrain();
    /// The sensor's pose `seconds` after the start.
    static SensorPose pose(double seconds);
    /// The ST 0601 packet for that moment: time stamp, platform and sensor angles, position
    /// (ellipsoid height, tag 75, and true altitude, tag 15, equal: the fixture has no geoid),
    /// field of view, slant range, frame centre and the four full-precision corners on the
    /// terrain (from SensorModel against the analytic terrain).
    static St0601Packet packet(double seconds);
};

}  // namespace orbis::fmv
