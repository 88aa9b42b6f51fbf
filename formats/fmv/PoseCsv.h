#pragma once
// Per-frame sensor pose from a CSV sidecar, the export format of older FMV tools: one header
// line of column names, then one line per frame. Each row becomes an St0601Packet with the
// fields its columns give, so the FMV layer reads KLV and CSV poses the same way.
//
// Separator: ',', ';' or tab (whichever the header line has most of). Lines that are blank or
// start with '#' are skipped; a field may be in double quotes. Empty cells and NaN, NA, null,
// none, "-" are "no value". Column names are matched without regard to case, spaces, '_', '-',
// '.', brackets and slashes, so "Sensor Latitude (deg)", "sensor_lat" and "SensorLat" are one.
// Accepted names (a trailing unit may be added: deg/degrees, rad/radians (converted), m/meters/
// metres, ft/feet (converted); for time: s/sec/seconds, ms, us/usec/microseconds):
//
//   time        time, timestamp, t, utc, datetime, date time, unix time, epoch, precision time stamp
//   latitude    lat, latitude, sensor lat, sensor latitude, platform lat(itude)
//   longitude   lon, long, lng, longitude, sensor lon/long/longitude, platform lon(gitude)
//   altitude    alt, altitude, alt msl, sensor alt(itude), sensor true altitude        (m above MSL)
//   height      hae, height, ellipsoid height, sensor hae/height, sensor ellipsoid height (m above WGS84)
//   heading     heading, yaw, platform heading (angle), platform yaw
//   pitch       pitch, platform pitch (angle)
//   roll        roll, bank, platform roll (angle)
//   sensor az   sensor relative azimuth (angle), sensor rel az, rel az, relative azimuth, sensor az(imuth), gimbal pan, pan
//   sensor el   sensor relative elevation (angle), sensor rel el, rel el, relative elevation, sensor el(evation), gimbal tilt, tilt
//   sensor roll sensor relative roll (angle), sensor rel roll, rel roll, relative roll, sensor roll, gimbal roll
//   hfov        hfov, horizontal fov, sensor hfov, sensor horizontal fov, fov h, fov x, (sensor) horizontal field of view
//   vfov        vfov, vertical fov, sensor vfov, sensor vertical fov, fov v, fov y, (sensor) vertical field of view
//   others      frame center lat/lon/elevation (centre too), slant range, target width
//
// Time: ISO 8601 text (2009-01-12T22:08:22.5Z), or a number whose unit the column name gives;
// without one, a number of at least 1e14 is µs since 1970 (ST 0601's unit), at least 1e11 ms,
// else seconds (since 1970, or since the start of the video: relative times then fall on
// 1970-01-01, and the FMV layer maps video time onto scene time anyway). Pitch and roll go to
// the full-range fields (tags 90, 91) since a CSV knows no ±20°/±50° limits.
// Required columns: time, latitude, longitude, and altitude or height. Other columns are
// ignored (and listed).

#include "base/Result.h"
#include "formats/fmv/St0601.h"

#include <string>
#include <string_view>
#include <vector>

namespace orbis::fmv {

/// Largest pose CSV read (it is read whole; each row becomes a ~1 kB packet).
inline constexpr uint64_t kMaxPoseCsvBytes = uint64_t(64) << 20;

struct PoseSample {
    std::size_t line = 0;   ///< 1-based line in the file
    St0601Packet pose;      ///< the fields the columns give; checksum Missing, no warnings
};

struct PoseCsv {
    std::vector<PoseSample> samples;      ///< in file order
    std::vector<std::string> columns;     ///< per column: the field name it feeds (st0601TagName), or "" if ignored
    std::vector<std::string> ignored;     ///< header names of the ignored columns
    std::string timeUnit;                 ///< "iso8601", "s", "ms" or "us"
};

/// Parses CSV text; `name` (the file) starts every message. Errors: no header, a required column
/// missing (the message lists the names accepted), two columns for one field, a value that is
/// not a number or not a time ("name: line 12, column 3 (lat): 'abc' is not a number"), a row
/// with more cells than the header, a time before 1970.
Result<PoseCsv> parsePoseCsv(std::string_view text, const std::string& name);

/// Reads and parses `path` (errors name it; files over kMaxPoseCsvBytes are refused).
Result<PoseCsv> readPoseCsv(const std::string& path);

/// True when the first non-comment line of `path` is a header parsePoseCsv would accept.
bool looksLikePoseCsv(const std::string& path);

}  // namespace orbis::fmv
