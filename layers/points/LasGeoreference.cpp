// A CRS to ECEF through GDAL/OGR (PROJ underneath): the source CRS's axis order is the GIS one
// (x = easting or longitude), the target is EPSG:4978 (WGS84 geocentric). Heights of a
// horizontal-only CRS are taken in its linear unit (the LAS habit for feet-based surveys).
#include "layers/points/LasReader.h"

#include <cpl_error.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

namespace orbis::points {

struct LasGeoreference::Impl {
    OGRSpatialReference source, target;
    OGRCoordinateTransformation* transform = nullptr;
    double linearUnit = 1.0, verticalUnit = 1.0;
    bool scaleHeights = false;
    // OGRCoordinateTransformation must not be used by two threads at once (GDAL's rule), and
    // loading jobs may share one georeference.
    std::mutex transforming;
    ~Impl() {
        if (transform) OGRCoordinateTransformation::DestroyCT(transform);
    }
};

LasGeoreference::LasGeoreference(LasGeoreference&&) noexcept = default;
LasGeoreference& LasGeoreference::operator=(LasGeoreference&&) noexcept = default;
LasGeoreference::~LasGeoreference() = default;

Result<LasGeoreference> LasGeoreference::create(const std::string& crs, const std::string& what) {
    LasGeoreference g;
    g.impl_ = std::make_unique<Impl>();
    Impl& m = *g.impl_;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
    const OGRErr err = m.source.SetFromUserInput(crs.c_str());
    std::string gdalMessage = CPLGetLastErrorMsg();
    CPLPopErrorHandler();
    if (err != OGRERR_NONE) {
        std::string shown = crs.size() > 80 ? crs.substr(0, 80).append("...") : crs;
        std::string message = what;
        message.append(": cannot read the coordinate reference system \"").append(shown).append("\"");
        if (!gdalMessage.empty()) message.append(" (").append(gdalMessage).append(")");
        return makeError(std::move(message));
    }
    m.source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    m.target.importFromEPSG(4978);
    m.target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (m.source.IsProjected() || m.source.IsLocal()) m.linearUnit = m.source.GetLinearUnits();
    const bool hasVertical = m.source.IsCompound() || m.source.IsGeocentric() || m.source.GetAxesCount() == 3;
    m.scaleHeights = !hasVertical && m.source.IsProjected() && std::abs(m.linearUnit - 1.0) > 1e-12;
    m.verticalUnit = m.scaleHeights ? m.linearUnit : 1.0;
    if (m.source.IsCompound()) {
        const char* unit = nullptr;
        const double v = m.source.GetTargetLinearUnits("VERT_CS", &unit);
        if (v > 0.0) m.verticalUnit = v;
    }
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
    m.transform = OGRCreateCoordinateTransformation(&m.source, &m.target);
    gdalMessage = CPLGetLastErrorMsg();
    CPLPopErrorHandler();
    if (!m.transform) {
        std::string message = what;
        message.append(": no transformation from ").append(m.source.GetName() ? m.source.GetName() : "the CRS");
        message.append(" to WGS84 geocentric");
        if (!gdalMessage.empty()) message.append(" (").append(gdalMessage).append(")");
        return makeError(std::move(message));
    }
    return g;
}

size_t LasGeoreference::toEcef(std::span<glm::dvec3> xyz) const {
    constexpr size_t kBatch = 4096;
    std::vector<double> x(kBatch), y(kBatch), z(kBatch);
    std::vector<int> ok(kBatch);
    size_t failed = 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (size_t first = 0; first < xyz.size(); first += kBatch) {
        const size_t n = std::min(kBatch, xyz.size() - first);
        for (size_t i = 0; i < n; ++i) {
            x[i] = xyz[first + i].x;
            y[i] = xyz[first + i].y;
            z[i] = xyz[first + i].z * (impl_->scaleHeights ? impl_->linearUnit : 1.0);
        }
        bool all = false;
        {
            std::lock_guard lock(impl_->transforming);
            CPLPushErrorHandler(CPLQuietErrorHandler);
            all = impl_->transform->Transform(int(n), x.data(), y.data(), z.data(), ok.data());
            CPLPopErrorHandler();
        }
        for (size_t i = 0; i < n; ++i) {
            const bool good = (all || ok[i]) && std::isfinite(x[i]) && std::isfinite(y[i]) && std::isfinite(z[i]);
            xyz[first + i] = good ? glm::dvec3(x[i], y[i], z[i]) : glm::dvec3(nan);
            failed += good ? 0 : 1;
        }
    }
    return failed;
}

std::string LasGeoreference::name() const {
    const char* n = impl_->source.GetName();
    std::string s = n ? n : "unnamed CRS";
    const char* auth = impl_->source.GetAuthorityName(nullptr);
    const char* code = impl_->source.GetAuthorityCode(nullptr);
    if (auth && code) s = std::string(auth).append(":").append(code).append(" ").append(s);
    return s;
}

double LasGeoreference::linearUnitMetres() const { return impl_->linearUnit; }
double LasGeoreference::verticalUnitMetres() const { return impl_->verticalUnit; }

}  // namespace orbis::points
