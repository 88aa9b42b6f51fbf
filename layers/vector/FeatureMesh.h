#pragma once
// Features in 3-D for the GPU: extruded buildings (walls and a flat roof, lit by the sun, their
// base on the ground), polygons at their own altitude (relative to the ground or absolute) as
// surfaces, and lines and points at altitude as screen-width segments and markers. No Vulkan:
// the vertices and instances are the shaders' (shared/VectorTypes.h).
//
// Which features: every polygon whose style extrudes it ("extrude"), whatever the altitude
// mode, and in the "relative" and "absolute" modes every feature. A polygon around a pole
// (Antarctica) is left to the drape: its ring alone cannot say which cap it bounds in 3-D.
//
// Heights (metres above the ellipsoid, in the terrain's datum): g(v) is the ground under a
// vertex (MeshGround, sampled on the pool from the scene's ground snapshot), z(v) the vertex's
// own Z (0 without one). The surface is at s(v) = g(v) ("clamped"),
// g(v) + z(v) ("relative") or z(v) ("absolute"). An extruded polygon's roof is flat at
// max s(v) + height; its walls go down to min g(v) less a skirt (a tenth of the building's
// height, at least kSkirtMetres), so that no gap opens under a wall where the terrain drawn,
// coarser than the DEM, lies lower than the ground sampled. A polygon at altitude without
// extrusion is its surface s(v) (its fill at its fillOpacity: below 1, blended), cut into
// triangles no longer than kMaxEdgeDeg so that it follows the Earth's curve; a line's segments are cut the same way, heights interpolated.
//
// Meshes are cut into chunks (the level-kChunkLevel tile of a polygon's first vertex, and the
// style's camera range): each chunk has an ECEF origin (double) and float vertices relative to
// it, a bounding sphere for culling, and the range it is drawn within.

#include "base/TimeFormat.h"
#include "layers/vector/IconCache.h"
#include "layers/vector/VectorContent.h"
#include "shared/VectorTypes.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::jobs {
class CancelToken;
}

namespace orbis::vector {

enum class AltitudeMode : uint8_t { Clamped, Relative, Absolute };

/// "clamped", "relative", "absolute"; nothing for anything else.
std::optional<AltitudeMode> parseAltitudeMode(std::string_view name);
const char* altitudeModeName(AltitudeMode mode);

inline constexpr uint32_t kChunkLevel = 12;      ///< chunks: tiles of 0.044 degrees (~5 km)
inline constexpr double kSkirtMetres = 2.0;
inline constexpr double kMaxEdgeDeg = 0.1;       ///< ~11 km: a chord sags < 2.5 m below the curve

/// Whether a feature with this style is drawn in 3-D in this mode (else: draped).
bool drawnIn3d(const Feature& feature, const FeatureStyle& style, AltitudeMode mode);

/// The ground under every vertex of the features drawn as meshes, sampled a slice at a time
/// (any thread; one at a time).
class MeshGround {
public:
    using HeightFn = std::function<std::optional<double>(double lonDeg, double latDeg)>;

    MeshGround() = default;
    /// Lists the features drawn as meshes (every one, whatever its time). `content` must outlive
    /// the sampling.
    MeshGround(const VectorContent& content, const ContentStyles& styles, AltitudeMode mode);

    /// Samples up to `maxSamples` more vertices; true when every vertex has its ground. Where the
    /// ground is unknown (no terrain), 0: the ellipsoid.
    bool sample(const HeightFn& ground, size_t maxSamples);
    bool done() const { return next_ >= first_.back(); }
    /// The vertices to sample.
    size_t samples() const { return first_.back(); }

    /// The features (layer, index) in the order sampled.
    const std::vector<std::pair<uint32_t, uint32_t>>& features() const { return features_; }
    /// Feature k's heights, one per coordinate.
    std::span<const float> heights(size_t k) const {
        return {heights_.data() + first_[k], first_[k + 1] - first_[k]};
    }

private:
    const VectorContent* content_ = nullptr;   ///< while sampling
    std::vector<std::pair<uint32_t, uint32_t>> features_;
    std::vector<size_t> first_{0};
    std::vector<float> heights_;
    size_t next_ = 0;          ///< the next height to sample
    size_t nextFeature_ = 0;   ///< the feature it belongs to
};

struct MeshOptions {
    AltitudeMode mode = AltitudeMode::Clamped;
    double extrusionScale = 1.0;   ///< multiplies every extruded height (a live setting)
    TimeNs time = 0;               ///< features with times show when they include it
    /// The vertices' feature id is 1 + the feature's fid (a paged source's tiles: ids that
    /// agree between tiles), not its place in the content.
    bool idsByFid = false;
    /// Where points' icons are read (the layer's, shared with its drape): a point whose style
    /// names a readable icon among the atlas's first cells is drawn as it; none: disks.
    IconCache* icons = nullptr;
};

struct MeshChunk {
    glm::dvec3 origin{0.0};        ///< ECEF (m): vertices are relative to it
    glm::dvec3 center{0.0};        ///< the bounding sphere, ECEF
    double radius = 0.0;
    double minRangeM = 0.0, maxRangeM = 0.0;   ///< the camera range it is drawn within
    std::vector<shader::VectorMeshVertex> vertices;
    std::vector<uint32_t> indices;       ///< opaque triangles (solids, and surfaces of fillOpacity 1)
    std::vector<uint32_t> translucent;   ///< surfaces below fillOpacity 1: one face each, blended
    std::vector<shader::VectorSegment> segments;   ///< lines at altitude
    std::vector<shader::VectorMarker> markers;     ///< points at altitude
    /// The clock of its moving markers' glides (MarkerMotion: seconds on the layer's steady
    /// clock); 0: none glides.
    double glideEpoch = 0.0;
    bool empty() const { return indices.empty() && translucent.empty() && segments.empty() && markers.empty(); }
};

struct FeatureMesh {
    std::vector<MeshChunk> chunks;
    uint64_t features = 0, triangles = 0, segments = 0, markers = 0;
    uint64_t forced = 0;   ///< roof triangles of self-intersecting polygons (Triangulate.h)
    std::vector<std::string> warnings;
    uint64_t bytes() const;
};

/// Feature (layer, index)'s id in the vertices (VectorMeshVertex::feature): 1 + its place among
/// all the content's features; 0 is "none" (the highlight's push constant).
uint32_t meshFeatureId(const VectorContent& content, size_t layer, size_t feature);

/// The meshes of the features shown at `options.time`. Any thread; stops early (an empty mesh)
/// when `cancel` is set.
FeatureMesh buildFeatureMesh(const VectorContent& content, const ContentStyles& styles, const MeshGround& ground,
                             const MeshOptions& options, const jobs::CancelToken* cancel = nullptr);

}  // namespace orbis::vector
