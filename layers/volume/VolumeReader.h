#pragma once
// Scientific volumes from netCDF (and anything else GDAL's multidimensional API opens): one
// variable at one time step (or all of them), placed on a (lon, lat, height) grid with CF
// conventions. CPU only, no Vulkan; safe to call from any thread (each call opens its own dataset).
//
//   VolumeReadOptions o;
//   o.path = "air.nc";
//   o.variable = "t";                       // or "/group/t"
//   auto field = readVolume(o);             // Result<VolumeField>
//   if (!field) log::error(field.message()); // names the file, the variable and the problem
//
// What is recognised, from the coordinate variables' CF attributes (axis, standard_name, units,
// positive) with GDAL's dimension types and the usual names as fallbacks:
// - longitude (degrees_east) 0..360 or -180..180, in either order; returned ascending and
//   continuous, so a grid across the antimeridian keeps going past 180;
// - latitude (degrees_north), uniform or not (Gaussian grids), returned ascending;
// - the vertical: heights (m, km), depths (positive down, returned as negative heights) or
//   pressures (Pa, hPa, mbar), converted to heights by the 1976 US standard atmosphere or an
//   isothermal scale height (selectable); returned ascending in height;
// - time: CF "<unit> since <date>" on the standard / Gregorian calendars, as UTC instants.
// Packing (scale_factor/add_offset), _FillValue, missing_value, valid_min/max/range and NaN all
// become "no data" (NaN in the values, left out of the range).

#include "base/Result.h"
#include "base/TimeFormat.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace orbis::layers {

/// How pressure levels become heights.
enum class PressureToHeight {
    StandardAtmosphere,   ///< US Standard Atmosphere 1976, 0..86 km (geopotential heights)
    ScaleHeight,          ///< isothermal: z = H ln(p0 / p), H = 7000 m, p0 = 101325 Pa
};

/// Where the vertical coordinate came from.
enum class VerticalSource { Height, Depth, Pressure };

struct VolumeReadOptions {
    std::string path;
    /// The variable: a name (searched in every group) or a full path "/group/name".
    std::string variable;
    /// Index along the time dimension (ignored when the variable has none).
    size_t timeIndex = 0;
    PressureToHeight pressureToHeight = PressureToHeight::StandardAtmosphere;
    /// Refuse fields whose values would need more than this many bytes of memory.
    uint64_t maxBytes = uint64_t(1) << 30;
};

struct VolumeField {
    std::string variable;   ///< full name, e.g. "/t"
    std::string units, longName;

    // The grid: sample positions along each axis, ascending.
    std::vector<double> lonDeg;      ///< continuous: may run past 180 (e.g. 170 .. 190)
    std::vector<double> latDeg;      ///< -90 .. 90
    std::vector<double> heightM;     ///< metres above the ellipsoid
    bool lonWraps = false;           ///< the samples cover the whole circle (periodic in lon)
    VerticalSource verticalSource = VerticalSource::Height;
    std::vector<double> verticalRaw; ///< the file's vertical values, in the order of heightM
    std::string verticalUnits;

    /// Values, lon fastest, then lat, then height: values[(k * ny + j) * nx + i]. NaN = no data.
    std::vector<float> values;
    float minValue = 0.0f, maxValue = 0.0f;   ///< over the valid values (0, 0 when none)
    size_t validCount = 0;

    /// Time steps of the variable as UTC instants (empty: no time dimension, or its units have
    /// no reference date, in which case timeSteps still counts the steps).
    std::vector<TimeNs> times;
    size_t timeSteps = 1;
    size_t timeIndex = 0;

    size_t nx() const { return lonDeg.size(); }
    size_t ny() const { return latDeg.size(); }
    size_t nz() const { return heightM.size(); }
    float at(size_t i, size_t j, size_t k) const { return values[(k * ny() + j) * nx() + i]; }
};

/// Reads one time step of one variable. Errors name the file, the variable and the problem
/// (missing variable, too few dimensions, a dimension that cannot be placed, a corrupt file,
/// a size beyond maxBytes).
Result<VolumeField> readVolume(const VolumeReadOptions& options);

/// Every time step of a variable: `field` holds time step 0 (timeIndex 0) with the grid, the
/// times, and the range and count of the valid values over all the steps; `more` holds the
/// values of steps 1, 2, ... in order, each laid out as field.values. When only one step was read,
/// `field` is that step (as readVolume returns it) and `more` is empty.
struct VolumeTimeSteps {
    VolumeField field;
    std::vector<std::vector<float>> more;
};

/// Reads every time step of one variable through a single open of the file: a file replaced on
/// disk while it is read (renamed over, as tools write) is not read at all, so the steps always
/// share one grid. `readAll`, when given, sees the grid and the times before any value is read:
/// true reads every step, false only options.timeIndex (as readVolume), an error refuses (a
/// memory budget). options.maxBytes bounds each step.
Result<VolumeTimeSteps> readVolumeTimeSteps(const VolumeReadOptions& options,
                                            const std::function<Result<bool>(const VolumeField& grid)>& readAll = {});

/// What a file holds, as JSON: its variables with their dimensions (classified as lon, lat,
/// vertical, time or other), units, packing, fill values and ranges, and for each volume
/// variable whether it can be read. For `orbis info`. Text that is not UTF-8 (an attribute's
/// bytes in another encoding) is shown with U+FFFD, and each such value is named in `problems`
/// ("/lon units: byte 0xFF at 7 is not UTF-8").
Result<std::string> describeVolumeJson(const std::string& path, std::vector<std::string>* problems = nullptr);

/// True when GDAL opens `path` as a multidimensional dataset with at least one array of three
/// or more dimensions (a candidate volume).
bool looksLikeVolumeFile(const std::string& path);

/// Geopotential height (m) of a pressure (Pa) in the US Standard Atmosphere 1976, from the
/// surface up to 86 km (0.3734 Pa); pressures outside are extrapolated along the end layers.
double standardAtmosphereHeight(double pascals);
/// Its inverse: pressure (Pa) at a geopotential height (m).
double standardAtmospherePressure(double metres);

/// CF time units ("hours since 2001-01-01 00:00:00") to (seconds per unit, reference instant).
/// Errors for units without "since", unknown units, or months/years (not fixed lengths).
struct CfTimeUnits {
    double secondsPerUnit = 1.0;
    TimeNs reference = 0;
};
Result<CfTimeUnits> parseCfTimeUnits(const std::string& units);

}  // namespace orbis::layers
