#pragma once
// A LAS file placed on the globe (CPU only, no Vulkan): where its coordinates are (the file's
// CRS, a scene override, or metres east/north/up of a given origin) and their way to ECEF. The
// octree built from it is a PointStore.

#include "base/Result.h"
#include "globe/Ellipsoid.h"
#include "layers/points/LasReader.h"
#include "layers/points/PointStore.h"

#include <memory>
#include <optional>
#include <string>

namespace orbis::points {

/// Where a cloud's coordinates are: a CRS (scene override, else the file's) or a local frame.
struct PointPlacement {
    std::string crs;                        ///< scene override: WKT, "EPSG:n" or a PROJ string
    std::optional<globe::Geodetic> origin;  ///< coordinates are metres east, north, up of this point
};

/// The transformation a cloud's coordinates go through to ECEF.
class PointGeoreference {
public:
    /// From the placement, else the file's own CRS; a clear error naming the file when it has
    /// none (no WKT or GeoTIFF VLR, no sidecar) and the scene gives none either.
    static Result<PointGeoreference> create(const LasFile& file, const PointPlacement& placement);
    /// In place, CRS (or local) coordinates to ECEF; returns how many could not be placed (NaN).
    size_t toEcef(std::span<glm::dvec3> xyz) const;
    /// "EPSG:2992 NAD83 / Oregon GIC Lambert (ft) (from the sidecar ...)" or "local ENU at ...".
    const std::string& description() const { return description_; }
    /// The size in metres of the file's coordinate grid (its scale) where the cloud is: the
    /// smallest ECEF step one unit of an axis makes at the header's minimum corner.
    double resolutionMetres(const LasFile& file) const;

private:
    std::shared_ptr<LasGeoreference> crs_;
    glm::dvec3 origin_{0.0};
    glm::dmat3 enu_{1.0};
    std::string description_;
};

/// True for files named .las/.laz or starting with "LASF".
bool looksLikeLas(const std::string& path);
/// `orbis info`: header, VLRs, CRS (and the bounds on the globe), the first points, as JSON.
Result<std::string> describeLasJson(const std::string& path);

}  // namespace orbis::points
