#include "layers/vector/VectorOgr.h"

#include "base/Secrets.h"
#include "globe/GdalSetup.h"

#include <cpl_error.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

namespace orbis::vector::detail {

GdalErrorScope::GdalErrorScope() {
    CPLPushErrorHandlerEx(&GdalErrorScope::handler, this);
    CPLErrorReset();
}

GdalErrorScope::~GdalErrorScope() { CPLPopErrorHandler(); }

void GdalErrorScope::handler(CPLErr level, CPLErrorNum, const char* message) {
    auto* self = static_cast<GdalErrorScope*>(CPLGetErrorHandlerUserData());
    if (!self || !message) return;
    // One line per message (OGR's SQL parser points at the error on a second line).
    std::string text(message);
    std::replace(text.begin(), text.end(), '\n', ' ');
    if (level >= CE_Failure) {
        // A driver may repeat itself; a few distinct messages say enough.
        if (self->failures_.size() < 4 && std::find(self->failures_.begin(), self->failures_.end(), text) == self->failures_.end())
            self->failures_.push_back(std::move(text));
    } else if (level == CE_Warning) {
        self->lastWarning_ = std::move(text);
    }
}

std::string GdalErrorScope::message(const char* fallback) const {
    std::string out;
    for (const std::string& f : failures_) out.append(out.empty() ? "" : "; ").append(f);
    if (out.empty()) out = lastWarning_.empty() ? std::string(fallback) : lastWarning_;
    return out;
}

void GdalErrorScope::clear() {
    failures_.clear();
    lastWarning_.clear();
    CPLErrorReset();
}

std::string withServerTimeouts(const std::string& source) {
    // PostgreSQL in libpq's key=value form ("PG:dbname=..."): a server that does not answer
    // ends the connection after kPgConnectTimeoutS and a query after kPgStatementTimeoutS,
    // unless the connection string or the environment (PGCONNECT_TIMEOUT, PGOPTIONS) says.
    if (source.rfind("PG:", 0) != 0 || source.find("://") != std::string::npos) return source;
    std::string out = source;
    if (out.find("connect_timeout") == std::string::npos && !std::getenv("PGCONNECT_TIMEOUT"))
        out += " connect_timeout=" + std::to_string(kPgConnectTimeoutS);
    if (out.find("options") == std::string::npos && !std::getenv("PGOPTIONS"))
        out += " options='-c statement_timeout=" + std::to_string(kPgStatementTimeoutS * 1000) + "'";
    return out;
}

namespace {

/// A web service's failure in plain words (OGR's WFS driver repeats itself and quotes whole XML
/// documents): "the server answered HTTP 500", "no answer from the server (<curl's words>)",
/// "the server reports an exception: <its text>"; anything else as it is.
std::string plainServiceError(const std::string& why) {
    if (const size_t at = why.find("HTTP error code : "); at != std::string::npos) {
        const int code = std::atoi(why.c_str() + at + 18);
        if (code > 0) return "the server answered HTTP " + std::to_string(code);
    }
    if (const size_t at = why.find("timed out"); at != std::string::npos) {
        const size_t start = why.rfind("Operation", at), end = why.find_first_of(";(", at);
        return "no answer from the server (" + why.substr(start == std::string::npos ? at : start,
                                                          end == std::string::npos ? std::string::npos : end - (start == std::string::npos ? at : start)) + ")";
    }
    // The first <ServiceException ...> element (not the report around it) and its text.
    size_t at = why.find("<ServiceException");
    while (at != std::string::npos && at + 17 < why.size() && why[at + 17] != ' ' && why[at + 17] != '>')
        at = why.find("<ServiceException", at + 1);
    if (at != std::string::npos) {
        const size_t open = why.find('>', at), close = why.find("</", open == std::string::npos ? at : open);
        if (open != std::string::npos && close != std::string::npos && close > open)
            return "the server reports an exception: " + why.substr(open + 1, std::min<size_t>(close - open - 1, 500));
    }
    return why;
}

}  // namespace

Result<DatasetPtr> openVectorSource(const std::string& source) {
    globe::configureGdal();   // drivers, and HTTP timeouts: a stalled WFS ends the read
    std::error_code ec;
    if (source.empty()) return makeError("vector source: no path or connection string given");
    if (!isConnectionString(source) && !std::filesystem::exists(source, ec)) return makeError(redactSecrets(source) + ": no such file");
    GdalErrorScope errors;
    DatasetPtr dataset(GDALDataset::Open(withServerTimeouts(source).c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!dataset) {
        std::string why = errors.message("no vector driver recognises it");
        if (source.find("://") != std::string::npos) why = plainServiceError(why);
        // The driver's words may quote the connection string.
        return makeError(redactSecrets(source) + ": OGR cannot open it as vector data (" + redactSecrets(why) + ")");
    }
    return dataset;
}

std::string crsLabel(const OGRSpatialReference& srs, int* epsg) {
    *epsg = 0;
    const char* name = srs.GetName();
    const char* authority = srs.GetAuthorityName(nullptr);
    const char* code = srs.GetAuthorityCode(nullptr);
    OGRSpatialReference identified;
    if (!authority || !code) {
        // A Shapefile's .prj names no authority; the common CRSs are recognised by their WKT.
        identified = srs;
        if (identified.AutoIdentifyEPSG() == OGRERR_NONE) {
            authority = identified.GetAuthorityName(nullptr);
            code = identified.GetAuthorityCode(nullptr);
        }
    }
    if (authority && code) {
        if (std::string(authority) == "EPSG") *epsg = std::atoi(code);
        return std::string(authority) + ":" + code;
    }
    return name ? std::string(name) : std::string("unnamed CRS");
}

Result<LayerCrs> layerCrs(OGRLayer& layer, const std::string& source) {
    LayerCrs out;
    const std::string where = source + ": layer '" + layer.GetName() + "'";
    const OGRSpatialReference* layerSrs = layer.GetSpatialRef();
    if (!layerSrs) {
        OGREnvelope e;
        GdalErrorScope quiet;
        const bool known = layer.GetExtent(&e, TRUE) == OGRERR_NONE;
        if (known && (e.MinX < -180.0 || e.MaxX > 360.0 || e.MinY < -90.0 || e.MaxY > 90.0)) {
            char range[160];
            std::snprintf(range, sizeof range, "x %.6g .. %.6g, y %.6g .. %.6g", e.MinX, e.MaxX, e.MinY, e.MaxY);
            return makeError(where + ": no coordinate reference system, and the coordinates (" + range +
                             ") are not longitudes and latitudes");
        }
        out.crs = "none (taken as WGS84 lon/lat)";
        out.warning = "no coordinate reference system: coordinates taken as WGS84 longitude/latitude";
        return out;
    }
    OGRSpatialReference from(*layerSrs), to;
    from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    to.SetWellKnownGeogCS("WGS84");
    to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    out.crs = crsLabel(from, &out.epsg);
    out.crsName = from.GetName() ? from.GetName() : "";
    GdalErrorScope errors;
    out.transform.reset(OGRCreateCoordinateTransformation(&from, &to));
    if (!out.transform)
        return makeError(where + ": no transformation from its CRS " + out.crs +
                         (out.crsName.empty() || out.crsName == out.crs ? "" : " (" + out.crsName + ")") +
                         " to WGS84 (" + errors.message("PROJ found none") + ")");
    return out;
}

std::optional<LonLatBox> layerExtent(OGRLayer& layer, OGRCoordinateTransformation* transform) {
    OGREnvelope e;
    if (layer.GetExtent(&e, TRUE) != OGRERR_NONE) return std::nullopt;
    LonLatBox b{e.MinX, e.MinY, e.MaxX, e.MaxY};
    if (transform && !transform->TransformBounds(e.MinX, e.MinY, e.MaxX, e.MaxY, &b.west, &b.south, &b.east, &b.north, 21))
        return std::nullopt;
    // PROJ's densified edges may overshoot the globe's edges by a rounding error.
    b.west = std::clamp(b.west, -180.0, 180.0), b.east = std::clamp(b.east, -180.0, 180.0);
    b.south = std::clamp(b.south, -90.0, 90.0), b.north = std::clamp(b.north, -90.0, 90.0);
    return b;
}

}  // namespace orbis::vector::detail
