#pragma once
// Geoid heights (EGM96) through PROJ, for altitudes given above mean sea level: ST 0601's true
// altitude, GPX elevations, NMEA GGA altitudes, trajectory CSVs in metres MSL. Debian's proj-data
// carries the grid (us_nga_egm96_15.tif).

#include <functional>

namespace orbis::globe {

/// The geoid's height above the WGS84 ellipsoid at (lon, lat), metres.
using GeoidHeightFn = std::function<double(double lonDeg, double latDeg)>;

/// EGM96 through OGR (EPSG:4326+5773 -> EPSG:4979), or an empty function when PROJ has no grid
/// (then callers take MSL altitudes as ellipsoid heights and say so). The function returned is
/// not thread-safe (one PROJ transformation): give each thread its own.
GeoidHeightFn egm96Geoid();

}  // namespace orbis::globe
