#include "formats/livefeed/Nmea.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <vector>

namespace orbis::livefeed {
namespace {

/// The sentence as it appears in messages: quoted, control bytes escaped, at most 100 characters.
std::string quote(std::string_view s) {
    std::string q = "'";
    for (std::size_t i = 0; i < s.size() && i < 100; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7f) {
            q += char(c);
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", c);
            q += hex;
        }
    }
    if (s.size() > 100) q += "...";
    return q + "'";
}

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

bool isDigit(char c) { return c >= '0' && c <= '9'; }

/// A decimal number without exponent, sign allowed ("-12.5", "003.1"). from_chars is locale-free.
std::optional<double> parseNumber(std::string_view s, bool& ok) {
    if (s.empty()) return std::nullopt;
    for (char c : s) {
        if (!isDigit(c) && c != '.' && c != '-' && c != '+') {
            ok = false;
            return std::nullopt;
        }
    }
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::fixed);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
        ok = false;
        return std::nullopt;
    }
    return v;
}

std::optional<int> parseInt(std::string_view s, bool& ok) {
    if (s.empty()) return std::nullopt;
    int v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || v < 0) {
        ok = false;
        return std::nullopt;
    }
    return v;
}

/// Unit letter fields ("M", "N", "K", "T"): empty or exactly `expected`.
bool unitIs(std::string_view field, char expected) { return field.empty() || (field.size() == 1 && field[0] == expected); }

/// NMEA 2.3 mode indicator (RMC field 12, VTG field 9): one letter, or absent.
bool parseMode(std::string_view field, char& mode) {
    if (field.empty()) return true;
    if (field.size() != 1 || field[0] < 'A' || field[0] > 'Z') return false;
    mode = field[0];
    return true;
}

struct Fields {
    std::vector<std::string_view> f;   // f[0] is the address ("GPGGA")
    std::size_t size() const { return f.size(); }
    std::string_view operator[](std::size_t i) const { return i < f.size() ? f[i] : std::string_view(); }
};

Fields split(std::string_view body) {
    Fields out;
    out.f.reserve(24);
    std::size_t start = 0;
    for (std::size_t i = 0; i <= body.size(); ++i) {
        if (i == body.size() || body[i] == ',') {
            out.f.push_back(body.substr(start, i - start));
            start = i + 1;
        }
    }
    return out;
}

NmeaSentence fail(NmeaSentence s, NmeaStatus status, std::string_view line, std::string why) {
    s.status = status;
    s.data = std::monostate{};
    s.error = "NMEA sentence " + quote(line) + ": " + why;
    return s;
}

bool parseGga(const Fields& f, NmeaGga& g, std::string& why) {
    // NMEA 0183 GGA: time, lat, N/S, lon, E/W, quality, satellites, HDOP, altitude, M,
    // geoid separation, M, age of differential data, reference station id.
    if (f.size() < 15) {
        why = "GGA has " + std::to_string(f.size() - 1) + " fields, expected 14";
        return false;
    }
    bool ok = true;
    if (!f[1].empty()) {
        g.timeOfDay = parseNmeaTimeOfDay(f[1]);
        if (!g.timeOfDay) return (why = "bad UTC time '" + std::string(f[1]) + "'"), false;
    }
    g.latDeg = parseNmeaAngle(f[2], f[3], true, ok);
    if (!ok) return (why = "bad latitude '" + std::string(f[2]) + "," + std::string(f[3]) + "'"), false;
    g.lonDeg = parseNmeaAngle(f[4], f[5], false, ok);
    if (!ok) return (why = "bad longitude '" + std::string(f[4]) + "," + std::string(f[5]) + "'"), false;
    if (g.latDeg.has_value() != g.lonDeg.has_value()) return (why = "latitude without longitude"), false;
    const std::optional<int> quality = parseInt(f[6], ok);
    if (!ok || quality.value_or(0) > 9) return (why = "bad fix quality '" + std::string(f[6]) + "'"), false;
    g.quality = quality.value_or(0);
    g.satellites = parseInt(f[7], ok).value_or(-1);
    if (!ok) return (why = "bad satellite count '" + std::string(f[7]) + "'"), false;
    g.hdop = parseNumber(f[8], ok);
    g.altitudeMsl = parseNumber(f[9], ok);
    g.geoidSeparation = parseNumber(f[11], ok);
    if (!ok) return (why = "bad number in HDOP, altitude or geoid separation"), false;
    if (!unitIs(f[10], 'M') || !unitIs(f[12], 'M')) return (why = "altitude unit is not M"), false;
    if (g.hasPosition() && !g.timeOfDay) return (why = "position without UTC time"), false;
    return true;
}

bool parseRmc(const Fields& f, NmeaRmc& r, std::string& why) {
    // NMEA 0183 RMC: time, status A/V, lat, N/S, lon, E/W, speed (knots), course (true),
    // date ddmmyy, magnetic variation, E/W, [mode (2.3+)], [navigational status (4.1+)].
    if (f.size() < 12) {
        why = "RMC has " + std::to_string(f.size() - 1) + " fields, expected at least 11";
        return false;
    }
    bool ok = true;
    if (!f[1].empty()) {
        r.timeOfDay = parseNmeaTimeOfDay(f[1]);
        if (!r.timeOfDay) return (why = "bad UTC time '" + std::string(f[1]) + "'"), false;
    }
    if (f[2] != "A" && f[2] != "V") return (why = "status '" + std::string(f[2]) + "' is neither A nor V"), false;
    r.active = f[2] == "A";
    r.latDeg = parseNmeaAngle(f[3], f[4], true, ok);
    if (!ok) return (why = "bad latitude '" + std::string(f[3]) + "," + std::string(f[4]) + "'"), false;
    r.lonDeg = parseNmeaAngle(f[5], f[6], false, ok);
    if (!ok) return (why = "bad longitude '" + std::string(f[5]) + "," + std::string(f[6]) + "'"), false;
    if (r.latDeg.has_value() != r.lonDeg.has_value()) return (why = "latitude without longitude"), false;
    const std::optional<double> knots = parseNumber(f[7], ok);
    r.courseDeg = parseNumber(f[8], ok);
    const std::optional<double> variation = parseNumber(f[10], ok);
    if (!ok) return (why = "bad number in speed, course or magnetic variation"), false;
    if (knots) r.speedMps = *knots * kMpsPerKnot;
    if (variation) {
        if (f[11] != "E" && f[11] != "W") return (why = "magnetic variation without E/W"), false;
        r.magneticVariationDeg = f[11] == "W" ? -*variation : *variation;
    }
    if (!f[9].empty()) {
        const std::string_view d = f[9];
        if (d.size() != 6 || !std::all_of(d.begin(), d.end(), isDigit)) return (why = "bad date '" + std::string(d) + "'"), false;
        const int day = (d[0] - '0') * 10 + (d[1] - '0');
        const int month = (d[2] - '0') * 10 + (d[3] - '0');
        const int yy = (d[4] - '0') * 10 + (d[5] - '0');
        const int year = yy >= 80 ? 1900 + yy : 2000 + yy;
        if (month < 1 || month > 12 || day < 1 || day > daysInMonth(year, month))
            return (why = "bad date '" + std::string(d) + "'"), false;
        r.date = CivilDate{year, month, day};
    }
    if (!parseMode(f[12], r.mode)) return (why = "bad mode indicator '" + std::string(f[12]) + "'"), false;
    if (r.hasPosition() && (!r.timeOfDay || !r.date)) return (why = "position without UTC time or date"), false;
    return true;
}

bool parseVtg(const Fields& f, NmeaVtg& v, std::string& why) {
    // NMEA 0183 VTG: course true, T, course magnetic, M, speed knots, N, speed km/h, K, [mode].
    if (f.size() < 9) {
        why = "VTG has " + std::to_string(f.size() - 1) + " fields, expected at least 8";
        return false;
    }
    bool ok = true;
    v.courseTrueDeg = parseNumber(f[1], ok);
    v.courseMagneticDeg = parseNumber(f[3], ok);
    v.speedKnots = parseNumber(f[5], ok);
    v.speedKmh = parseNumber(f[7], ok);
    if (!ok) return (why = "bad number in course or speed"), false;
    if (!unitIs(f[2], 'T') || !unitIs(f[4], 'M') || !unitIs(f[6], 'N') || !unitIs(f[8], 'K'))
        return (why = "unit letters are not T, M, N, K"), false;
    if (!parseMode(f[9], v.mode)) return (why = "bad mode indicator '" + std::string(f[9]) + "'"), false;
    return true;
}

}  // namespace

std::optional<double> NmeaVtg::speedMps() const {
    if (mode == 'N') return std::nullopt;
    if (speedKmh) return *speedKmh / 3.6;
    if (speedKnots) return *speedKnots * kMpsPerKnot;
    return std::nullopt;
}

std::uint8_t nmeaChecksum(std::string_view body) {
    std::uint8_t x = 0;
    for (char c : body) x ^= static_cast<std::uint8_t>(c);
    return x;
}

std::optional<TimeNs> parseNmeaTimeOfDay(std::string_view s) {
    if (s.size() < 6) return std::nullopt;
    for (int i = 0; i < 6; ++i)
        if (!isDigit(s[i])) return std::nullopt;
    const int hh = (s[0] - '0') * 10 + (s[1] - '0');
    const int mm = (s[2] - '0') * 10 + (s[3] - '0');
    const int ss = (s[4] - '0') * 10 + (s[5] - '0');
    if (hh > 23 || mm > 59 || ss > 60) return std::nullopt;
    if (ss == 60 && (hh != 23 || mm != 59)) return std::nullopt;   // leap seconds are inserted at 23:59:60 only
    TimeNs frac = 0;
    if (s.size() > 6) {
        if (s[6] != '.') return std::nullopt;
        TimeNs scale = kNsPerSecond / 10;
        for (std::size_t i = 7; i < s.size(); ++i) {
            if (!isDigit(s[i])) return std::nullopt;
            frac += (s[i] - '0') * scale;   // digits past the 9th add nothing (scale is 0)
            scale /= 10;
        }
    }
    return (TimeNs(hh) * 3600 + mm * 60 + ss) * kNsPerSecond + frac;
}

std::optional<double> parseNmeaAngle(std::string_view value, std::string_view hemisphere, bool latitude, bool& ok) {
    if (value.empty() && hemisphere.empty()) return std::nullopt;
    const char pos = latitude ? 'N' : 'E';
    const char neg = latitude ? 'S' : 'W';
    if (hemisphere.size() != 1 || (hemisphere[0] != pos && hemisphere[0] != neg) || value.empty()) {
        ok = false;
        return std::nullopt;
    }
    // ddmm.mmmm: the degrees are everything before the last two digits of the integer part.
    const std::size_t dot = value.find('.');
    const std::size_t intLen = dot == std::string_view::npos ? value.size() : dot;
    const std::size_t degLen = latitude ? 2 : 3;
    if (intLen < 3 || intLen > degLen + 2 || value[0] == '-' || value[0] == '+') {
        ok = false;
        return std::nullopt;
    }
    bool numberOk = true;
    const std::optional<double> deg = parseNumber(value.substr(0, intLen - 2), numberOk);
    const std::optional<double> minutes = parseNumber(value.substr(intLen - 2), numberOk);
    if (!numberOk || !deg || !minutes || *minutes < 0.0 || *minutes >= 60.0) {
        ok = false;
        return std::nullopt;
    }
    const double angle = *deg + *minutes / 60.0;
    if (angle > (latitude ? 90.0 : 180.0)) {
        ok = false;
        return std::nullopt;
    }
    return hemisphere[0] == neg ? -angle : angle;
}

NmeaSentence parseNmeaSentence(std::string_view line, const NmeaOptions& options) {
    NmeaSentence s;
    while (!line.empty() && (line.back() == '\r' || line.back() == '\n' || line.back() == ' ' || line.back() == '\t'))
        line.remove_suffix(1);
    if (line.empty() || (line[0] != '$' && line[0] != '!')) return fail(std::move(s), NmeaStatus::Malformed, line, "does not start with '$'");

    std::string_view body = line.substr(1);
    const std::size_t star = body.find('*');
    if (star != std::string_view::npos) {
        const std::string_view sum = body.substr(star + 1);
        const int hi = sum.size() == 2 ? hexDigit(sum[0]) : -1;
        const int lo = sum.size() == 2 ? hexDigit(sum[1]) : -1;
        if (hi < 0 || lo < 0) return fail(std::move(s), NmeaStatus::Malformed, line, "checksum is not two hex digits");
        body = body.substr(0, star);
        const std::uint8_t expected = static_cast<std::uint8_t>(hi * 16 + lo);
        const std::uint8_t actual = nmeaChecksum(body);
        if (expected != actual) {
            char why[64];
            std::snprintf(why, sizeof why, "checksum %02X, computed %02X", expected, actual);
            return fail(std::move(s), NmeaStatus::BadChecksum, line, why);
        }
    } else if (options.requireChecksum) {
        return fail(std::move(s), NmeaStatus::BadChecksum, line, "no checksum");
    }
    for (char c : body) {
        // NMEA 0183 §5.1: printable ASCII only ('$', '*', '!' and '\' are reserved).
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e || c == '$' || c == '*')
            return fail(std::move(s), NmeaStatus::Malformed, line, "invalid character in sentence");
    }

    const Fields fields = split(body);
    const std::string_view address = fields[0];
    if (address.size() >= 1 && address[0] == 'P') {   // proprietary: "$P" + manufacturer code
        s.talker = std::string(1, 'P');
        s.type = std::string(address.substr(1));
        s.status = NmeaStatus::UnknownType;
        return s;
    }
    if (address.size() != 5 || !std::all_of(address.begin(), address.end(), [](char c) { return (c >= 'A' && c <= 'Z') || isDigit(c); }))
        return fail(std::move(s), NmeaStatus::Malformed, line, "address '" + std::string(address) + "' is not talker + type");
    s.talker = std::string(address.substr(0, 2));
    s.type = std::string(address.substr(2));

    std::string why;
    bool ok = true;
    if (s.type == "GGA") {
        NmeaGga g;
        ok = parseGga(fields, g, why);
        s.data = g;
    } else if (s.type == "RMC") {
        NmeaRmc r;
        ok = parseRmc(fields, r, why);
        s.data = r;
    } else if (s.type == "VTG") {
        NmeaVtg v;
        ok = parseVtg(fields, v, why);
        s.data = v;
    } else {
        s.status = NmeaStatus::UnknownType;
        return s;
    }
    if (!ok) return fail(std::move(s), NmeaStatus::Malformed, line, why);
    s.status = NmeaStatus::Ok;
    return s;
}

}  // namespace orbis::livefeed
