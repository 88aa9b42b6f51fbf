// What a vector source holds, for `orbis info`: layers, geometry types, counts, CRSs, fields and
// extents on the globe, from OGR's layer metadata (no feature is converted).
#include "layers/vector/VectorReader.h"

#include "layers/vector/VectorOgr.h"

#include <ogrsf_frmts.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

namespace orbis::vector {
namespace {

using detail::GdalErrorScope;

nlohmann::ordered_json extentJson(OGRLayer& layer, OGRCoordinateTransformation* transform) {
    const auto b = detail::layerExtent(layer, transform);
    if (!b) return nullptr;
    return {{"west", b->west}, {"south", b->south}, {"east", b->east}, {"north", b->north}};
}

nlohmann::ordered_json layerJson(OGRLayer& layer, const std::string& source) {
    nlohmann::ordered_json j;
    j["name"] = layer.GetName();
    j["geometryType"] = OGRGeometryTypeToName(layer.GetGeomType());
    j["featureCount"] = layer.GetFeatureCount(TRUE);
    auto crs = detail::layerCrs(layer, source);
    if (!crs) {
        j["crs"] = {{"problem", crs.message()}};
    } else {
        nlohmann::ordered_json c{{"id", crs->crs}, {"name", crs->crsName}};
        if (crs->epsg) c["epsg"] = crs->epsg;
        if (!crs->warning.empty()) c["warning"] = crs->warning;
        j["crs"] = c;
    }
    nlohmann::ordered_json fields = nlohmann::ordered_json::array();
    const OGRFeatureDefn& definition = *layer.GetLayerDefn();
    for (int i = 0; i < definition.GetFieldCount(); ++i) {
        const OGRFieldDefn* f = definition.GetFieldDefn(i);
        fields.push_back({{"name", f->GetNameRef()}, {"type", OGRFieldDefn::GetFieldTypeName(f->GetType())}});
    }
    j["fields"] = fields;
    j["extent"] = extentJson(layer, crs ? crs->transform.get() : nullptr);
    return j;
}

}  // namespace

Result<std::string> describeVectorJson(const std::string& source) {
    auto dataset = detail::openVectorSource(source);
    if (!dataset) return dataset.error();
    GdalErrorScope quiet;
    nlohmann::ordered_json out;
    out["kind"] = "vector";
    out["file"] = source;
    out["driver"] = (*dataset)->GetDriver() ? (*dataset)->GetDriver()->GetDescription() : "";
    out["layers"] = nlohmann::ordered_json::array();
    for (int i = 0; i < (*dataset)->GetLayerCount(); ++i)
        if (OGRLayer* layer = (*dataset)->GetLayer(i)) out["layers"].push_back(layerJson(*layer, source));
    return out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

bool looksLikeVectorFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return false;
    auto dataset = detail::openVectorSource(path);
    if (!dataset) return false;
    for (int i = 0; i < (*dataset)->GetLayerCount(); ++i) {
        OGRLayer* layer = (*dataset)->GetLayer(i);
        if (layer && layer->GetLayerDefn()->GetGeomFieldCount() > 0) return true;
    }
    return false;
}

}  // namespace orbis::vector
