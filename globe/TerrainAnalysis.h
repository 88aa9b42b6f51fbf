#pragma once
// Terrain analysis on the CPU: the profile of the ground along a path and the line of sight
// between two points. The ground is a height function (metres above the ellipsoid at a lon/lat;
// none where unknown): for analysis, the finest DEM data (a RasterSource read at its own
// resolution), not the tiles the view has streamed. No Vulkan, no GDAL.
//
// The sight line is the straight segment between the two points in ECEF (the Earth's curve is
// in the geometry), raised by refraction: the ray bends with a radius of R / k, so a point d1
// from one end and d2 from the other sees it k d1 d2 / (2 R) higher (k = 1/7, the usual
// coefficient, is gdal_viewshed's default 1 - 0.85714; 0: geometric).

#include "globe/Ellipsoid.h"
#include "globe/Geodesic.h"

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace orbis::globe {

using HeightAt = std::function<std::optional<double>(double lonDeg, double latDeg)>;

struct ProfileSample {
    double distanceM = 0.0;     ///< along the path from its start
    LonLat at{0.0};
    std::optional<double> height;   ///< the ground; none where the data has none
};

struct TerrainProfile {
    std::vector<ProfileSample> samples;
    double lengthM = 0.0;
    std::optional<double> minHeight, maxHeight;
    double ascentM = 0.0, descentM = 0.0;   ///< summed rises and falls between known samples
    size_t unknown = 0;                     ///< samples without ground
};

/// The ground along a path of geodesics, every `stepM` at most (each vertex sampled too), at
/// most `maxSamples` in all (the step grows to fit).
TerrainProfile terrainProfile(std::span<const LonLat> path, const HeightAt& ground, double stepM, size_t maxSamples = 100000);

struct SightOptions {
    double stepM = 5.0;           ///< along the line (about the DEM's pixel size)
    double refraction = 1.0 / 7.0;
    size_t maxSamples = 200000;   ///< the step grows to fit
};

struct LineOfSight {
    bool visible = true;
    /// The first place where the ground rises above the line (when not visible): its distance
    /// from the observer along the ground, where, the ground's height and how far above the
    /// line it is there.
    double blockedAtM = 0.0;
    LonLat blockedAt{0.0};
    double blockingHeight = 0.0, aboveLineM = 0.0;
    /// The largest rise of the ground above the line, and the smallest clearance below it
    /// (negative when blocked).
    double clearanceM = 0.0;
    double distanceM = 0.0;   ///< observer to target, straight
    size_t samples = 0, unknown = 0;
};

/// Whether `target` is seen from `observer` (heights above the ellipsoid) over `ground`. The
/// last and first metre are not tested (the ground a point stands on does not hide it).
LineOfSight lineOfSight(const Geodetic& observer, const Geodetic& target, const HeightAt& ground, const SightOptions& options = {});

}  // namespace orbis::globe
