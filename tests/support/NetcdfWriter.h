#pragma once
// Writes small netCDF-4 files with GDAL's multidimensional writer for tests of the volume
// reader and layer: dimensions with coordinate variables and CF attributes, one variable with
// optional packing and fill value, in a group or at the root.

#include <gdal_priv.h>

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace orbis::test {

/// One dimension with its coordinate variable.
struct NcDim {
    std::string name;
    std::vector<double> values;
    std::map<std::string, std::string> attrs;   // "units" goes through SetUnit
    GDALDataType type = GDT_Float64;
};

struct NcVariable {
    std::string name = "t";
    std::string group;   // "" = root, else a sub-group name
    GDALDataType type = GDT_Float32;
    std::map<std::string, std::string> attrs;
    std::map<std::string, std::vector<double>> numericAttrs;
    std::optional<double> noData, scale, offset;
};

/// Writes `file` with `dims` (in the variable's order) and one variable whose value at a
/// multi-index comes from `value`. Returns "" or what went wrong.
std::string writeNetcdf(const std::filesystem::path& file, const std::vector<NcDim>& dims, const NcVariable& var,
                        const std::function<double(const std::vector<size_t>&)>& value);

NcDim ncLon(std::vector<double> v);
NcDim ncLat(std::vector<double> v);
NcDim ncPressure(std::vector<double> v, const char* units = "Pa");
NcDim ncTime(std::vector<double> v, const char* units = "hours since 2001-01-01 00:00:00");

}  // namespace orbis::test
