#pragma once
// Points that move (a live layer's vehicles, updated a few times a second in the database) glide
// from where they are shown to where they now are, rather than jump at the feed's rate.
//
// Each 3-D marker (FeatureMesh: a point at altitude) is tracked by its feature id and its place
// among that feature's points (a MultiPoint's k-th point). When a mesh comes in holding a marker
// at another place than its track's target, the marker glides, at a constant speed, from where
// it is shown at that moment to the new place, over `seconds`: by default ("auto") the time since
// that feature last moved, within [minSeconds, maxSeconds], so that a feed at a steady rate makes
// a steady motion (each glide ends about when the next update comes). A marker whose target did
// not change (its tile built again for another feature) goes on with the glide it had. A jump
// longer than `maxJumpM` (a new object under an old id) is not glided.
//
// The glide is in the marker instances (shader::VectorMarker::from, glide) and one clock per
// chunk (MeshChunk::glideEpoch, the push constant VectorMeshPush::glideNow): the GPU moves the
// markers each frame, nothing is uploaded. Positions are ECEF doubles here; on the GPU, floats
// relative to the chunk's origin. The labels of moving points follow them (shownAt).
//
// Times are seconds on any steady clock (the layer's: steady_clock). No Vulkan; main thread.

#include "layers/vector/FeatureMesh.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <unordered_map>

namespace orbis::vector {

struct GlideOptions {
    /// Seconds a moved marker takes to reach its new place; negative: "auto" (the time since
    /// the feature's last move, within [minSeconds, maxSeconds]); 0: it jumps.
    double seconds = -1.0;
    double minSeconds = 0.05, maxSeconds = 2.0;
    double maxJumpM = 20000.0;
};

class MarkerMotion {
public:
    explicit MarkerMotion(const GlideOptions& options = {}) : options_(options) {}

    /// A mesh about to be drawn for the first time, at `now`: its markers that moved get their
    /// glide (from, times), its chunks their clock and a bounding sphere that holds where the
    /// markers glide from.
    void arrive(FeatureMesh& mesh, double now);
    /// The meshes drawn from `now` on (all tiles together): a marker in none of them for
    /// kForgetSeconds is forgotten. (Not at once: a point that moves into another tile leaves
    /// its old tile's mesh, built again, before or after it enters the new one's.)
    void drawing(const FeatureMesh& drawn, double now);
    static constexpr double kForgetSeconds = 10.0;

    /// Where feature `id`'s first marker is shown at `now` (ECEF); none when it has no track.
    std::optional<glm::dvec3> shownAt(uint32_t id, double now) const;
    /// True while some marker glides at `now`.
    bool moving(double now) const { return now < movingUntil_; }
    size_t tracked() const { return tracks_.size(); }
    /// Glides started so far, and those skipped for being too long.
    uint64_t glides() const { return glides_; }
    uint64_t jumps() const { return jumps_; }
    const GlideOptions& options() const { return options_; }

private:
    struct Track {
        glm::dvec3 from{0.0}, to{0.0};
        double start = 0.0, seconds = 0.0;   ///< the glide from `from` to `to`
        double lastMove = 0.0;               ///< when the target last changed (or first seen)
        double lastDrawn = 0.0;              ///< when a mesh drawn last held it
        glm::dvec3 at(double now) const;
    };
    static uint64_t key(uint32_t id, uint32_t ordinal) { return uint64_t(id) << 24 | ordinal; }

    GlideOptions options_;
    std::unordered_map<uint64_t, Track> tracks_;
    double movingUntil_ = 0.0;
    uint64_t glides_ = 0, jumps_ = 0;
};

}  // namespace orbis::vector
