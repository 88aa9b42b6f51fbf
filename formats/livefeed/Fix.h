#pragma once
// One position of a live object, as the live feed decoders produce it (NMEA 0183 or the XML
// message), and the counters that every decoder keeps. CPU only, no I/O.
//
// A Fix carries what a consumer needs to move a model (position, height, heading or course,
// speeds) and to measure latency: `received` is the steady-clock instant at which the bytes that
// completed the fix came out of the socket (recv() returned), so `drainTime - received` is the
// time the fix waited in the queue and `received - serverSendTime` the time on the wire.

#include "base/TimeFormat.h"

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

namespace orbis::livefeed {

/// Which decoder made a fix.
enum class FixFormat : std::uint8_t { Nmea, Xml };

struct Fix {
    TimeNs time = 0;          ///< UTC instant of the position (ns since 1970)
    double lonDeg = 0.0;      ///< WGS84 longitude, -180..180
    double latDeg = 0.0;      ///< WGS84 latitude, -90..90

    /// Height above the WGS84 ellipsoid (m). NMEA: GGA altitude + geoid separation, only when the
    /// receiver gives the separation. XML: `alt` unless altRef="msl".
    std::optional<double> heightEllipsoid;
    /// Altitude above mean sea level (the geoid) in m, when the source gives it (GGA, or XML with
    /// altRef="msl"). A consumer with a geoid model can derive the ellipsoid height from it.
    std::optional<double> altitudeMsl;
    std::optional<double> speedMps;          ///< speed over ground (m/s)
    std::optional<double> courseDeg;         ///< course over ground, degrees from true north, clockwise
    std::optional<double> verticalSpeedMps;  ///< up is positive (XML `vspeed`; NMEA has none)
    std::optional<double> headingDeg;        ///< body heading, degrees from true north (XML only)
    std::optional<double> pitchDeg;          ///< body pitch, nose up positive (XML only)
    std::optional<double> rollDeg;           ///< body roll, right wing down positive (XML only)

    /// NMEA GGA fix quality (1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float, 6 dead reckoning, ...);
    /// -1 when unknown (RMC-only epochs, XML).
    int quality = -1;
    int satellites = -1;                     ///< satellites used (GGA), -1 when unknown
    std::optional<double> hdop;              ///< horizontal dilution of precision (GGA)

    FixFormat format = FixFormat::Nmea;
    /// Set by LiveSource: 1, 2, 3, ... in arrival order over the source's life (gaps mean fixes
    /// were dropped from a full queue). 0 from a bare decoder.
    std::uint64_t sequence = 0;
    /// When recv() returned the bytes that completed this fix (steady clock). An NMEA fix held
    /// back for the rest of its epoch and released later (NmeaDecoder.h) carries the release time.
    std::chrono::steady_clock::time_point received{};
};

/// What a decoder saw. Every dropped input is counted under one reason; `lastError` keeps the
/// text of the last one for display (it quotes the input, shortened).
struct FeedCounters {
    std::uint64_t bytes = 0;         ///< bytes fed
    std::uint64_t messagesOk = 0;    ///< sentences / messages decoded (with or without a position)
    std::uint64_t fixes = 0;         ///< fixes emitted
    std::uint64_t noFix = 0;         ///< decoded but without a position (GGA quality 0, RMC status V)
    std::uint64_t badChecksum = 0;   ///< NMEA: wrong checksum, or none where one is required
    std::uint64_t unknownType = 0;   ///< NMEA: well-formed sentences of other types (GSV, GSA, $P...)
    std::uint64_t malformed = 0;     ///< syntax or range errors, garbage lines, broken XML
    std::uint64_t oversized = 0;     ///< lines / messages over the size limit, dropped
    std::string lastError;           ///< why the last dropped input was dropped

    FeedCounters& operator+=(const FeedCounters& o);
};

/// "2026-03-20T08:00:00.500Z 46.1000000N 7.2000000E h=1500.0" style one-liner for logs and tests.
std::string describe(const Fix& fix);

}  // namespace orbis::livefeed
