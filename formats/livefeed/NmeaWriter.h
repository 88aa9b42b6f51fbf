#pragma once
// Writes Fixes as NMEA 0183 sentences with correct checksums: the test servers play recorded
// tracks with it, and a replay tool can be built on it. Pure functions of the Fix.
//
// Precision goes beyond what receivers print, so that a round trip through NmeaDecoder loses
// little: time to the millisecond (rounded), latitude/longitude minutes to 6 decimals
// (1e-6 arc minute = 1.9 mm), altitudes to the millimetre, speed to 0.001 knot (0.5 mm/s) and
// 0.001 km/h, course to 0.01°. The RMC date has a two-digit year, so years outside 1980..2079
// do not survive (NMEA's own limit).

#include "formats/livefeed/Fix.h"

#include <string>
#include <string_view>

namespace orbis::livefeed {

/// "$" + body + "*hh" + CR LF, hh being the XOR checksum of `body` (upper-case hex).
std::string nmeaSentence(std::string_view body);

class NmeaWriter {
public:
    /// `talker`: the two-character talker id ("GP", "GN", ...).
    explicit NmeaWriter(std::string talker = "GP") : talker_(std::move(talker)) {}

    /// GGA: time, position, quality (fix.quality, or 1 when unknown), satellites (or 8), HDOP
    /// (or 1.0), altitude above MSL and geoid separation: from altitudeMsl and heightEllipsoid
    /// when both are known; with only heightEllipsoid, altitude = height and separation = 0, so
    /// that a reader's alt + separation gives the height back.
    std::string gga(const Fix& fix) const;
    /// RMC: time, status A, position, speed (knots), course, date, mode A.
    std::string rmc(const Fix& fix) const;
    /// VTG: course true, speed in knots and km/h, mode A.
    std::string vtg(const Fix& fix) const;
    /// GGA, RMC, VTG of one epoch, in that order.
    std::string epoch(const Fix& fix) const { return gga(fix) + rmc(fix) + vtg(fix); }

private:
    std::string talker_;
};

}  // namespace orbis::livefeed
