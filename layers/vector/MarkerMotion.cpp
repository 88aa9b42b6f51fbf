#include "layers/vector/MarkerMotion.h"

#include <algorithm>

namespace orbis::vector {
namespace {

/// A target nearer than this to the last one has not moved (float positions round to ~1 mm at
/// a chunk's few kilometres).
constexpr double kSamePlaceM = 0.01;
constexpr uint32_t kMaxOrdinal = (1u << 24) - 1;

}  // namespace

glm::dvec3 MarkerMotion::Track::at(double now) const {
    if (seconds <= 0.0 || now >= start + seconds) return to;
    const double f = std::clamp((now - start) / seconds, 0.0, 1.0);
    return from + (to - from) * f;
}

void MarkerMotion::arrive(FeatureMesh& mesh, double now) {
    std::unordered_map<uint32_t, uint32_t> ordinals;
    for (MeshChunk& chunk : mesh.chunks) {
        if (chunk.markers.empty()) continue;
        chunk.glideEpoch = now;
        ordinals.clear();
        for (shader::VectorMarker& m : chunk.markers) {
            m.from = m.position;
            m.glide = glm::vec2(0.0f);
            uint32_t& ordinal = ordinals[m.feature];
            const uint64_t k = key(m.feature, ordinal);
            ordinal = std::min(ordinal + 1, kMaxOrdinal);
            const glm::dvec3 target = chunk.origin + glm::dvec3(m.position);
            auto [it, added] = tracks_.try_emplace(k);
            Track& t = it->second;
            if (added) {   // first seen: shown where it is
                t = {target, target, now, 0.0, now, now};
                continue;
            }
            if (glm::length(target - t.to) > kSamePlaceM) {
                const glm::dvec3 shown = t.at(now);
                double seconds = options_.seconds >= 0.0 ? options_.seconds
                                                         : std::clamp(now - t.lastMove, options_.minSeconds, options_.maxSeconds);
                if (glm::length(target - shown) > options_.maxJumpM) {
                    seconds = 0.0;
                    ++jumps_;
                } else if (seconds > 0.0) {
                    ++glides_;
                }
                t = {shown, target, now, seconds, now, now};
            }
            if (t.seconds <= 0.0 || now >= t.start + t.seconds) continue;   // at rest
            // Gliding: from its start, on this chunk's clock (seconds after glideEpoch).
            m.from = glm::vec3(t.from - chunk.origin);
            m.glide = glm::vec2(float(t.start - now), float(t.start + t.seconds - now));
            chunk.radius = std::max(chunk.radius, glm::length(t.from - chunk.center) + 1.0);
            movingUntil_ = std::max(movingUntil_, t.start + t.seconds);
        }
    }
}

void MarkerMotion::drawing(const FeatureMesh& drawn, double now) {
    std::unordered_map<uint32_t, uint32_t> ordinals;
    for (const MeshChunk& chunk : drawn.chunks) {
        ordinals.clear();
        for (const shader::VectorMarker& m : chunk.markers) {
            uint32_t& ordinal = ordinals[m.feature];
            if (const auto it = tracks_.find(key(m.feature, ordinal)); it != tracks_.end()) it->second.lastDrawn = now;
            ordinal = std::min(ordinal + 1, kMaxOrdinal);
        }
    }
    std::erase_if(tracks_, [&](const auto& entry) { return now - entry.second.lastDrawn > kForgetSeconds; });
}

std::optional<glm::dvec3> MarkerMotion::shownAt(uint32_t id, double now) const {
    const auto it = tracks_.find(key(id, 0));
    if (it == tracks_.end()) return std::nullopt;
    return it->second.at(now);
}

}  // namespace orbis::vector
