#include "layers/volume/VolumeReader.h"

#include "base/Utf8.h"
#include "globe/GdalSetup.h"

#include <cpl_error.h>
#include <gdal_priv.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

namespace orbis::layers {
namespace {

// ---------------------------------------------------------------------------------------------
// GDAL plumbing

/// GDAL's messages on this thread are kept quiet while it lives; the last one explains failures.
struct QuietGdal {
    QuietGdal() {
        CPLPushErrorHandler(CPLQuietErrorHandler);
        CPLErrorReset();
    }
    ~QuietGdal() { CPLPopErrorHandler(); }
    static std::string last(const char* fallback) {
        const char* m = CPLGetLastErrorMsg();
        return m && *m ? std::string(m) : std::string(fallback);
    }
};

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string stringAttribute(const GDALIHasAttribute& object, const char* name) {
    const auto a = object.GetAttribute(name);
    if (!a) return {};
    const char* s = a->ReadAsString();
    return s ? std::string(s) : std::string();
}

std::vector<double> doubleAttribute(const GDALIHasAttribute& object, const char* name) {
    const auto a = object.GetAttribute(name);
    if (!a || a->GetDataType().GetClass() != GEDTC_NUMERIC) return {};
    return a->ReadAsDoubleArray();
}

/// A whole 1-D array as doubles.
std::optional<std::vector<double>> readAll1d(const GDALMDArray& array) {
    const auto& dims = array.GetDimensions();
    if (dims.size() != 1) return std::nullopt;
    std::vector<double> v(size_t(dims[0]->GetSize()));
    const GUInt64 start = 0;
    const size_t count = v.size();
    if (!array.Read(&start, &count, nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), v.data()))
        return std::nullopt;
    return v;
}

std::shared_ptr<GDALMDArray> findArray(const std::shared_ptr<GDALGroup>& group, const std::string& name,
                                       std::vector<std::string>& found) {
    std::shared_ptr<GDALMDArray> first;
    if (auto a = group->OpenMDArray(name)) {
        found.push_back(a->GetFullName());
        first = a;
    }
    for (const auto& sub : group->GetGroupNames())
        if (auto g = group->OpenGroup(sub))
            if (auto a = findArray(g, name, found); a && !first) first = a;
    return first;
}

void forEachArray(const std::shared_ptr<GDALGroup>& group,
                  const std::function<void(const std::shared_ptr<GDALMDArray>&)>& f) {
    for (const auto& name : group->GetMDArrayNames())
        if (auto a = group->OpenMDArray(name)) f(a);
    for (const auto& sub : group->GetGroupNames())
        if (auto g = group->OpenGroup(sub)) forEachArray(g, f);
}

// ---------------------------------------------------------------------------------------------
// Axes

enum class Axis { Lon, Lat, Vertical, Time, Other };

const char* axisName(Axis a) {
    switch (a) {
        case Axis::Lon: return "lon";
        case Axis::Lat: return "lat";
        case Axis::Vertical: return "vertical";
        case Axis::Time: return "time";
        default: return "other";
    }
}

bool isPressureUnit(const std::string& u) {
    return u == "pa" || u == "hpa" || u == "mbar" || u == "millibar" || u == "mb" || u == "kpa";
}
bool isLengthUnit(const std::string& u) {
    return u == "m" || u == "meter" || u == "meters" || u == "metre" || u == "metres" || u == "km";
}

/// Classifies a dimension from its coordinate variable's CF attributes, then GDAL's dimension
/// type, then its name.
Axis classify(const GDALDimension& dim) {
    const auto var = dim.GetIndexingVariable();
    const std::string name = lower(dim.GetName());
    std::string axis, standard, units, positive;
    if (var) {
        axis = lower(stringAttribute(*var, "axis"));
        standard = lower(stringAttribute(*var, "standard_name"));
        units = lower(var->GetUnit());
        if (units.empty()) units = lower(stringAttribute(*var, "units"));
        positive = lower(stringAttribute(*var, "positive"));
    }
    if (axis == "x" || standard == "longitude" || units == "degrees_east" || units == "degree_east" ||
        units == "degree_e" || units == "degrees_e")
        return Axis::Lon;
    if (axis == "y" || standard == "latitude" || units == "degrees_north" || units == "degree_north" ||
        units == "degree_n" || units == "degrees_n")
        return Axis::Lat;
    if (axis == "t" || standard == "time" || units.find(" since ") != std::string::npos) return Axis::Time;
    if (axis == "z" || !positive.empty() || standard == "air_pressure" || standard == "height" ||
        standard == "altitude" || standard == "depth" || isPressureUnit(units))
        return Axis::Vertical;
    const std::string type = dim.GetType();
    if (type == "HORIZONTAL_X") return Axis::Lon;
    if (type == "HORIZONTAL_Y") return Axis::Lat;
    if (type == "VERTICAL") return Axis::Vertical;
    if (type == "TEMPORAL") return Axis::Time;
    if (name == "lon" || name == "longitude") return Axis::Lon;
    if (name == "lat" || name == "latitude") return Axis::Lat;
    if (name == "lev" || name == "level" || name == "plev" || name == "height" || name == "depth" || name == "z" ||
        name == "alt" || name == "altitude")
        return Axis::Vertical;
    if (name == "time" || name == "t") return Axis::Time;
    return Axis::Other;
}

bool strictlyMonotonic(const std::vector<double>& v, bool* ascending) {
    if (v.empty() || !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); })) return false;
    if (v.size() == 1) {
        *ascending = true;
        return true;
    }
    *ascending = v[1] > v[0];
    for (size_t i = 1; i < v.size(); ++i)
        if (*ascending ? !(v[i] > v[i - 1]) : !(v[i] < v[i - 1])) return false;
    return true;
}

// ---------------------------------------------------------------------------------------------
// CF time

/// "2001-1-1 0:0:0" and friends to ISO 8601 for parseIso8601.
std::optional<std::string> normaliseCfDate(std::string text) {
    text = trim(text);
    int y = 0, mo = 0, d = 0, h = 0, mi = 0;
    double s = 0.0;
    char rest[64] = {};
    const int n = std::sscanf(text.c_str(), "%d-%d-%d%*[ T]%d:%d:%lf%63s", &y, &mo, &d, &h, &mi, &s, rest);
    if (n < 3) return std::nullopt;
    std::string zone = n >= 7 ? std::string(rest) : std::string();
    if (zone == "UTC" || zone == "utc" || zone == "GMT") zone = "Z";
    char buf[96];
    const int whole = int(std::floor(s));
    const double frac = s - whole;
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d", y, mo, d, n >= 4 ? h : 0, n >= 5 ? mi : 0,
                  n >= 6 ? whole : 0);
    std::string iso = buf;
    if (frac > 0.0) {
        char f[16];
        std::snprintf(f, sizeof f, "%.6f", frac);
        iso += std::string(f).substr(1);
    }
    return iso + (zone.empty() ? "Z" : zone);
}

// ---------------------------------------------------------------------------------------------
// The standard atmosphere (US 1976), geopotential heights

struct AtmosphereLayer {
    double base, temperature, lapse, pressure;   // m, K, K/m, Pa
};
constexpr AtmosphereLayer kAtmosphere[] = {
    {0.0, 288.15, -0.0065, 101325.0},   {11000.0, 216.65, 0.0, 22632.06},   {20000.0, 216.65, 0.001, 5474.889},
    {32000.0, 228.65, 0.0028, 868.0187}, {47000.0, 270.65, 0.0, 110.9063},   {51000.0, 270.65, -0.0028, 66.93887},
    {71000.0, 214.65, -0.002, 3.956420},
};
constexpr double kGMR = 9.80665 * 0.0289644 / 8.3144598;   // g0 M / R*, K/m

double pressureInLayer(const AtmosphereLayer& l, double h) {
    if (l.lapse == 0.0) return l.pressure * std::exp(-kGMR * (h - l.base) / l.temperature);
    return l.pressure * std::pow(l.temperature / (l.temperature + l.lapse * (h - l.base)), kGMR / l.lapse);
}

double heightInLayer(const AtmosphereLayer& l, double p) {
    if (l.lapse == 0.0) return l.base - l.temperature / kGMR * std::log(p / l.pressure);
    return l.base + l.temperature / l.lapse * (std::pow(p / l.pressure, -l.lapse / kGMR) - 1.0);
}

}  // namespace

double standardAtmosphereHeight(double pascals) {
    const size_t n = std::size(kAtmosphere);
    for (size_t i = n; i-- > 0;)
        if (pascals <= kAtmosphere[i].pressure || i == 0) return heightInLayer(kAtmosphere[i], pascals);
    return 0.0;
}

double standardAtmospherePressure(double metres) {
    const size_t n = std::size(kAtmosphere);
    for (size_t i = n; i-- > 0;)
        if (metres >= kAtmosphere[i].base || i == 0) return pressureInLayer(kAtmosphere[i], metres);
    return kAtmosphere[0].pressure;
}

Result<CfTimeUnits> parseCfTimeUnits(const std::string& units) {
    const std::string u = lower(trim(units));
    const auto since = u.find(" since ");
    if (since == std::string::npos) return makeError("time units \"" + units + "\" have no reference date (\"<unit> since <date>\")");
    const std::string unit = trim(u.substr(0, since));
    CfTimeUnits out;
    if (unit == "seconds" || unit == "second" || unit == "secs" || unit == "sec" || unit == "s") out.secondsPerUnit = 1.0;
    else if (unit == "minutes" || unit == "minute" || unit == "mins" || unit == "min") out.secondsPerUnit = 60.0;
    else if (unit == "hours" || unit == "hour" || unit == "hrs" || unit == "hr" || unit == "h") out.secondsPerUnit = 3600.0;
    else if (unit == "days" || unit == "day" || unit == "d") out.secondsPerUnit = 86400.0;
    else
        return makeError("time unit \"" + unit + "\" in \"" + units +
                         "\" is not supported (seconds, minutes, hours or days; months and years have no fixed length)");
    const auto date = normaliseCfDate(units.substr(since + 7));
    if (!date) return makeError("cannot read the reference date in time units \"" + units + "\"");
    auto t = parseIso8601(*date);
    if (!t) return makeError("reference date in time units \"" + units + "\": " + t.message());
    out.reference = *t;
    return out;
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

struct Placed {
    Axis axis = Axis::Other;
    std::shared_ptr<GDALDimension> dim;
    size_t size = 0;
};

struct Context {
    std::string file, variable;
    Error error(const std::string& what) const { return makeError(file + ": variable \"" + variable + "\": " + what); }
};

/// The variable's dimensions, each placed on an axis, and which one is lon, lat, vertical, time.
struct Dimensions {
    std::vector<Placed> placed;   ///< in the file's order
    int index[5] = {-1, -1, -1, -1, -1};   ///< by Axis: the dimension's position, -1 for none
    bool has(Axis a) const { return index[int(a)] >= 0; }
    const Placed& of(Axis a) const { return placed[size_t(index[int(a)])]; }
};

/// An axis's coordinates in ascending order, and whether the file had them so.
struct Coordinates {
    std::vector<double> values;
    bool ascending = true;
};

Result<std::shared_ptr<GDALMDArray>> openVariable(GDALDataset& ds, const std::string& file, const std::string& variable,
                                                  std::string* fullName) {
    const auto root = ds.GetRootGroup();
    if (!root) return makeError(file + ": GDAL opens it but finds no groups or variables");
    std::shared_ptr<GDALMDArray> array;
    if (!variable.empty() && variable.front() == '/') {
        array = root->OpenMDArrayFromFullname(variable);
    } else {
        std::vector<std::string> found;
        array = findArray(root, variable, found);
        if (found.size() > 1) {
            std::string list;
            for (const auto& f : found) list += (list.empty() ? "" : ", ") + f;
            return makeError(file + ": variable \"" + variable + "\" is in several groups (" + list +
                             "): give the full name");
        }
    }
    if (!array) {
        std::string names;
        forEachArray(root, [&](const std::shared_ptr<GDALMDArray>& a) {
            if (a->GetDimensionCount() >= 3) names += (names.empty() ? "" : ", ") + a->GetFullName();
        });
        return makeError(file + ": no variable \"" + variable + "\"" +
                         (names.empty() ? std::string(" (and no variable with 3 or more dimensions)")
                                        : " (volume variables: " + names + ")"));
    }
    *fullName = array->GetFullName();
    return array;
}

GDALDatasetUniquePtr openMultidim(const std::string& path, std::string* error) {
    if (!std::filesystem::exists(path)) {
        *error = path + ": no such file";
        return nullptr;
    }
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_MULTIDIM_RASTER | GDAL_OF_READONLY));
    if (!ds) *error = path + ": not a multidimensional file GDAL can read (" + QuietGdal::last("unknown format") + ")";
    return ds;
}

/// Places every dimension of the variable on an axis; errors for two dimensions on one axis, a
/// dimension that cannot be placed, or a missing lon, lat or vertical.
Result<Dimensions> placeDimensions(const GDALMDArray& array, const Context& ctx) {
    const auto& dims = array.GetDimensions();
    if (dims.size() < 3)
        return ctx.error("has " + std::to_string(dims.size()) +
                         " dimension(s): a volume needs longitude, latitude and a vertical dimension");
    Dimensions out;
    for (size_t d = 0; d < dims.size(); ++d) {
        Placed p{classify(*dims[d]), dims[d], size_t(dims[d]->GetSize())};
        const int a = int(p.axis);
        if (p.axis != Axis::Other && out.index[a] >= 0)
            return ctx.error("dimensions \"" + dims[size_t(out.index[a])]->GetName() + "\" and \"" + dims[d]->GetName() +
                             "\" both look like " + axisName(p.axis));
        if (p.axis == Axis::Other && p.size > 1)
            return ctx.error("cannot place dimension \"" + dims[d]->GetName() + "\" (size " + std::to_string(p.size) +
                             "): it is not longitude, latitude, vertical or time by its CF attributes");
        if (p.axis != Axis::Other) out.index[a] = int(d);
        out.placed.push_back(p);
    }
    for (Axis need : {Axis::Lon, Axis::Lat, Axis::Vertical})
        if (!out.has(need)) {
            std::string names;
            for (const auto& d : dims) names += (names.empty() ? "" : ", ") + d->GetName();
            return ctx.error(std::string("has no ") + axisName(need) + " dimension (dimensions: " + names + ")");
        }
    return out;
}

/// The coordinate variable of an axis's dimension, unpacked (packed coordinates are rare but legal).
Result<std::vector<double>> readCoordinate(const Dimensions& dims, Axis a, const Context& ctx) {
    const auto& dim = dims.of(a).dim;
    const auto var = dim->GetIndexingVariable();
    if (!var) return ctx.error("dimension \"" + dim->GetName() + "\" has no coordinate variable");
    auto v = readAll1d(*var);
    if (!v) return ctx.error("cannot read coordinate \"" + dim->GetName() + "\": " + QuietGdal::last("read failed"));
    bool hasScale = false, hasOffset = false;
    const double scale = var->GetScale(&hasScale), offset = var->GetOffset(&hasOffset);
    if (hasScale || hasOffset)
        for (double& x : *v) x = x * (hasScale ? scale : 1.0) + (hasOffset ? offset : 0.0);
    return *v;
}

/// Longitudes, ascending and continuous (each step forward by 0 < d <= 360, starting in
/// [-180, 180)); `wraps` when they cover the whole circle.
Result<Coordinates> readLongitudes(const Dimensions& dims, const Context& ctx, bool* wraps) {
    auto lon = readCoordinate(dims, Axis::Lon, ctx);
    if (!lon) return lon.error();
    std::vector<double>& v = *lon;
    const bool ascending = !(v.size() > 1 && v[1] < v[0]);
    if (!ascending) std::reverse(v.begin(), v.end());
    for (double x : v)
        if (!std::isfinite(x)) return ctx.error("longitude has non-finite values");
    v[0] = std::remainder(v[0], 360.0);
    if (v[0] >= 180.0) v[0] -= 360.0;
    for (size_t i = 1; i < v.size(); ++i) {
        double d = std::remainder(v[i] - v[i - 1], 360.0);
        if (d <= 0.0) d += 360.0;
        v[i] = v[i - 1] + d;
    }
    const double span = v.back() - v.front();
    if (span > 360.0 + 1e-9) return ctx.error("longitudes span more than 360 degrees (not monotonic?)");
    *wraps = false;
    if (v.size() > 1) *wraps = span + span / double(v.size() - 1) >= 360.0 - 1e-6 * 360.0;
    return Coordinates{std::move(v), ascending};
}

/// Latitudes, ascending, within the poles.
Result<Coordinates> readLatitudes(const Dimensions& dims, const Context& ctx) {
    auto lat = readCoordinate(dims, Axis::Lat, ctx);
    if (!lat) return lat.error();
    bool ascending = true;
    if (!strictlyMonotonic(*lat, &ascending)) return ctx.error("latitudes are not strictly monotonic");
    if (!ascending) std::reverse(lat->begin(), lat->end());
    if (lat->front() < -90.0 - 1e-9 || lat->back() > 90.0 + 1e-9) return ctx.error("latitudes outside -90 .. 90");
    return Coordinates{std::move(*lat), ascending};
}

/// The vertical levels as heights (m), ascending: pressures through `pressureToHeight`, depths
/// negated, kilometres scaled. Sets out.verticalSource, verticalUnits and verticalRaw (the
/// file's values in the order of the heights).
Result<Coordinates> readVertical(const Dimensions& dims, const Context& ctx, PressureToHeight pressureToHeight,
                                 VolumeField& out) {
    const auto& vdim = dims.of(Axis::Vertical).dim;
    auto vert = readCoordinate(dims, Axis::Vertical, ctx);
    if (!vert) return vert.error();
    const auto vvar = vdim->GetIndexingVariable();
    std::string vunits = lower(trim(vvar->GetUnit()));
    if (vunits.empty()) vunits = lower(trim(stringAttribute(*vvar, "units")));
    out.verticalUnits = vvar->GetUnit();
    std::vector<double> heights(vert->size());
    if (isPressureUnit(vunits)) {
        out.verticalSource = VerticalSource::Pressure;
        const double toPa = vunits == "pa" ? 1.0 : vunits == "kpa" ? 1000.0 : 100.0;
        for (size_t k = 0; k < vert->size(); ++k) {
            const double p = (*vert)[k] * toPa;
            if (!(p > 0.0)) return ctx.error("pressure level " + std::to_string((*vert)[k]) + " " + vvar->GetUnit() + " is not positive");
            heights[k] = pressureToHeight == PressureToHeight::StandardAtmosphere ? standardAtmosphereHeight(p)
                                                                                  : 7000.0 * std::log(101325.0 / p);
        }
    } else if (isLengthUnit(vunits)) {
        const double toM = vunits == "km" ? 1000.0 : 1.0;
        const bool down = lower(stringAttribute(*vvar, "positive")) == "down" ||
                          lower(stringAttribute(*vvar, "standard_name")) == "depth";
        out.verticalSource = down ? VerticalSource::Depth : VerticalSource::Height;
        for (size_t k = 0; k < vert->size(); ++k) heights[k] = (down ? -1.0 : 1.0) * (*vert)[k] * toM;
    } else {
        return ctx.error("cannot place the vertical dimension \"" + vdim->GetName() + "\": units \"" +
                         vvar->GetUnit() + "\" are neither a pressure (Pa, hPa) nor a length (m, km)");
    }
    bool ascending = true;
    if (!strictlyMonotonic(heights, &ascending)) return ctx.error("vertical levels are not strictly monotonic");
    if (!ascending) {
        std::reverse(heights.begin(), heights.end());
        std::reverse(vert->begin(), vert->end());
    }
    out.verticalRaw = std::move(*vert);
    return Coordinates{std::move(heights), ascending};
}

/// The time dimension, if any: out.timeSteps, timeIndex and the steps' UTC instants (CF units on
/// the standard/Gregorian calendars; none otherwise).
Result<void> readTimes(const Dimensions& dims, const Context& ctx, size_t timeIndex, VolumeField& out) {
    if (!dims.has(Axis::Time)) return {};
    const Placed& tdim = dims.of(Axis::Time);
    out.timeSteps = tdim.size;
    if (timeIndex >= tdim.size)
        return ctx.error("time step " + std::to_string(timeIndex) + " does not exist (" + std::to_string(tdim.size) +
                         " steps)");
    out.timeIndex = timeIndex;
    const auto tvar = tdim.dim->GetIndexingVariable();
    if (!tvar) return {};
    std::string tunits = tvar->GetUnit();
    if (tunits.empty()) tunits = stringAttribute(*tvar, "units");
    const std::string calendar = lower(stringAttribute(*tvar, "calendar"));
    const bool gregorian = calendar.empty() || calendar == "standard" || calendar == "gregorian" ||
                           calendar == "proleptic_gregorian";
    auto cf = parseCfTimeUnits(tunits);
    auto values = readAll1d(*tvar);
    if (cf && gregorian && values)
        for (double v : *values) out.times.push_back(cf->reference + fromSeconds(v * cf->secondsPerUnit));
    return {};
}

/// One time step of the whole variable in the file's order, as doubles (after a size check).
Result<std::vector<double>> readRaw(const GDALMDArray& array, const Dimensions& dims, const Context& ctx,
                                    const VolumeReadOptions& options, size_t nx, size_t ny, size_t nz) {
    const long double bytes = (long double)nx * ny * nz * (sizeof(double) + sizeof(float));
    if (bytes > (long double)options.maxBytes)
        return ctx.error("needs " + std::to_string(uint64_t(bytes / 1048576.0L)) + " MB to read (" + std::to_string(nx) +
                         " x " + std::to_string(ny) + " x " + std::to_string(nz) + "), more than the budget of " +
                         std::to_string(options.maxBytes >> 20) + " MB");
    std::vector<GUInt64> start(dims.placed.size(), 0);
    std::vector<size_t> count(dims.placed.size(), 1);
    for (size_t d = 0; d < dims.placed.size(); ++d) {
        if (dims.placed[d].axis == Axis::Time) start[d] = options.timeIndex;
        else count[d] = dims.placed[d].size;
    }
    std::vector<double> raw;
    try {
        raw.resize(nx * ny * nz);
    } catch (const std::bad_alloc&) {
        return ctx.error("out of memory for " + std::to_string(nx * ny * nz) + " values");
    }
    if (!array.Read(start.data(), count.data(), nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), raw.data()))
        return ctx.error("cannot be read (truncated or corrupt?): " + QuietGdal::last("read failed"));
    return raw;
}

/// The variable's no-data rules (tested in the packed, file space) and its packing.
struct Packing {
    bool hasNoData = false;
    double noData = 0.0;
    std::vector<double> missing;
    double lo = -HUGE_VAL, hi = HUGE_VAL;   // valid_range / valid_min / valid_max
    double scale = 1.0, offset = 0.0;

    explicit Packing(const GDALMDArray& array) {
        noData = array.GetNoDataValueAsDouble(&hasNoData);
        missing = doubleAttribute(array, "missing_value");
        const std::vector<double> range = doubleAttribute(array, "valid_range");
        const std::vector<double> vmin = doubleAttribute(array, "valid_min"), vmax = doubleAttribute(array, "valid_max");
        lo = range.size() == 2 ? range[0] : vmin.empty() ? -HUGE_VAL : vmin[0];
        hi = range.size() == 2 ? range[1] : vmax.empty() ? HUGE_VAL : vmax[0];
        bool hasScale = false, hasOffset = false;
        const double s = array.GetScale(&hasScale), o = array.GetOffset(&hasOffset);
        scale = hasScale ? s : 1.0, offset = hasOffset ? o : 0.0;
    }
    /// The value of a raw number: NaN for no data.
    float unpack(double r) const {
        bool valid = std::isfinite(r) && !(hasNoData && r == noData) && r >= lo && r <= hi;
        for (double m : missing) valid = valid && r != m;
        if (!valid) return std::numeric_limits<float>::quiet_NaN();
        const float v = float(r * scale + offset);
        return std::isfinite(v) ? v : std::numeric_limits<float>::quiet_NaN();
    }
};

/// Scatters `raw` (the file's order) into out.values (lon fastest, then lat, then height, each
/// ascending), unpacked, with the range and count of the valid values.
void storeValues(const std::vector<double>& raw, const Dimensions& dims, const Packing& packing,
                 const bool ascending[3], VolumeField& out) {
    const size_t nx = out.nx(), ny = out.ny(), nz = out.nz();
    std::vector<size_t> stride(dims.placed.size(), 1);
    for (size_t d = dims.placed.size(); d-- > 1;)
        stride[d - 1] = stride[d] * (dims.placed[d].axis == Axis::Time ? 1 : dims.placed[d].size);
    const size_t sLon = stride[size_t(dims.index[int(Axis::Lon)])], sLat = stride[size_t(dims.index[int(Axis::Lat)])],
                 sVert = stride[size_t(dims.index[int(Axis::Vertical)])];
    out.values.resize(nx * ny * nz);
    float vMin = std::numeric_limits<float>::max(), vMax = -vMin;
    for (size_t k = 0; k < nz; ++k) {
        const size_t fk = ascending[2] ? k : nz - 1 - k;
        for (size_t j = 0; j < ny; ++j) {
            const size_t fj = ascending[1] ? j : ny - 1 - j;
            for (size_t i = 0; i < nx; ++i) {
                const size_t fi = ascending[0] ? i : nx - 1 - i;
                const float v = packing.unpack(raw[fk * sVert + fj * sLat + fi * sLon]);
                if (std::isfinite(v)) {
                    vMin = std::min(vMin, v);
                    vMax = std::max(vMax, v);
                    ++out.validCount;
                }
                out.values[(k * ny + j) * nx + i] = v;
            }
        }
    }
    if (out.validCount) out.minValue = vMin, out.maxValue = vMax;
}

}  // namespace

namespace {

/// A variable opened for reading: its grid placed and read (field holds everything but the
/// values), ready to read any of its time steps through the same open dataset.
struct OpenedVolume {
    GDALDatasetUniquePtr ds;
    std::shared_ptr<GDALMDArray> array;
    Dimensions dims;
    Context ctx;
    bool ascending[3] = {true, true, true};
    VolumeField field;
};

Result<OpenedVolume> openVolume(const VolumeReadOptions& options) {
    std::string openError;
    OpenedVolume v;
    v.ds = openMultidim(options.path, &openError);
    if (!v.ds) return makeError(openError);
    auto opened = openVariable(*v.ds, options.path, options.variable, &v.field.variable);
    if (!opened) return opened.error();
    v.array = std::move(opened).value();
    v.ctx = Context{options.path, v.field.variable};

    auto dims = placeDimensions(*v.array, v.ctx);
    if (!dims) return dims.error();
    v.dims = std::move(dims).value();
    auto lon = readLongitudes(v.dims, v.ctx, &v.field.lonWraps);
    if (!lon) return lon.error();
    auto lat = readLatitudes(v.dims, v.ctx);
    if (!lat) return lat.error();
    auto heights = readVertical(v.dims, v.ctx, options.pressureToHeight, v.field);
    if (!heights) return heights.error();
    if (auto times = readTimes(v.dims, v.ctx, options.timeIndex, v.field); !times) return times.error();
    v.field.units = v.array->GetUnit();
    v.field.longName = stringAttribute(*v.array, "long_name");
    v.ascending[0] = lon->ascending, v.ascending[1] = lat->ascending, v.ascending[2] = heights->ascending;
    v.field.lonDeg = std::move(lon->values);
    v.field.latDeg = std::move(lat->values);
    v.field.heightM = std::move(heights->values);
    return v;
}

/// One time step's values (with their range and count) into `out`, which has the grid.
Result<void> readTimeStep(const OpenedVolume& v, const VolumeReadOptions& options, size_t timeIndex, VolumeField& out) {
    VolumeReadOptions step = options;
    step.timeIndex = timeIndex;
    auto raw = readRaw(*v.array, v.dims, v.ctx, step, out.nx(), out.ny(), out.nz());
    if (!raw) return raw.error();
    out.values.clear();
    out.validCount = 0;
    out.minValue = out.maxValue = 0.0f;
    storeValues(*raw, v.dims, Packing(*v.array), v.ascending, out);
    return {};
}

}  // namespace

Result<VolumeField> readVolume(const VolumeReadOptions& options) {
    globe::configureGdal();
    QuietGdal quiet;
    auto v = openVolume(options);
    if (!v) return v.error();
    if (auto read = readTimeStep(*v, options, options.timeIndex, v->field); !read) return read.error();
    return std::move(v->field);
}

Result<VolumeTimeSteps> readVolumeTimeSteps(const VolumeReadOptions& options,
                                            const std::function<Result<bool>(const VolumeField&)>& readAll) {
    globe::configureGdal();
    QuietGdal quiet;
    auto v = openVolume(options);
    if (!v) return v.error();
    VolumeTimeSteps out;
    out.field = v->field;   // the grid and the times, no values yet
    bool all = true;
    if (readAll) {
        auto decided = readAll(out.field);
        if (!decided) return decided.error();
        all = *decided;
    }
    if (!all || out.field.timeSteps <= 1) {
        if (auto read = readTimeStep(*v, options, options.timeIndex, out.field); !read) return read.error();
        return out;
    }
    // Every step through the same open dataset: a file replaced on disk meanwhile (renamed over
    // this one, as tools write) is not read, so two files' grids and values never mix.
    out.field.timeIndex = 0;
    for (size_t i = 0; i < v->field.timeSteps; ++i) {
        VolumeField step = v->field;
        if (auto read = readTimeStep(*v, options, i, step); !read) return read.error();
        if (i == 0) {
            out.field.values = std::move(step.values);
            out.field.validCount = step.validCount;
            out.field.minValue = step.minValue, out.field.maxValue = step.maxValue;
            continue;
        }
        if (step.validCount) {   // the range over every step's valid values (a step of no data adds none)
            const bool any = out.field.validCount > 0;
            out.field.minValue = any ? std::min(out.field.minValue, step.minValue) : step.minValue;
            out.field.maxValue = any ? std::max(out.field.maxValue, step.maxValue) : step.maxValue;
            out.field.validCount += step.validCount;
        }
        out.more.push_back(std::move(step.values));
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Describing

bool looksLikeVolumeFile(const std::string& path) {
    globe::configureGdal();
    QuietGdal quiet;
    std::string error;
    auto ds = openMultidim(path, &error);
    if (!ds) return false;
    const auto root = ds->GetRootGroup();
    if (!root) return false;
    bool any = false;
    forEachArray(root, [&](const std::shared_ptr<GDALMDArray>& a) { any = any || a->GetDimensionCount() >= 3; });
    return any;
}

namespace {

/// The offset of the first byte of `s` that is not part of a well-formed UTF-8 sequence.
std::optional<size_t> illFormedUtf8(std::string_view s) {
    for (size_t pos = 0; pos < s.size();) {
        const size_t at = pos;
        bool valid = true;
        decodeUtf8(s, pos, valid);
        if (!valid) return at;
    }
    return std::nullopt;
}

/// Names every string in `j` that is not UTF-8 (dump shows it with U+FFFD).
void findIllFormedText(const nlohmann::json& j, const std::string& where, std::vector<std::string>& problems) {
    if (j.is_string()) {
        const auto& s = j.get_ref<const std::string&>();
        if (const auto at = illFormedUtf8(s)) {
            char byte[8];
            std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(s[*at]));
            problems.push_back(where + ": byte " + byte + " at " + std::to_string(*at) + " is not UTF-8 (shown as U+FFFD)");
        }
    } else if (j.is_object()) {
        for (const auto& [key, value] : j.items()) findIllFormedText(value, where + " " + key, problems);
    } else if (j.is_array()) {
        for (const auto& value : j) findIllFormedText(value, where, problems);
    }
}

/// One variable as describeVolumeJson lists it: name, type, units, dimensions, packing, range.
nlohmann::json describeArray(const GDALMDArray& a) {
    nlohmann::json v;
    v["name"] = a.GetFullName();
    v["type"] = GDALGetDataTypeName(a.GetDataType().GetNumericDataType());
    if (!a.GetUnit().empty()) v["units"] = a.GetUnit();
    if (const auto ln = stringAttribute(a, "long_name"); !ln.empty()) v["longName"] = ln;
    nlohmann::json dims = nlohmann::json::array();
    for (const auto& d : a.GetDimensions())
        dims.push_back({{"name", d->GetName()}, {"size", d->GetSize()}, {"axis", axisName(classify(*d))}});
    v["dimensions"] = dims;
    bool has = false;
    const double nd = a.GetNoDataValueAsDouble(&has);
    if (has) v["fillValue"] = nd;
    const double scale = a.GetScale(&has);
    if (has) v["scale"] = scale;
    const double offset = a.GetOffset(&has);
    if (has) v["offset"] = offset;
    if (a.GetDimensionCount() == 1)
        if (auto values = readAll1d(a); values && !values->empty()) {
            const auto [mn, mx] = std::minmax_element(values->begin(), values->end());
            v["range"] = {*mn, *mx};
        }
    return v;
}

/// What readVolume makes of a volume variable's first time step.
nlohmann::json describeVolume(const std::string& path, const std::string& name) {
    VolumeReadOptions o;
    o.path = path;
    o.variable = name;
    o.maxBytes = uint64_t(512) << 20;
    auto f = readVolume(o);
    if (!f) return {{"readable", false}, {"error", f.message()}};
    nlohmann::json vol = {{"readable", true},
                          {"grid", {f->nx(), f->ny(), f->nz()}},
                          {"lon", {f->lonDeg.front(), f->lonDeg.back()}},
                          {"lat", {f->latDeg.front(), f->latDeg.back()}},
                          {"heightM", {f->heightM.front(), f->heightM.back()}},
                          {"lonWraps", f->lonWraps},
                          {"vertical", f->verticalSource == VerticalSource::Pressure ? "pressure"
                                       : f->verticalSource == VerticalSource::Depth  ? "depth"
                                                                                      : "height"},
                          {"timeSteps", f->timeSteps},
                          {"validValues", f->validCount},
                          {"noDataValues", f->values.size() - f->validCount}};
    if (f->validCount) vol["range"] = {f->minValue, f->maxValue};
    if (!f->times.empty()) vol["times"] = {formatIso8601(f->times.front(), 0), formatIso8601(f->times.back(), 0)};
    return vol;
}

}  // namespace

Result<std::string> describeVolumeJson(const std::string& path, std::vector<std::string>* problems) {
    globe::configureGdal();
    QuietGdal quiet;
    std::string error;
    GDALDatasetUniquePtr ds = openMultidim(path, &error);
    if (!ds) return makeError(error);
    const auto root = ds->GetRootGroup();
    if (!root) return makeError(path + ": GDAL opens it but finds no groups or variables");
    nlohmann::json variables = nlohmann::json::array();
    std::vector<std::string> volumes;
    forEachArray(root, [&](const std::shared_ptr<GDALMDArray>& a) {
        variables.push_back(describeArray(*a));
        if (a->GetDimensionCount() >= 3) volumes.push_back(a->GetFullName());
    });
    // Volume variables: what readVolume makes of their first time step.
    for (auto& v : variables) {
        const std::string name = v["name"];
        if (std::find(volumes.begin(), volumes.end(), name) != volumes.end()) v["volume"] = describeVolume(path, name);
    }
    if (problems)
        for (const auto& v : variables)
            findIllFormedText(v, path + ": " + (v["name"].is_string() ? v["name"].get<std::string>() : std::string("?")), *problems);
    nlohmann::json out = {{"file", path}, {"driver", ds->GetDriver() ? ds->GetDriver()->GetDescription() : "?"},
                          {"variables", variables}};
    return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);   // attributes are not always UTF-8
}

}  // namespace orbis::layers
