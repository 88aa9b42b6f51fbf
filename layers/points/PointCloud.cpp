#include "layers/points/PointCloud.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace orbis::points {

Result<PointGeoreference> PointGeoreference::create(const LasFile& file, const PointPlacement& placement) {
    PointGeoreference g;
    if (placement.origin) {
        const globe::Geodetic& o = *placement.origin;
        const auto& ell = globe::Ellipsoid::wgs84();
        g.origin_ = ell.toEcef(o);
        g.enu_ = ell.enuFrame(o.lonDeg, o.latDeg);
        char text[128];
        std::snprintf(text, sizeof text, "metres east, north, up of lon %.9g, lat %.9g, height %.6g m", o.lonDeg,
                      o.latDeg, o.height);
        g.description_ = text;
        return g;
    }
    std::string crs = placement.crs, source = "the scene's \"crs\"";
    if (crs.empty()) {
        crs = file.crs().wkt;
        source = file.crs().source;
    }
    if (crs.empty()) {
        std::string message = file.path();
        message.append(": no coordinate reference system (").append(file.crs().source);
        message.append("): the file has no WKT or GeoTIFF VLR and no sidecar .wkt/.prj; give the layer a \"crs\" "
                       "(e.g. \"EPSG:32632\") or an \"origin\" {\"lon\", \"lat\", \"height\"} for local coordinates");
        return makeError(std::move(message));
    }
    auto ref = LasGeoreference::create(crs, std::string(file.path()).append(" (CRS from ").append(source).append(")"));
    if (!ref) return ref.error();
    g.crs_ = std::make_shared<LasGeoreference>(std::move(*ref));
    g.description_ = g.crs_->name();
    g.description_.append(" (from ").append(source).append(")");
    return g;
}

size_t PointGeoreference::toEcef(std::span<glm::dvec3> xyz) const {
    if (crs_) return crs_->toEcef(xyz);
    for (glm::dvec3& p : xyz) p = origin_ + enu_ * p;
    return 0;
}

double PointGeoreference::resolutionMetres(const LasFile& file) const {
    const LasHeader& h = file.header();
    std::array<glm::dvec3, 4> p;
    p.fill(h.min);
    for (int a = 0; a < 3; ++a) p[size_t(a) + 1][a] += h.scale[a];
    toEcef(p);
    double best = std::numeric_limits<double>::infinity();
    for (size_t a = 1; a < 4; ++a) {
        const double d = glm::length(p[a] - p[0]);
        if (std::isfinite(d) && d > 0.0) best = std::min(best, d);
    }
    return best;
}

}  // namespace orbis::points
