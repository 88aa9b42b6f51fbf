#pragma once
// Virtual time as one integer: nanoseconds since 1970-01-01T00:00:00Z, UTC without leap seconds
// (POSIX time scaled to ns). An int64 of ns covers 1677-09-21 .. 2262-04-11, which is why years
// outside 1678..2261 are refused by the parser. Conversions use Howard Hinnant's days-from-civil
// arithmetic, not timegm/gmtime: they do not depend on the C library, the locale or TZ, and they
// are exact for dates before 1970.
//
// All functions are pure and thread-safe.

#include "base/Result.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace orbis {

/// Nanoseconds since 1970-01-01T00:00:00Z (UTC, no leap seconds).
using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;
inline constexpr TimeNs kNsPerDay = 86'400 * kNsPerSecond;

/// Years the parser accepts: every instant in them fits an int64 of ns, whatever the offset.
inline constexpr int kMinYear = 1678;
inline constexpr int kMaxYear = 2261;

/// A proleptic Gregorian calendar date.
struct CivilDate {
    int year = 1970;
    int month = 1;   ///< 1..12
    int day = 1;     ///< 1..31
};

/// Days since 1970-01-01 of a proleptic Gregorian date (Hinnant, "chrono-Compatible Low-Level
/// Date Algorithms", days_from_civil). The date is not validated.
std::int64_t daysFromCivil(int year, int month, int day);

/// Inverse of daysFromCivil (Hinnant's civil_from_days).
CivilDate civilFromDays(std::int64_t days);

/// Days in `month` of `year` (Gregorian leap rule: every 4th year, except centuries not
/// divisible by 400).
int daysInMonth(int year, int month);

/// Parses an ISO 8601 / RFC 3339 instant:
///   2026-03-20T08:00:00Z, 2026-03-20T08:00:00.123456789+02:00, 2026-03-20 08:00:00-05:30,
///   2026-03-20T08:00Z (no seconds), 2026-03-20 (midnight UTC).
/// 'T' may also be 't' or a space; the offset is Z, z, +hh:mm, -hh:mm, +hhmm or +hh. A time
/// without an offset is read as UTC (scene files are written in UTC; local time would make the
/// same file mean different instants on different machines). At most 9 fractional digits.
/// Leap seconds (ss = 60) and hour 24 are refused. On error the message quotes the text and
/// says what is wrong with it.
Result<TimeNs> parseIso8601(std::string_view text);

/// Formats `t` as 2026-03-20T08:00:00.000Z with `fractionDigits` (clamped to 0..9) digits after
/// the seconds; 0 writes no decimal point. Extra digits are truncated toward the past, never
/// rounded, so the printed second is always the one that contains `t` (also for t < 0).
std::string formatIso8601(TimeNs t, int fractionDigits = 3);

/// Seconds since the epoch. Splits whole seconds and the remainder so that the nanoseconds
/// survive as well as a double allows.
double toSeconds(TimeNs t);

/// Nanoseconds nearest to `seconds`, saturated to the int64 range; NaN gives 0.
TimeNs fromSeconds(double seconds);

/// Julian Date of `t` on the UTC time scale (2440587.5 at the epoch). A double holds a JD to
/// about 40 microseconds; use daysSinceJ2000 where more is needed.
double julianDateUtc(TimeNs t);

/// Days since J2000.0 (2000-01-01T12:00:00, JD 2451545.0) on the UTC scale, computed from the
/// integer time so that it keeps sub-microsecond precision near the present.
double daysSinceJ2000(TimeNs t);

}  // namespace orbis
