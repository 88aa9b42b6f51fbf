#include "tests/support/NetcdfWriter.h"

namespace orbis::test {
namespace {

bool setAttr(GDALIHasAttribute& o, const std::string& k, const std::string& v) {
    auto a = o.CreateAttribute(k, {}, GDALExtendedDataType::CreateString());
    return a && a->Write(v.c_str());
}

}  // namespace

std::string writeNetcdf(const std::filesystem::path& file, const std::vector<NcDim>& dims, const NcVariable& var,
                        const std::function<double(const std::vector<size_t>&)>& value) {
    GDALAllRegister();
    auto* driver = GetGDALDriverManager()->GetDriverByName("netCDF");
    if (!driver) return "no netCDF driver";
    const char* opts[] = {"FORMAT=NC4", nullptr};
    GDALDatasetUniquePtr ds(driver->CreateMultiDimensional(file.c_str(), nullptr, const_cast<char**>(opts)));
    if (!ds) return "cannot create " + file.string();
    auto root = ds->GetRootGroup();
    auto group = var.group.empty() ? root : root->CreateGroup(var.group);
    if (!group) return "cannot create group " + var.group;
    std::vector<std::shared_ptr<GDALDimension>> gdims;
    for (const auto& d : dims) {
        auto gd = group->CreateDimension(d.name, "", "", d.values.size());
        auto cv = gd ? group->CreateMDArray(d.name, {gd}, GDALExtendedDataType::Create(d.type)) : nullptr;
        if (!cv) return "cannot create dimension " + d.name;
        for (const auto& [k, v] : d.attrs)
            if (!(k == "units" ? cv->SetUnit(v) : setAttr(*cv, k, v))) return "cannot set " + k + " on " + d.name;
        const GUInt64 start = 0;
        const size_t count = d.values.size();
        if (!cv->Write(&start, &count, nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), d.values.data()))
            return "cannot write coordinate " + d.name;
        gdims.push_back(gd);
    }
    auto array = group->CreateMDArray(var.name, gdims, GDALExtendedDataType::Create(var.type));
    if (!array) return "cannot create variable " + var.name;
    for (const auto& [k, v] : var.attrs)
        if (!(k == "units" ? array->SetUnit(v) : setAttr(*array, k, v))) return "cannot set " + k;
    if (var.noData && !array->SetNoDataValue(*var.noData)) return "cannot set the fill value";
    if (var.scale && !array->SetScale(*var.scale)) return "cannot set scale_factor";
    if (var.offset && !array->SetOffset(*var.offset)) return "cannot set add_offset";
    for (const auto& [k, v] : var.numericAttrs) {
        auto a = array->CreateAttribute(k, {v.size()}, GDALExtendedDataType::Create(var.type));
        if (!a || !a->Write(v.data(), v.size())) return "cannot set " + k;
    }
    size_t total = 1;
    for (const auto& d : dims) total *= d.values.size();
    std::vector<double> data(total);
    std::vector<size_t> idx(dims.size(), 0);
    for (size_t n = 0; n < total; ++n) {
        data[n] = value(idx);
        for (size_t d = dims.size(); d-- > 0;) {
            if (++idx[d] < dims[d].values.size()) break;
            idx[d] = 0;
        }
    }
    std::vector<GUInt64> start(dims.size(), 0);
    std::vector<size_t> count;
    for (const auto& d : dims) count.push_back(d.values.size());
    if (!array->Write(start.data(), count.data(), nullptr, nullptr, GDALExtendedDataType::Create(GDT_Float64), data.data()))
        return "cannot write " + var.name;
    return {};
}

NcDim ncLon(std::vector<double> v) { return {"lon", std::move(v), {{"units", "degrees_east"}, {"standard_name", "longitude"}}}; }
NcDim ncLat(std::vector<double> v) { return {"lat", std::move(v), {{"units", "degrees_north"}, {"axis", "Y"}}}; }
NcDim ncPressure(std::vector<double> v, const char* units) { return {"lev", std::move(v), {{"units", units}, {"axis", "Z"}}}; }
NcDim ncTime(std::vector<double> v, const char* units) {
    return {"time", std::move(v), {{"units", units}, {"calendar", "standard"}}};
}

}  // namespace orbis::test
