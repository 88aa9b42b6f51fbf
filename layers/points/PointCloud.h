#pragma once
// A LAS file placed on the globe and organised for drawing (CPU only, no Vulkan): points read
// in bounded ranges from the mapped file, turned into ECEF (through the file's CRS, or as
// metres east/north/up of a given origin), their attributes packed for the shaders, then the
// octree (PointOctree) built over them.

#include "engine/core/Result.h"
#include "globe/Ellipsoid.h"
#include "layers/points/LasReader.h"
#include "layers/points/PointOctree.h"

#include <atomic>
#include <functional>
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

private:
    std::shared_ptr<LasGeoreference> crs_;
    glm::dvec3 origin_{0.0};
    glm::dmat3 enu_{1.0};
    std::string description_;
};

struct PointCloud {
    PointOctree octree;
    double heightMin = 0.0, heightMax = 0.0;   ///< metres above the ellipsoid
    float intensityGain = 1.0f;                ///< 1 / the 99th percentile of the intensities
    uint64_t read = 0;                         ///< points in the file
    uint64_t dropped = 0;                      ///< points that could not be placed
    bool rgb = false;                          ///< the format carries colour
    bool rgb16 = false;                        ///< colours use 16 bits (else 8 bits in 16-bit fields)
};

struct PointLoadOptions {
    PointOctree::Options octree;
    uint64_t pointsPerRead = 1u << 20;             ///< points decoded at a time
    const std::atomic<bool>* cancel = nullptr;     ///< stop early (an error "cancelled")
    std::function<void(double)> progress;          ///< 0..1, from the loading thread
};

/// True for files named .las/.laz or starting with "LASF".
bool looksLikeLas(const std::string& path);
/// `orbis info`: header, VLRs, CRS (and the bounds on the globe), the first points, as JSON.
Result<std::string> describeLasJson(const std::string& path);

/// Reads every point of `file` and builds the octree. Any thread.
Result<PointCloud> loadPointCloud(const LasFile& file, const PointGeoreference& georef, const PointLoadOptions& options);

}  // namespace orbis::points
