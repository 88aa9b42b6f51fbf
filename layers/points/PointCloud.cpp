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

Result<PointCloud> loadPointCloud(const LasFile& file, const PointGeoreference& georef, const PointLoadOptions& options) {
    const LasHeader& h = file.header();
    PointCloud cloud;
    cloud.read = file.points();
    cloud.rgb = h.hasRgb();
    const uint64_t n = file.points();
    const uint64_t per = std::max<uint64_t>(1, options.pointsPerRead);
    const auto& ell = globe::Ellipsoid::wgs84();

    std::vector<glm::dvec3> ecef(n);
    std::vector<PackedAttributes> packed(n);
    std::vector<float> heights(n);
    std::vector<uint32_t> intensityHistogram(65536, 0);
    std::vector<LasPoint> batch;
    std::vector<glm::dvec3> xyz;
    double hMin = std::numeric_limits<double>::max(), hMax = -hMin;
    for (uint64_t first = 0; first < n; first += per) {
        if (options.cancel && options.cancel->load()) return makeError(std::string(file.path()).append(": loading cancelled"));
        file.read(first, per, batch);
        // Colours stored in 8 bits inside the 16-bit fields are common: decided on the first batch.
        if (first == 0 && cloud.rgb)
            for (const LasPoint& p : batch) cloud.rgb16 = cloud.rgb16 || std::max({p.red, p.green, p.blue}) > 255;
        xyz.resize(batch.size());
        for (size_t i = 0; i < batch.size(); ++i) xyz[i] = batch[i].position;
        cloud.dropped += georef.toEcef(xyz);
        for (size_t i = 0; i < batch.size(); ++i) {
            const LasPoint& p = batch[i];
            const uint64_t at = first + i;
            ecef[at] = xyz[i];
            const bool ok = std::isfinite(xyz[i].x) && std::isfinite(xyz[i].y) && std::isfinite(xyz[i].z);
            const double height = ok ? ell.toGeodetic(xyz[i]).height : 0.0;
            heights[at] = float(height);
            if (ok) hMin = std::min(hMin, height), hMax = std::max(hMax, height);
            const auto channel = [&](uint16_t v) { return uint32_t(cloud.rgb16 ? v >> 8 : std::min<uint16_t>(v, 255)); };
            const uint32_t rgb = cloud.rgb ? channel(p.red) | channel(p.green) << 8 | channel(p.blue) << 16 : 0xFFFFFFu;
            packed[at].rgbClass = rgb | uint32_t(p.classification) << 24;
            packed[at].intensityHeight = p.intensity;
            ++intensityHistogram[p.intensity];
        }
        if (options.progress) options.progress(0.8 * double(std::min(n, first + per)) / double(n));
    }
    if (hMin > hMax) hMin = hMax = 0.0;
    cloud.heightMin = hMin;
    cloud.heightMax = hMax;
    const double span = hMax > hMin ? hMax - hMin : 1.0;
    for (uint64_t i = 0; i < n; ++i) {
        const double f = std::clamp((double(heights[i]) - hMin) / span, 0.0, 1.0);
        packed[i].intensityHeight |= uint32_t(std::lround(f * 65535.0)) << 16;
    }
    std::vector<float>().swap(heights);
    // Intensity gain: the 99th percentile maps to white (a few bright returns do not grey out the rest).
    uint64_t seen = 0, p99 = 0;
    for (uint32_t v = 0; v < 65536; ++v) {
        seen += intensityHistogram[v];
        if (seen * 100 >= n * 99) {
            p99 = v;
            break;
        }
    }
    cloud.intensityGain = 1.0f / float(std::max<uint64_t>(p99, 1));
    cloud.octree = PointOctree::build(ecef, packed, options.octree);
    if (options.progress) options.progress(1.0);
    return cloud;
}

}  // namespace orbis::points
