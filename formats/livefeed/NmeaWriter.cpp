#include "formats/livefeed/NmeaWriter.h"

#include "formats/livefeed/Nmea.h"

#include <cmath>
#include <cstdio>

namespace orbis::livefeed {
namespace {

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

/// The fix's time rounded to the millisecond, split into days since 1970 and ms of the day.
struct MsTime {
    std::int64_t days;
    std::int64_t msOfDay;
};
MsTime splitTime(TimeNs t) {
    const std::int64_t ms = floorDiv(t + 500'000, 1'000'000);
    const std::int64_t days = floorDiv(ms, 86'400'000);
    return {days, ms - days * 86'400'000};
}

std::string timeField(const MsTime& t) {
    char buf[16];
    const std::int64_t s = t.msOfDay / 1000;
    std::snprintf(buf, sizeof buf, "%02d%02d%02d.%03d", int(s / 3600), int(s / 60 % 60), int(s % 60), int(t.msOfDay % 1000));
    return buf;
}

/// "ddmm.mmmmmm,N" / "dddmm.mmmmmm,E", rounded in integer micro-minutes so that 59.9999999'
/// carries into the degrees instead of printing 60.
std::string angleField(double deg, bool latitude) {
    const std::int64_t uMin = std::llround(std::fabs(deg) * 60.0 * 1e6);
    const std::int64_t d = uMin / 60'000'000;
    const std::int64_t rem = uMin % 60'000'000;
    char buf[32];
    std::snprintf(buf, sizeof buf, latitude ? "%02d%02d.%06d,%c" : "%03d%02d.%06d,%c", int(d), int(rem / 1'000'000),
                  int(rem % 1'000'000), latitude ? (deg < 0 ? 'S' : 'N') : (deg < 0 ? 'W' : 'E'));
    return buf;
}

std::string number(const std::optional<double>& v, const char* format) {
    if (!v) return {};
    char buf[48];
    std::snprintf(buf, sizeof buf, format, *v);
    return buf;
}

std::optional<double> course(const Fix& fix) {
    if (!fix.courseDeg) return std::nullopt;
    const double c = std::fmod(*fix.courseDeg, 360.0);
    return c < 0 ? c + 360.0 : c;
}

}  // namespace

std::string nmeaSentence(std::string_view body) {
    char sum[8];
    std::snprintf(sum, sizeof sum, "*%02X\r\n", nmeaChecksum(body));
    return std::string("$").append(body).append(sum);
}

std::string NmeaWriter::gga(const Fix& fix) const {
    std::optional<double> alt, separation;
    if (fix.altitudeMsl) {
        alt = fix.altitudeMsl;
        if (fix.heightEllipsoid) separation = *fix.heightEllipsoid - *fix.altitudeMsl;
    } else if (fix.heightEllipsoid) {
        alt = fix.heightEllipsoid;
        separation = 0.0;
    }
    char head[32];
    std::snprintf(head, sizeof head, ",%d,%02d,", fix.quality > 0 ? fix.quality : 1, fix.satellites >= 0 ? fix.satellites : 8);
    const std::string body = talker_ + "GGA," + timeField(splitTime(fix.time)) + "," + angleField(fix.latDeg, true) + "," +
                             angleField(fix.lonDeg, false) + head + number(fix.hdop ? fix.hdop : 1.0, "%.1f") + "," +
                             number(alt, "%.3f") + ",M," + number(separation, "%.3f") + ",M,,";
    return nmeaSentence(body);
}

std::string NmeaWriter::rmc(const Fix& fix) const {
    const MsTime t = splitTime(fix.time);
    const CivilDate date = civilFromDays(t.days);
    char dateField[16];
    std::snprintf(dateField, sizeof dateField, "%02d%02d%02d", date.day, date.month, ((date.year % 100) + 100) % 100);
    std::optional<double> knots;
    if (fix.speedMps) knots = *fix.speedMps / kMpsPerKnot;
    const std::string body = talker_ + "RMC," + timeField(t) + ",A," + angleField(fix.latDeg, true) + "," +
                             angleField(fix.lonDeg, false) + "," + number(knots, "%.3f") + "," + number(course(fix), "%.2f") +
                             "," + dateField + ",,,A";
    return nmeaSentence(body);
}

std::string NmeaWriter::vtg(const Fix& fix) const {
    std::optional<double> knots, kmh;
    if (fix.speedMps) {
        knots = *fix.speedMps / kMpsPerKnot;
        kmh = *fix.speedMps * 3.6;
    }
    const std::string body = talker_ + "VTG," + number(course(fix), "%.2f") + ",T,,M," + number(knots, "%.3f") + ",N," +
                             number(kmh, "%.3f") + ",K,A";
    return nmeaSentence(body);
}

}  // namespace orbis::livefeed
