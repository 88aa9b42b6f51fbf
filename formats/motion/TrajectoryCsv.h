#pragma once
// Trajectory samples from a CSV file: one header line of column names, then one line per
// sample (time, lon, lat, alt, heading/yaw, pitch, roll). CPU only.
//
// Separator: ',', ';' or tab (whichever the header line has most of); with ';' a decimal comma
// is accepted (45,5). Lines that are blank or start with '#' are skipped; a field may be in
// double quotes. A UTF-8 byte order mark is skipped. Column names are matched without regard to
// case, spaces, '_', '-', '.', brackets and slashes ("Heading (deg)", "heading_deg" and
// "HeadingDeg" are one), as in formats/fmv/PoseCsv.h. Accepted names:
//
//   time       time, timestamp, t, utc, datetime, unix time, epoch, time utc, precision time stamp
//   latitude   lat, latitude, sensor/platform lat(itude)
//   longitude  lon, long, lng, longitude, sensor/platform lon(g)(itude)
//   altitude   above the ellipsoid:    hae, alt hae, altitude hae, height, ellipsoid(al) height,
//                                      height ellipsoid, height above ellipsoid, alt/altitude/height
//                                      wgs84, sensor hae, sensor ellipsoid height
//              above mean sea level:   alt msl, altitude msl, msl, height msl, elevation msl, alt asl,
//                                      altitude asl, asl, height asl, orthometric height, (sensor)
//                                      true altitude
//              above the ground:       agl, alt agl, altitude agl, height agl, height above ground,
//                                      altitude above ground, alt above ground, above ground
//              unspecified:            alt, altitude, elevation, ele, elev, sensor alt(itude):
//                                      CsvOptions::altitudeRef says
//   heading    heading, yaw, hdg, true heading, heading true, heading/yaw angle, platform heading
//              (angle), platform yaw (angle)
//   pitch      pitch, pitch angle, platform pitch (angle)
//   roll       roll, bank, roll/bank angle, platform roll (angle)
//
// Units: a suffix on the name. Angles deg/degree(s) (the default) or rad/radian(s), for
// latitude and longitude too; lengths m/meter(s)/metre(s) (the default), ft/feet, km; time
// s/sec/secs/seconds, ms/msec/milliseconds, us/usec/microseconds, ns/nsec/nanoseconds.
// Time cells: ISO 8601 text (2024-05-01T12:00:00.25Z; parseIso8601's forms), or a number in the
// column's unit; without one, the first number decides: at least 1e17 is ns, 1e14 us, 1e11 ms,
// else seconds. Numbers are seconds (etc.) since 1970, plus CsvOptions::timeOffset (for times
// relative to a start). Decimal times are read exactly to the nanosecond (no double rounding).
//
// Several altitude columns: the ellipsoid height wins, then mean sea level, then unspecified,
// then above ground; the others are ignored (listed in `ignored`). No altitude column: every
// sample is on the ground (Ground, 0). Other columns are ignored and listed.
//
// Values. Empty cells and NaN, NA, N/A, null, none, "-" are "no value": for an angle it is
// absent (the Trajectory derives it from the motion); for time, latitude, longitude or altitude
// it is an error naming the line and column (a sample needs a place and a time).
//
// Errors (each names the file, and the line and column where there is one): no header, a
// required column missing (time, latitude, longitude; the message lists the names accepted), two
// columns for one value, a value that is not a number or not a time ("track.csv: line 12,
// column 3 (lat): 'abc' is not a number"), a row with more cells than the header, no data rows,
// a file over kMaxTrajectoryCsvBytes or that cannot be read. Times out of order and repeated
// times are not checked here but by Trajectory::create, whose messages name the lines too.

#include "base/Result.h"
#include "formats/motion/TrajectorySample.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::motion {

/// Largest trajectory CSV read (it is read whole; a sample takes ~100 bytes in memory, about as
/// much as its line).
inline constexpr uint64_t kMaxTrajectoryCsvBytes = uint64_t(256) << 20;

struct CsvOptions {
    /// For an altitude column whose name does not say what it is above (alt, altitude,
    /// elevation): mean sea level, what GPS receivers and flight logs report, and what
    /// formats/fmv/PoseCsv.h reads "alt" as.
    AltitudeRef altitudeRef = AltitudeRef::MeanSeaLevel;
    /// Added to numeric times (not to ISO 8601 ones): the UTC of time 0 for relative times.
    TimeNs timeOffset = 0;
};

struct TrajectoryCsv {
    std::vector<TrajectorySample> samples;    ///< in file order, `line` set
    std::vector<std::string> ignored;         ///< header names of the columns not used
    std::string timeUnit;                     ///< "iso8601", "s", "ms", "us" or "ns"
    std::optional<AltitudeRef> altitudeRef;   ///< of the altitude column used; none: no altitude column
};

/// Parses CSV text; `name` (the file) starts every message.
Result<TrajectoryCsv> parseTrajectoryCsv(std::string_view text, const std::string& name, const CsvOptions& options = {});

/// Reads and parses `path` (errors name it; files over kMaxTrajectoryCsvBytes are refused).
Result<TrajectoryCsv> readTrajectoryCsv(const std::string& path, const CsvOptions& options = {});

}  // namespace orbis::motion
