#pragma once
// NMEA 0183 sentences, one at a time: checksum, address, and the fields of GGA, RMC and VTG for
// any talker (GP, GN, GL, GA, GB, BD, ...). Pure functions, no I/O, no state; the stream decoder
// (NmeaDecoder.h) frames lines, combines dates and merges the sentences of one epoch.
//
// Sentence syntax (NMEA 0183 v4.11 §5.2): '$', a 5-character address (2-character talker +
// 3-character type; "$P..." proprietary), comma-separated fields, then "*hh": the XOR of every
// byte strictly between '$' and '*', as two hex digits (either case accepted). The standard
// limits a sentence to 82 characters including "$" and CR LF; real devices exceed it, so the
// framing limit is kMaxNmeaLineBytes instead.
//
// Checksums: NMEA 0183 makes the checksum optional for some sentences, but a viewer that moves a
// model on whatever it reads is better off dropping a sentence it cannot verify. So a missing
// checksum is an error by default (counted with the bad ones); `requireChecksum = false` accepts
// sentences without one. A present but wrong checksum is always an error.
//
// Empty fields are "no value" (receivers without a fix send ",,,,"), never an error. Too few
// fields, non-numeric text in a numeric field, a hemisphere other than N/S or E/W, minutes >= 60
// or a latitude past 90° are errors (malformed).

#include "base/TimeFormat.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace orbis::livefeed {

/// Longest line the decoder accepts (NMEA's limit is 82 characters; real devices and
/// proprietary sentences go beyond it). Longer lines are dropped and counted as oversized.
inline constexpr std::size_t kMaxNmeaLineBytes = 1024;

/// 1 knot = 1852 m / 3600 s exactly (international nautical mile).
inline constexpr double kMpsPerKnot = 1852.0 / 3600.0;

/// GGA: Global Positioning System fix data.
struct NmeaGga {
    std::optional<TimeNs> timeOfDay;         ///< ns since 00:00 UTC (no date in GGA)
    std::optional<double> latDeg, lonDeg;    ///< both or neither
    int quality = 0;                         ///< 0 invalid, 1 GPS, 2 DGPS, 3 PPS, 4 RTK, 5 float RTK, 6 estimated, 7 manual, 8 simulation
    int satellites = -1;                     ///< -1 when empty
    std::optional<double> hdop;
    std::optional<double> altitudeMsl;       ///< antenna altitude above mean sea level (m)
    std::optional<double> geoidSeparation;   ///< geoid above the WGS84 ellipsoid (m)
    /// A position the viewer may use: quality != 0 and lat/lon present.
    bool hasPosition() const { return quality != 0 && latDeg && lonDeg; }
};

/// RMC: recommended minimum specific GNSS data.
struct NmeaRmc {
    std::optional<TimeNs> timeOfDay;
    bool active = false;                     ///< status A; V = void (no position)
    std::optional<double> latDeg, lonDeg;
    std::optional<double> speedMps;          ///< from knots
    std::optional<double> courseDeg;         ///< true
    std::optional<CivilDate> date;           ///< ddmmyy; yy 80..99 -> 19yy, 00..79 -> 20yy (GPS began 1980)
    std::optional<double> magneticVariationDeg;  ///< east positive
    char mode = 0;                           ///< NMEA 2.3 mode indicator (A, D, E, F, M, N, P, R, S), 0 if absent; N = not valid
    bool hasPosition() const { return active && mode != 'N' && latDeg && lonDeg; }
};

/// VTG: course over ground and ground speed. No time: it belongs to the epoch it arrives in.
struct NmeaVtg {
    std::optional<double> courseTrueDeg;
    std::optional<double> courseMagneticDeg;
    std::optional<double> speedKnots;
    std::optional<double> speedKmh;
    char mode = 0;                           ///< NMEA 2.3 mode indicator, 0 if absent; N = not valid
    /// km/h when given (its resolution is finer than knots at the same number of decimals).
    std::optional<double> speedMps() const;
};

enum class NmeaStatus : std::uint8_t {
    Ok,            ///< a GGA, RMC or VTG, decoded
    UnknownType,   ///< a well-formed sentence of another type (checksum verified when present)
    BadChecksum,   ///< wrong checksum, or missing where required
    Malformed,     ///< anything else: syntax, field count, ranges
};

struct NmeaSentence {
    NmeaStatus status = NmeaStatus::Malformed;
    std::string talker;                      ///< "GP", "GN", ...; "P" for proprietary
    std::string type;                        ///< "GGA", "RMC", "VTG", or whatever the address says
    std::variant<std::monostate, NmeaGga, NmeaRmc, NmeaVtg> data;
    std::string error;                       ///< why, when status is not Ok (quotes the sentence)
};

struct NmeaOptions {
    /// Drop sentences without "*hh" (see the header comment for why this is the default).
    bool requireChecksum = true;
};

/// XOR of the bytes of `body` (the text between '$' and '*').
std::uint8_t nmeaChecksum(std::string_view body);

/// Parses one sentence: "$GPGGA,...*47", with or without trailing CR/LF and spaces. Bytes before
/// the '$' are an error (the stream decoder cuts them off first).
NmeaSentence parseNmeaSentence(std::string_view line, const NmeaOptions& options = {});

/// Time of day of an NMEA "hhmmss[.sss...]" field, in ns since midnight. Accepts 23:59:60 (a
/// leap second as receivers report it) as the next day's first instant (86400 s), since TimeNs
/// has no leap seconds.
std::optional<TimeNs> parseNmeaTimeOfDay(std::string_view field);

/// "ddmm.mmmm" (latitude) or "dddmm.mmmm" (longitude) with its hemisphere letter, in degrees.
/// Empty text and empty hemisphere: nullopt with `ok` true. Errors set `ok` false.
std::optional<double> parseNmeaAngle(std::string_view value, std::string_view hemisphere, bool latitude, bool& ok);

}  // namespace orbis::livefeed
