// netCDF volumes: the CF attribute and axis logic (axis, standard_name, units and their
// spellings, positive, calendars and "since" dates, packing, fill and valid values, dimensions
// that are neither space nor time) fed with synthetic multidimensional arrays that the input
// describes, written as a real netCDF file (GDAL's netCDF driver, on tmpfs) and read back by
// readVolume and orbis info's description.
#include "layers/volume/VolumeReader.h"
#include "tests/fuzz/FuzzGdal.h"

#include <fuzzer/FuzzedDataProvider.h>
#include <gdal_priv.h>
#include <unistd.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

const char* pick(FuzzedDataProvider& in, std::initializer_list<const char*> options) {
    const size_t i = in.ConsumeIntegralInRange<size_t>(0, options.size());
    return i < options.size() ? options.begin()[i] : nullptr;
}

std::string text(FuzzedDataProvider& in, std::initializer_list<const char*> options) {
    if (const char* p = pick(in, options)) return p;
    return in.ConsumeRandomLengthString(24);
}

void stringAttribute(GDALMDArray& a, const char* name, const std::string& value) {
    if (auto attr = a.CreateAttribute(name, {}, GDALExtendedDataType::CreateString())) attr->Write(value.c_str());
}

void numberAttribute(GDALMDArray& a, const char* name, double value, GDALDataType type) {
    if (auto attr = a.CreateAttribute(name, {}, GDALExtendedDataType::Create(type))) attr->Write(value);
}

double number(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
        case 0: return std::nan("");
        case 1: return in.ConsumeIntegralInRange<int>(-1000, 1000);
        case 2: return in.ConsumeFloatingPointInRange<double>(-1e6, 1e6);
        case 3: return in.ConsumeBool() ? HUGE_VAL : -HUGE_VAL;
        default: return in.ConsumeFloatingPoint<double>();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = "/dev/shm/orbis-fuzz-netcdf-" + std::to_string(getpid()) + ".nc";
    FuzzedDataProvider in(data, size);
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("netCDF");
    if (!driver) return 0;
    {
        GDALDatasetUniquePtr ds(driver->CreateMultiDimensional(path.c_str(), nullptr, nullptr));
        if (!ds) return 0;
        auto root = ds->GetRootGroup();
        std::vector<std::shared_ptr<GDALDimension>> dims;
        const int count = in.ConsumeIntegralInRange<int>(1, 5);
        for (int d = 0; d < count; ++d) {
            std::string name = text(in, {"lon", "lat", "lev", "time", "plev", "depth", "x", "y", "member", "month"});
            if (name.empty()) name = "d";
            name += std::to_string(d);   // unique
            const size_t n = in.ConsumeIntegralInRange<size_t>(1, 6);
            auto dim = root->CreateDimension(name, "", "", n);
            if (!dim) return 0;
            dims.push_back(dim);
            if (in.ConsumeBool()) {   // its coordinate variable
                auto coord = root->CreateMDArray(name, {dim}, GDALExtendedDataType::Create(in.ConsumeBool() ? GDT_Float64 : GDT_Int32));
                if (!coord) continue;
                std::vector<double> values(n);
                const double start = number(in), step = in.ConsumeBool() ? number(in) : 1.0;
                for (size_t i = 0; i < n; ++i) values[i] = in.ConsumeBool() ? start + step * double(i) : number(in);
                const GUInt64 origin[1] = {0};
                const size_t extent[1] = {n};
                coord->Write(origin, extent, nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), values.data());
                if (in.ConsumeBool())
                    stringAttribute(*coord, "units", text(in, {"degrees_east", "degrees_north", "degree_E", "degrees", "Pa", "hPa",
                                                              "millibars", "mbar", "m", "km", "meters",
                                                              "days since 2000-01-01", "hours since 1970-01-01 00:00:00",
                                                              "seconds since 2000-1-1 0:0:0", "months since 1900-01-01", "1"}));
                if (in.ConsumeBool()) stringAttribute(*coord, "axis", text(in, {"X", "Y", "Z", "T", "E"}));
                if (in.ConsumeBool())
                    stringAttribute(*coord, "standard_name", text(in, {"longitude", "latitude", "air_pressure", "height", "depth",
                                                                       "time", "realization"}));
                if (in.ConsumeBool()) stringAttribute(*coord, "positive", text(in, {"up", "down"}));
                if (in.ConsumeBool())
                    stringAttribute(*coord, "calendar", text(in, {"standard", "gregorian", "proleptic_gregorian", "noleap",
                                                                  "360_day", "julian"}));
            }
        }
        const GDALDataType type = pick(in, {"f", "s", "b"}) ? GDT_Float32 : GDT_Int16;
        auto v = root->CreateMDArray("v", dims, GDALExtendedDataType::Create(type));
        if (!v) return 0;
        size_t total = 1;
        for (const auto& d : dims) total *= size_t(d->GetSize());
        std::vector<double> values(total);
        for (double& x : values) x = in.remaining_bytes() ? number(in) : 1.0;
        std::vector<GUInt64> origin(dims.size(), 0);
        std::vector<size_t> extent;
        for (const auto& d : dims) extent.push_back(size_t(d->GetSize()));
        v->Write(origin.data(), extent.data(), nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), values.data());
        if (in.ConsumeBool()) numberAttribute(*v, "_FillValue", number(in), type);
        if (in.ConsumeBool()) numberAttribute(*v, "missing_value", number(in), type);
        if (in.ConsumeBool()) numberAttribute(*v, "scale_factor", number(in), GDT_Float32);
        if (in.ConsumeBool()) numberAttribute(*v, "add_offset", number(in), GDT_Float32);
        if (in.ConsumeBool()) numberAttribute(*v, "valid_min", number(in), type);
        if (in.ConsumeBool()) numberAttribute(*v, "valid_max", number(in), type);
        if (in.ConsumeBool()) stringAttribute(*v, "units", in.ConsumeRandomLengthString(16));
        if (in.ConsumeBool()) stringAttribute(*v, "long_name", in.ConsumeRandomLengthString(16));
    }
    orbis::layers::VolumeReadOptions options;
    options.path = path;
    options.variable = "v";
    options.timeIndex = in.ConsumeIntegralInRange<size_t>(0, 6);
    options.maxBytes = 1 << 20;
    (void)orbis::layers::readVolume(options);
    std::vector<std::string> problems;
    (void)orbis::layers::describeVolumeJson(path, &problems);
    unlink(path.c_str());
    return 0;
}
