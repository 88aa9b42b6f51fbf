#pragma once
// The vector reader's GDAL/OGR plumbing (internal to layers/vector): registering drivers,
// GDAL's error messages caught per thread, opening a source, and a layer's CRS and its
// transformation to WGS84 lon/lat.

#include "base/Result.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::vector::detail {

/// GDAL's messages on this thread are caught while it lives (CPLPushErrorHandlerEx: the handler
/// stack is per thread, so readers on other threads are not affected); the failures explain
/// what went wrong. Nests: an inner scope hides messages from the outer one.
class GdalErrorScope {
public:
    GdalErrorScope();
    ~GdalErrorScope();
    GdalErrorScope(const GdalErrorScope&) = delete;
    GdalErrorScope& operator=(const GdalErrorScope&) = delete;

    /// The failures reported since the scope began (or the last clear), joined with "; ",
    /// else the last warning, else `fallback`.
    std::string message(const char* fallback = "") const;
    bool failed() const { return !failures_.empty(); }
    void clear();

private:
    static void handler(CPLErr level, CPLErrorNum number, const char* message);
    std::vector<std::string> failures_;
    std::string lastWarning_;
};

struct DatasetCloser {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

struct TransformDeleter {
    void operator()(OGRCoordinateTransformation* t) const { OGRCoordinateTransformation::DestroyCT(t); }
};
using TransformPtr = std::unique_ptr<OGRCoordinateTransformation, TransformDeleter>;

/// A PostgreSQL server that does not answer: the connection gives up after this long, and a
/// query too (withServerTimeouts).
inline constexpr int kPgConnectTimeoutS = 10, kPgStatementTimeoutS = 60;
/// What GDAL is asked to open for `source`: a "PG:" key=value connection gets Orbis's
/// timeouts unless it (or PGCONNECT_TIMEOUT, PGOPTIONS) sets its own; anything else as it is.
std::string withServerTimeouts(const std::string& source);

/// Opens a vector source read-only. Errors: "<source>: no such file", or that OGR cannot open
/// it, with GDAL's reason.
Result<DatasetPtr> openVectorSource(const std::string& source);

/// How a layer's coordinates become WGS84 lon/lat.
struct LayerCrs {
    TransformPtr transform;    ///< null: the coordinates are lon/lat already (no CRS)
    std::string crs;           ///< "EPSG:4267", or the CRS's name
    std::string crsName;       ///< "NAD27"; empty without a CRS
    int epsg = 0;
    std::string warning;       ///< set when a missing CRS was taken as WGS84
};

/// The layer's CRS and its transformation to WGS84 lon/lat (traditional GIS axis order on both
/// sides, so x is easting or longitude). A layer without a CRS whose extent fits
/// [-180, 360] x [-90, 90] is taken as lon/lat with a warning; otherwise, and for a CRS PROJ
/// cannot transform, an error naming the source, the layer and the CRS.
Result<LayerCrs> layerCrs(OGRLayer& layer, const std::string& source);

/// The layer's extent in WGS84 lon/lat (its box transformed with densified edges, so that
/// projected boxes are covered; clamped to the globe), west > east when it crosses the
/// antimeridian as OGR reports it. None when OGR cannot tell or transform it.
struct LonLatBox {
    double west, south, east, north;
};
std::optional<LonLatBox> layerExtent(OGRLayer& layer, OGRCoordinateTransformation* transform);

/// "EPSG:4267" when the CRS (or, for an unnamed one, its best identified match) has an EPSG
/// code, else its name; sets `epsg` to the code or 0.
std::string crsLabel(const OGRSpatialReference& srs, int* epsg);

}  // namespace orbis::vector::detail
