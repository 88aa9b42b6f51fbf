#include "formats/fmv/PoseCsv.h"

#include "base/CsvText.h"

#include "base/TimeFormat.h"
#include "formats/fmv/St0601Fields.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace orbis::fmv {
namespace {

using csv::isNoValue;
using csv::nextLine;
using csv::skipLine;
using csv::separatorOf;
using csv::splitLine;

enum class Quantity { Time, Angle, Length };
constexpr uint32_t kTime = 0;   // the time column's pseudo-tag

struct Alias {
    uint32_t tag;   // ST 0601 tag the column feeds, kTime for the time
    Quantity quantity;
    std::array<const char*, 12> names;   // normalised (lower-case letters and digits); unused entries null
};

// ST 0601 tags: 5 heading, 90/91 full-range pitch/roll, 13/14/15 sensor position, 75 height
// above the ellipsoid, 16/17 FOV, 18/19/20 sensor relative angles, 21 slant range, 22 target
// width, 23/24/25 frame centre.
const Alias kAliases[] = {
    {kTime, Quantity::Time, {"time", "timestamp", "t", "utc", "datetime", "unixtime", "epoch", "precisiontimestamp", "timeutc", "utctime"}},
    {13, Quantity::Angle, {"lat", "latitude", "sensorlat", "sensorlatitude", "platformlat", "platformlatitude"}},
    {14, Quantity::Angle, {"lon", "long", "lng", "longitude", "sensorlon", "sensorlong", "sensorlng", "sensorlongitude", "platformlon",
                           "platformlong", "platformlongitude"}},
    {15, Quantity::Length, {"alt", "altitude", "altmsl", "altitudemsl", "sensoralt", "sensoraltitude", "sensortruealtitude", "truealtitude",
                            "sensoraltmsl"}},
    {75, Quantity::Length, {"hae", "height", "ellipsoidheight", "heightellipsoid", "sensorhae", "sensorheight", "sensorellipsoidheight",
                            "althae", "altitudehae"}},
    {5, Quantity::Angle, {"heading", "yaw", "platformheading", "platformheadingangle", "platformyaw", "platformyawangle"}},
    {90, Quantity::Angle, {"pitch", "platformpitch", "platformpitchangle"}},
    {91, Quantity::Angle, {"roll", "bank", "platformroll", "platformrollangle"}},
    {18, Quantity::Angle, {"sensorrelativeazimuth", "sensorrelativeazimuthangle", "sensorrelaz", "relaz", "relativeazimuth", "sensoraz",
                           "sensorazimuth", "gimbalpan", "pan", "gimbalazimuth", "gimbalaz"}},
    {19, Quantity::Angle, {"sensorrelativeelevation", "sensorrelativeelevationangle", "sensorrelel", "relel", "relativeelevation",
                           "sensorel", "sensorelevation", "gimbaltilt", "tilt", "gimbalelevation", "gimbalel"}},
    {20, Quantity::Angle, {"sensorrelativeroll", "sensorrelativerollangle", "sensorrelroll", "relroll", "relativeroll", "sensorroll",
                           "gimbalroll"}},
    {16, Quantity::Angle, {"hfov", "horizontalfov", "sensorhfov", "sensorhorizontalfov", "fovh", "fovx", "fovhorizontal",
                           "horizontalfieldofview", "sensorhorizontalfieldofview"}},
    {17, Quantity::Angle, {"vfov", "verticalfov", "sensorvfov", "sensorverticalfov", "fovv", "fovy", "fovvertical",
                           "verticalfieldofview", "sensorverticalfieldofview"}},
    {23, Quantity::Angle, {"framecenterlat", "framecenterlatitude", "framecentrelat", "framecentrelatitude"}},
    {24, Quantity::Angle, {"framecenterlon", "framecenterlong", "framecenterlongitude", "framecentrelon", "framecentrelong",
                           "framecentrelongitude"}},
    {25, Quantity::Length, {"framecenterelevation", "framecenteralt", "framecenteraltitude", "framecentreelevation", "framecentrealt",
                            "framecentrealtitude"}},
    {21, Quantity::Length, {"slantrange"}},
    {22, Quantity::Length, {"targetwidth"}},
};

struct Unit {
    const char* suffix;
    Quantity quantity;
    double scale;   // to degrees, metres, or (time) to µs; 0 for a time without a stated unit
};
// Longest suffixes first, so "seconds" is not read as "second" + "s".
const Unit kUnits[] = {
    {"microseconds", Quantity::Time, 1.0},       {"milliseconds", Quantity::Time, 1e3}, {"seconds", Quantity::Time, 1e6},
    {"degrees", Quantity::Angle, 1.0},           {"radians", Quantity::Angle, 180.0 / std::numbers::pi},
    {"meters", Quantity::Length, 1.0},           {"metres", Quantity::Length, 1.0},     {"degree", Quantity::Angle, 1.0},
    {"radian", Quantity::Angle, 180.0 / std::numbers::pi},
    {"meter", Quantity::Length, 1.0},            {"metre", Quantity::Length, 1.0},      {"feet", Quantity::Length, 0.3048},
    {"usec", Quantity::Time, 1.0},               {"msec", Quantity::Time, 1e3},         {"secs", Quantity::Time, 1e6},
    {"sec", Quantity::Time, 1e6},                {"deg", Quantity::Angle, 1.0},         {"rad", Quantity::Angle, 180.0 / std::numbers::pi},
    {"ft", Quantity::Length, 0.3048},            {"us", Quantity::Time, 1.0},           {"ms", Quantity::Time, 1e3},
    {"m", Quantity::Length, 1.0},                {"s", Quantity::Time, 1e6},
};

struct Column {
    const Alias* alias = nullptr;   // nullptr: ignored
    double scale = 1.0;             // see Unit::scale
};

Column columnOf(std::string_view header) {
    const auto [a, u] = csv::matchColumn<Alias, Unit>(kAliases, kUnits, header);
    if (!a) return {};
    return {a, u ? u->scale : a->quantity == Quantity::Time ? 0.0 : 1.0};
}


struct Header {
    char sep = ',';
    std::vector<Column> columns;
    std::vector<std::string> names;
};

/// The header's columns, or an error naming what is missing or given twice.
Result<Header> parseHeader(std::string_view line, const std::string& name, std::size_t lineNo) {
    Header h;
    h.sep = separatorOf(line);
    h.names = splitLine(line, h.sep);
    for (std::size_t i = 0; i < h.names.size(); ++i) {
        h.columns.push_back(columnOf(h.names[i]));
        for (std::size_t k = 0; k < i; ++k)
            if (h.columns[i].alias && h.columns[k].alias == h.columns[i].alias)
                return makeError(std::string(name).append(": line ").append(std::to_string(lineNo)).append(": columns ")
                                     .append(std::to_string(k + 1)).append(" (").append(h.names[k]).append(") and ")
                                     .append(std::to_string(i + 1)).append(" (").append(h.names[i]).append(") give the same value"));
    }
    auto has = [&](uint32_t tag) {
        return std::any_of(h.columns.begin(), h.columns.end(), [&](const Column& c) { return c.alias && c.alias->tag == tag; });
    };
    std::string missing;
    auto need = [&](bool ok, const char* what, const char* accepted) {
        if (!ok) missing.append(missing.empty() ? "" : "; ").append(what).append(" (").append(accepted).append(")");
    };
    need(has(kTime), "time", "time, timestamp, utc, t, ...");
    need(has(13), "latitude", "lat, latitude, sensor latitude, ...");
    need(has(14), "longitude", "lon, long, longitude, sensor longitude, ...");
    need(has(15) || has(75), "altitude or height", "alt, altitude, sensor true altitude, hae, height, ...");
    if (!missing.empty())
        return makeError(std::string(name).append(": line ").append(std::to_string(lineNo)).append(": no column for ").append(missing)
                             .append(" (see formats/fmv/PoseCsv.h for every name accepted)"));
    return h;
}

std::string where(const std::string& name, std::size_t line, std::size_t col, const std::string& header) {
    return std::string(name).append(": line ").append(std::to_string(line)).append(", column ").append(std::to_string(col + 1))
        .append(" (").append(header).append(")");
}

bool parseNumber(const std::string& s, double& out) {
    const char* end = s.data() + s.size();
    const auto r = std::from_chars(s.data(), end, out);
    return r.ec == std::errc() && r.ptr == end && std::isfinite(out);
}

/// The time cell as µs since 1970. `scale` (µs per unit) is fixed by the first number when the
/// header named no unit.
Result<uint64_t> parseTime(const std::string& cell, double& scale, std::string& unit) {
    double v = 0.0;
    if (!parseNumber(cell, v)) {
        auto t = parseIso8601(cell);
        if (!t) return makeError(std::string("'").append(cell).append("' is neither a number nor an ISO 8601 time"));
        if (*t < 0) return makeError(std::string("'").append(cell).append("' is before 1970"));
        if (unit.empty()) unit = "iso8601";
        return uint64_t(*t / 1000);
    }
    if (scale == 0.0) scale = std::abs(v) >= 1e14 ? 1.0 : std::abs(v) >= 1e11 ? 1e3 : 1e6;
    if (unit.empty()) unit = scale == 1.0 ? "us" : scale == 1e3 ? "ms" : "s";
    const double us = std::round(v * scale);
    if (us < 0.0) return makeError(std::string("'").append(cell).append("' is before 1970"));
    if (us >= 1.8e19) return makeError(std::string("'").append(cell).append("' is past what µs since 1970 in 64 bits hold"));
    return uint64_t(us);
}


}  // namespace

Result<PoseCsv> parsePoseCsv(std::string_view text, const std::string& name) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);   // UTF-8 byte order mark
    std::size_t pos = 0, lineNo = 0;
    std::string_view headerLine;
    while (pos <= text.size() && headerLine.empty()) {
        std::string_view line = nextLine(text, pos);
        ++lineNo;
        if (!skipLine(line)) headerLine = line;
    }
    if (headerLine.empty()) return makeError(std::string(name).append(": no header line (a pose CSV starts with column names)"));
    auto header = parseHeader(headerLine, name, lineNo);
    if (!header) return header.error();

    PoseCsv csv;
    for (std::size_t i = 0; i < header->columns.size(); ++i) {
        const Column& c = header->columns[i];
        csv.columns.push_back(!c.alias ? "" : c.alias->tag == kTime ? "precisionTimeUs" : st0601TagName(c.alias->tag));
        if (!c.alias) csv.ignored.push_back(header->names[i]);
    }
    double timeScale = 0.0;
    for (const Column& c : header->columns)
        if (c.alias && c.alias->tag == kTime) timeScale = c.scale;
    while (pos <= text.size()) {
        const std::string_view line = nextLine(text, pos);
        ++lineNo;
        if (skipLine(line)) continue;
        const auto cells = splitLine(line, header->sep);
        if (cells.size() > header->columns.size())
            return makeError(std::string(name).append(": line ").append(std::to_string(lineNo)).append(": ").append(std::to_string(cells.size()))
                                 .append(" cells, the header has ").append(std::to_string(header->columns.size())));
        PoseSample s;
        s.line = lineNo;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const Column& c = header->columns[i];
            if (!c.alias || isNoValue(cells[i])) continue;
            if (c.alias->tag == kTime) {
                auto t = parseTime(cells[i], timeScale, csv.timeUnit);
                if (!t) return makeError(where(name, lineNo, i, header->names[i]).append(": ").append(t.message()));
                s.pose.precisionTimeUs = *t;
                continue;
            }
            double v = 0.0;
            if (!parseNumber(cells[i], v))
                return makeError(where(name, lineNo, i, header->names[i]).append(": '").append(cells[i]).append("' is not a number"));
            detail::findField(c.alias->tag)->numberIn(s.pose) = v * c.scale;
        }
        if (!s.pose.precisionTimeUs)
            return makeError(std::string(name).append(": line ").append(std::to_string(lineNo)).append(": no time"));
        csv.samples.push_back(std::move(s));
    }
    if (csv.timeUnit.empty()) csv.timeUnit = timeScale == 1.0 ? "us" : timeScale == 1e3 ? "ms" : "s";
    return csv;
}

Result<PoseCsv> readPoseCsv(const std::string& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return makeError(std::string(path).append(": cannot read (").append(ec.message()).append(")"));
    if (size > kMaxPoseCsvBytes)
        return makeError(std::string(path).append(": ").append(std::to_string(size)).append(" bytes is more than the ")
                             .append(std::to_string(kMaxPoseCsvBytes >> 20)).append(" MiB a pose CSV may have"));
    std::ifstream in(path, std::ios::binary);
    std::string text(size, '\0');
    if (!in || !in.read(text.data(), std::streamsize(size))) return makeError(std::string(path).append(": cannot read the file"));
    return parsePoseCsv(text, path);
}

bool looksLikePoseCsv(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string text(64 * 1024, '\0');
    in.read(text.data(), std::streamsize(text.size()));
    text.resize(std::size_t(in.gcount()));
    std::size_t pos = 0, lineNo = 0;
    while (pos < text.size()) {
        const std::string_view line = nextLine(text, pos);
        ++lineNo;
        if (!skipLine(line)) return parseHeader(line, path, lineNo).ok();
    }
    return false;
}

}  // namespace orbis::fmv
