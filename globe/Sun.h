#pragma once
// Where the Sun is, for lighting the globe at the scene time. Low precision on purpose: about
// 0.01 degrees, far finer than a shading terminator needs, with no ephemeris files. No Vulkan.
//
// All functions are pure and thread-safe.

#include "base/TimeFormat.h"

#include <glm/glm.hpp>

namespace orbis::globe {

/// The Sun's apparent position in the equatorial frame of date.
struct SunEquatorial {
    double rightAscensionDeg = 0.0;  ///< [0, 360)
    double declinationDeg = 0.0;     ///< [-90, 90]
    double distanceAu = 1.0;
};

/// Low-precision solar coordinates of the Astronomical Almanac (section C, "Low precision
/// formulas for the Sun"): about 0.01 degrees between 1950 and 2050.
SunEquatorial sunEquatorial(TimeNs t);

/// Greenwich mean sidereal time in degrees, [0, 360), from the IAU 1982 expression (Aoki et al.
/// 1982) with UT1 taken as UTC (|UT1 - UTC| < 0.9 s, i.e. < 0.004 degrees).
double greenwichMeanSiderealTimeDeg(TimeNs t);

/// Unit vector from the Earth's centre toward the Sun, in ECEF (WGS84 Earth-fixed: x through
/// lon 0 / lat 0, z through the North Pole).
glm::dvec3 sunDirectionEcef(TimeNs t);

/// The point where the Sun is at the zenith (geocentric): x = longitude in [-180, 180),
/// y = latitude (the declination), both in degrees.
glm::dvec2 subsolarPointDeg(TimeNs t);

}  // namespace orbis::globe
