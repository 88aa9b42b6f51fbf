#include "formats/motion/TrajectoryCsv.h"

#include "base/CsvText.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace orbis::motion {
namespace {

using csv::isNoValue;
using csv::nextLine;
using csv::skipLine;
using csv::separatorOf;
using csv::splitLine;

enum class Field { Time, Lat, Lon, Alt, Heading, Pitch, Roll };
enum class Quantity { Time, Angle, Length };

struct Alias {
    Field field;
    Quantity quantity;
    std::optional<AltitudeRef> ref;        // altitude columns: what the name says they are above
    std::array<const char*, 16> names;     // normalised (lower-case letters and digits); unused entries null
};

const Alias kAliases[] = {
    {Field::Time, Quantity::Time, {}, {"time", "timestamp", "t", "utc", "datetime", "unixtime", "epoch", "timeutc", "utctime",
                                       "precisiontimestamp"}},
    {Field::Lat, Quantity::Angle, {}, {"lat", "latitude", "sensorlat", "sensorlatitude", "platformlat", "platformlatitude"}},
    {Field::Lon, Quantity::Angle, {}, {"lon", "long", "lng", "longitude", "sensorlon", "sensorlong", "sensorlongitude", "platformlon",
                                       "platformlong", "platformlongitude"}},
    {Field::Alt, Quantity::Length, AltitudeRef::Ellipsoid,
     {"hae", "althae", "altitudehae", "height", "ellipsoidheight", "ellipsoidalheight", "heightellipsoid", "heightwgs84", "altwgs84",
      "altitudewgs84", "sensorellipsoidheight", "sensorhae", "heightaboveellipsoid"}},
    {Field::Alt, Quantity::Length, AltitudeRef::MeanSeaLevel,
     {"altmsl", "altitudemsl", "msl", "heightmsl", "elevationmsl", "altasl", "altitudeasl", "asl", "heightasl", "orthometricheight",
      "truealtitude", "sensortruealtitude"}},
    {Field::Alt, Quantity::Length, AltitudeRef::Ground,
     {"agl", "altagl", "altitudeagl", "heightagl", "heightaboveground", "altitudeaboveground", "altaboveground", "aboveground"}},
    {Field::Alt, Quantity::Length, {}, {"alt", "altitude", "elevation", "ele", "elev", "sensoralt", "sensoraltitude"}},
    {Field::Heading, Quantity::Angle, {}, {"heading", "yaw", "hdg", "trueheading", "headingtrue", "headingangle", "yawangle",
                                           "platformheading", "platformheadingangle", "platformyaw", "platformyawangle"}},
    {Field::Pitch, Quantity::Angle, {}, {"pitch", "pitchangle", "platformpitch", "platformpitchangle"}},
    {Field::Roll, Quantity::Angle, {}, {"roll", "rollangle", "bank", "bankangle", "platformroll", "platformrollangle"}},
};

struct Unit {
    const char* suffix;
    Quantity quantity;
    double scale;   // to degrees, metres, or (time) to ns
    const char* name;
};
// Longest suffixes first, so "seconds" is not read as "second" + "s".
const Unit kUnits[] = {
    {"nanoseconds", Quantity::Time, 1.0, "ns"},   {"microseconds", Quantity::Time, 1e3, "us"}, {"milliseconds", Quantity::Time, 1e6, "ms"},
    {"kilometers", Quantity::Length, 1e3, ""},    {"kilometres", Quantity::Length, 1e3, ""},   {"seconds", Quantity::Time, 1e9, "s"},
    {"degrees", Quantity::Angle, 1.0, ""},        {"radians", Quantity::Angle, 180.0 / std::numbers::pi, ""},
    {"meters", Quantity::Length, 1.0, ""},        {"metres", Quantity::Length, 1.0, ""},       {"degree", Quantity::Angle, 1.0, ""},
    {"radian", Quantity::Angle, 180.0 / std::numbers::pi, ""},
    {"meter", Quantity::Length, 1.0, ""},         {"metre", Quantity::Length, 1.0, ""},        {"feet", Quantity::Length, 0.3048, ""},
    {"foot", Quantity::Length, 0.3048, ""},       {"nsec", Quantity::Time, 1.0, "ns"},         {"usec", Quantity::Time, 1e3, "us"},
    {"msec", Quantity::Time, 1e6, "ms"},          {"secs", Quantity::Time, 1e9, "s"},          {"degs", Quantity::Angle, 1.0, ""},
    {"rads", Quantity::Angle, 180.0 / std::numbers::pi, ""},
    {"sec", Quantity::Time, 1e9, "s"},            {"deg", Quantity::Angle, 1.0, ""},           {"rad", Quantity::Angle, 180.0 / std::numbers::pi, ""},
    {"km", Quantity::Length, 1e3, ""},            {"ft", Quantity::Length, 0.3048, ""},        {"ns", Quantity::Time, 1.0, "ns"},
    {"us", Quantity::Time, 1e3, "us"},            {"ms", Quantity::Time, 1e6, "ms"},           {"m", Quantity::Length, 1.0, ""},
    {"s", Quantity::Time, 1e9, "s"},
};

struct Column {
    const Alias* alias = nullptr;   // nullptr: ignored
    double scale = 1.0;             // see Unit::scale; 0 for a time without a stated unit
    const char* unitName = "";
};

Column columnOf(std::string_view header) {
    const auto [a, u] = csv::matchColumn<Alias, Unit>(kAliases, kUnits, header);
    if (!a) return {};
    if (!u) return {a, a->quantity == Quantity::Time ? 0.0 : 1.0, ""};
    return {a, u->scale, u->name};
}


std::string lineText(std::size_t line) { return ": line " + std::to_string(line); }

std::string where(const std::string& name, std::size_t line, std::size_t col, const std::string& header) {
    return name + lineText(line) + ", column " + std::to_string(col + 1) + " (" + header + ")";
}

/// A finite number, the whole cell.
bool parseNumber(const std::string& s, double& out) {
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return r.ec == std::errc() && r.ptr == end && std::isfinite(out);
}

/// A plain decimal ([-+]digits[.digits]) as an exact integer and its count of fraction digits.
bool parseDecimal(std::string_view s, __int128& mantissa, int& fractionDigits) {
    std::size_t i = 0;
    bool negative = false;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) negative = s[i++] == '-';
    mantissa = 0;
    fractionDigits = 0;
    int digits = 0;
    bool point = false;
    for (; i < s.size(); ++i) {
        if (s[i] == '.' && !point) {
            point = true;
            continue;
        }
        if (s[i] < '0' || s[i] > '9') return false;
        if (++digits > 30) return false;
        mantissa = mantissa * 10 + (s[i] - '0');
        if (point) ++fractionDigits;
    }
    if (digits == 0) return false;
    if (negative) mantissa = -mantissa;
    return true;
}

struct Header {
    char sep = ',';
    std::vector<Column> columns;
    std::vector<std::string> names;
    std::array<int, 7> index{-1, -1, -1, -1, -1, -1, -1};   // per Field: the column used
};

int altitudeRank(const Alias& a) {   // lower wins
    if (!a.ref) return 2;
    return *a.ref == AltitudeRef::Ellipsoid ? 0 : *a.ref == AltitudeRef::MeanSeaLevel ? 1 : 3;
}

std::string acceptedNames(Field f) {
    std::string s;
    for (const Alias& a : kAliases) {
        if (a.field != f) continue;
        for (const char* name : a.names)
            if (name) s.append(s.empty() ? "" : ", ").append(name);
    }
    return s;
}

Result<Header> parseHeader(std::string_view line, const std::string& name, std::size_t lineNo) {
    Header h;
    h.sep = separatorOf(line);
    h.names = splitLine(line, h.sep);
    for (std::size_t i = 0; i < h.names.size(); ++i) {
        Column c = columnOf(h.names[i]);
        h.columns.push_back(c);
        if (!c.alias) continue;
        int& used = h.index[std::size_t(c.alias->field)];
        if (used >= 0 && c.alias->field == Field::Alt && altitudeRank(*c.alias) != altitudeRank(*h.columns[std::size_t(used)].alias)) {
            if (altitudeRank(*c.alias) < altitudeRank(*h.columns[std::size_t(used)].alias)) used = int(i);
            continue;
        }
        if (used >= 0)
            return makeError(name + lineText(lineNo) + ": columns " + std::to_string(used + 1) + " (" + h.names[std::size_t(used)] +
                             ") and " + std::to_string(i + 1) + " (" + h.names[i] + ") give the same value");
        used = int(i);
    }
    std::string missing;
    auto need = [&](Field f, const char* what) {
        if (h.index[std::size_t(f)] < 0)
            missing.append(missing.empty() ? "" : "; ").append(what).append(" (").append(acceptedNames(f)).append(")");
    };
    need(Field::Time, "time");
    need(Field::Lat, "latitude");
    need(Field::Lon, "longitude");
    if (!missing.empty())
        return makeError(name + lineText(lineNo) + ": no column for " + missing +
                         "; names may carry a unit (lat_rad, time_ms); see formats/motion/TrajectoryCsv.h");
    return h;
}

/// The time cell as ns since 1970. `scale` (ns per unit) is fixed by the first number when the
/// header named no unit.
Result<TimeNs> parseTime(std::string cell, double& scale, std::string& unit, TimeNs offset) {
    __int128 mantissa = 0;
    int fraction = 0;
    double v = 0.0;
    const bool decimal = parseDecimal(cell, mantissa, fraction);
    if (!decimal && !parseNumber(cell, v)) {
        auto t = parseIso8601(cell);
        if (!t) return makeError("'" + cell + "' is neither a number nor an ISO 8601 time (" + t.message() + ")");
        if (unit.empty()) unit = "iso8601";
        return *t;
    }
    if (decimal) v = double(mantissa) / std::pow(10.0, fraction);
    if (scale == 0.0) scale = std::abs(v) >= 1e17 ? 1.0 : std::abs(v) >= 1e14 ? 1e3 : std::abs(v) >= 1e11 ? 1e6 : 1e9;
    if (unit.empty()) unit = scale == 1.0 ? "ns" : scale == 1e3 ? "us" : scale == 1e6 ? "ms" : "s";
    __int128 ns = 0;
    const __int128 limit = __int128(1) << 63;
    if (decimal && fraction <= 18) {   // exact: mantissa * scale / 10^fraction, rounded half away from 0
        __int128 pow10 = 1;
        for (int i = 0; i < fraction; ++i) pow10 *= 10;
        const __int128 bound = limit * pow10;   // < 2^63 * 10^18 < 2^124
        const __int128 unitNs = __int128(scale);
        if (mantissa > bound / unitNs || mantissa < -bound / unitNs)
            return makeError("'" + cell + "' is past what int64 nanoseconds since 1970 hold (years 1677..2262)");
        const __int128 scaled = mantissa * unitNs;
        ns = (scaled + (scaled >= 0 ? pow10 / 2 : -(pow10 / 2))) / pow10;
    } else {
        const double d = std::round(v * scale);
        if (!(std::abs(d) < 9.2e18)) return makeError("'" + cell + "' is past what int64 nanoseconds since 1970 hold (years 1677..2262)");
        ns = __int128(d);
    }
    ns += offset;
    if (ns >= limit || ns < -limit) return makeError("'" + cell + "' plus the time offset is past what int64 nanoseconds hold");
    return TimeNs(ns);
}


const char* fieldName(Field f) {
    switch (f) {
        case Field::Time: return "time";
        case Field::Lat: return "latitude";
        case Field::Lon: return "longitude";
        case Field::Alt: return "altitude";
        default: return "angle";
    }
}

void setField(TrajectorySample& s, Field field, double v) {
    switch (field) {
        case Field::Lat: s.latDeg = v; break;
        case Field::Lon: s.lonDeg = v; break;
        case Field::Alt: s.alt = v; break;
        case Field::Heading: s.headingDeg = v; break;
        case Field::Pitch: s.pitchDeg = v; break;
        case Field::Roll: s.rollDeg = v; break;
        case Field::Time: break;
    }
}

/// The first line that is not blank or a comment (empty when there is none); `pos` and
/// `lineNo` move past it.
std::string_view headerLineOf(std::string_view text, std::size_t& pos, std::size_t& lineNo) {
    std::string_view headerLine;
    while (pos <= text.size() && headerLine.empty()) {
        const std::string_view line = nextLine(text, pos);
        ++lineNo;
        if (!skipLine(line)) headerLine = line;
    }
    return headerLine;
}

/// What the header says about the whole file: the columns nobody reads, what the altitude is
/// above, and the time unit if the time column names one.
void describeColumns(const Header& header, const CsvOptions& options, TrajectoryCsv& csv) {
    for (std::size_t i = 0; i < header.columns.size(); ++i)
        if (std::find(header.index.begin(), header.index.end(), int(i)) == header.index.end()) csv.ignored.push_back(header.names[i]);
    const int altColumn = header.index[std::size_t(Field::Alt)];
    if (altColumn >= 0) {
        const Alias& a = *header.columns[std::size_t(altColumn)].alias;
        csv.altitudeRef = a.ref.value_or(options.altitudeRef);
    }
    csv.timeUnit = header.columns[std::size_t(header.index[std::size_t(Field::Time)])].unitName;
}

/// Reads the data rows under a header, one sample each. The time unit, when the header names
/// none, is fixed by the first time (and kept in `csv.timeUnit`).
class RowReader {
public:
    RowReader(const Header& header, std::size_t headerLineNo, const std::string& name, const CsvOptions& options,
              TrajectoryCsv& csv)
        : header_(header), headerLineNo_(headerLineNo), name_(name), options_(options), csv_(csv),
          timeScale_(header.columns[std::size_t(header.index[std::size_t(Field::Time)])].scale) {}

    Result<TrajectorySample> row(std::string_view line, std::size_t lineNo) {
        auto cells = splitLine(line, header_.sep);
        if (cells.size() > header_.columns.size())
            return makeError(name_ + lineText(lineNo) + ": " + std::to_string(cells.size()) + " cells, the header (line " +
                             std::to_string(headerLineNo_) + ") has " + std::to_string(header_.columns.size()));
        cells.resize(header_.columns.size());   // missing trailing cells: no value
        TrajectorySample s;
        s.line = lineNo;
        s.altRef = csv_.altitudeRef.value_or(AltitudeRef::Ground);
        for (std::size_t f = 0; f < header_.index.size(); ++f) {
            const int col = header_.index[f];
            if (col < 0) continue;
            if (auto r = cell(Field(f), std::size_t(col), cells[std::size_t(col)], lineNo, s); !r) return r.error();
        }
        return s;
    }

private:
    /// Column `c`'s cell into the sample's `field`.
    Result<void> cell(Field field, std::size_t c, std::string& cell, std::size_t lineNo, TrajectorySample& s) {
        const bool required = field == Field::Time || field == Field::Lat || field == Field::Lon || field == Field::Alt;
        if (isNoValue(cell)) {
            if (required)
                return makeError(where(name_, lineNo, c, header_.names[c]) + ": no " + fieldName(field) + " ('" + cell +
                                 "'): every sample needs a time and a position");
            return {};
        }
        if (header_.sep == ';' && cell.find(',') != std::string::npos && cell.find('.') == std::string::npos)
            std::replace(cell.begin(), cell.end(), ',', '.');   // decimal comma
        if (field == Field::Time) {
            auto t = parseTime(cell, timeScale_, csv_.timeUnit, options_.timeOffset);
            if (!t) return makeError(where(name_, lineNo, c, header_.names[c]) + ": " + t.message());
            s.t = *t;
            return {};
        }
        double v = 0.0;
        if (!parseNumber(cell, v)) return makeError(where(name_, lineNo, c, header_.names[c]) + ": '" + cell + "' is not a number");
        setField(s, field, v * header_.columns[c].scale);
        return {};
    }

    const Header& header_;
    const std::size_t headerLineNo_;
    const std::string& name_;
    const CsvOptions& options_;
    TrajectoryCsv& csv_;
    double timeScale_;   // ns per unit of the time column; 0 until the first time fixes it
};

}  // namespace

Result<TrajectoryCsv> parseTrajectoryCsv(std::string_view text, const std::string& name, const CsvOptions& options) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);   // UTF-8 byte order mark
    std::size_t pos = 0, lineNo = 0;
    const std::string_view headerLine = headerLineOf(text, pos, lineNo);
    if (headerLine.empty())
        return makeError(name + ": no header line (a trajectory CSV starts with column names: time, lon, lat, alt, ...)");
    const std::size_t headerLineNo = lineNo;
    auto header = parseHeader(headerLine, name, lineNo);
    if (!header) return header.error();

    TrajectoryCsv csv;
    describeColumns(*header, options, csv);
    RowReader rows(*header, headerLineNo, name, options, csv);
    while (pos <= text.size()) {
        const std::string_view line = nextLine(text, pos);
        ++lineNo;
        if (skipLine(line)) continue;
        auto sample = rows.row(line, lineNo);
        if (!sample) return sample.error();
        csv.samples.push_back(*sample);
    }
    if (csv.samples.empty()) return makeError(name + ": no data rows after the header (line " + std::to_string(headerLineNo) + ")");
    if (csv.timeUnit.empty()) csv.timeUnit.push_back('s');   // (not = "s": GCC 12 warns falsely, bug 105329)
    return csv;
}

Result<TrajectoryCsv> readTrajectoryCsv(const std::string& path, const CsvOptions& options) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return makeError(path + ": cannot read (" + ec.message() + ")");
    if (size > kMaxTrajectoryCsvBytes)
        return makeError(path + ": " + std::to_string(size) + " bytes is more than the " + std::to_string(kMaxTrajectoryCsvBytes >> 20) +
                         " MiB a trajectory CSV may have (split it, or thin its samples)");
    std::ifstream in(path, std::ios::binary);
    std::string text(size, '\0');
    if (!in || !in.read(text.data(), std::streamsize(size))) return makeError(path + ": cannot read the file");
    return parseTrajectoryCsv(text, path, options);
}

}  // namespace orbis::motion
