#include "layers/vector/LabelPlacement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace orbis::vector {
namespace {

bool finiteBox(const LabelCandidate& c) {
    return std::isfinite(c.min.x) && std::isfinite(c.min.y) && std::isfinite(c.max.x) && std::isfinite(c.max.y) &&
           c.min.x <= c.max.x && c.min.y <= c.max.y;
}

}  // namespace

bool LabelPlacer::overlapsPlaced(const Box& box) const {
    const glm::ivec2 lo = glm::clamp(glm::ivec2(glm::floor(box.min / cellPx_)), glm::ivec2(0), cells_ - 1);
    const glm::ivec2 hi = glm::clamp(glm::ivec2(glm::floor(box.max / cellPx_)), glm::ivec2(0), cells_ - 1);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            for (uint32_t i : grid_[size_t(y) * size_t(cells_.x) + size_t(x)]) {
                const Box& p = placed_[i];
                // Open rectangles: boxes that only touch do not overlap.
                if (box.min.x < p.max.x && p.min.x < box.max.x && box.min.y < p.max.y && p.min.y < box.max.y) return true;
            }
    return false;
}

void LabelPlacer::insert(const Box& box) {
    const auto index = uint32_t(placed_.size());
    placed_.push_back(box);
    const glm::ivec2 lo = glm::clamp(glm::ivec2(glm::floor(box.min / cellPx_)), glm::ivec2(0), cells_ - 1);
    const glm::ivec2 hi = glm::clamp(glm::ivec2(glm::floor(box.max / cellPx_)), glm::ivec2(0), cells_ - 1);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) grid_[size_t(y) * size_t(cells_.x) + size_t(x)].push_back(index);
}

std::vector<uint32_t> LabelPlacer::place(std::span<const LabelCandidate> candidates, const LabelPlacementOptions& options) {
    stats_ = {};
    stats_.candidates = candidates.size();
    std::vector<uint32_t> out;
    const glm::dvec2 screen = options.screen;
    if (!(screen.x > 0.0 && screen.y > 0.0 && std::isfinite(screen.x) && std::isfinite(screen.y))) {
        shown_.clear();
        return out;
    }

    // The grid for this frame: cells over the screen, emptied but keeping their capacity.
    cellPx_ = options.cellPx > 1.0 ? options.cellPx : 64.0;
    cells_ = glm::max(glm::ivec2(glm::ceil(screen / cellPx_)), glm::ivec2(1));
    grid_.resize(size_t(cells_.x) * size_t(cells_.y));
    for (auto& cell : grid_) cell.clear();
    placed_.clear();

    // The candidates that can be drawn at all (a finite box on the screen; a new label needs
    // the margin inside), with their rank: last frame's labels first within the priority
    // hysteresis, then by id (stable).
    struct Entry {
        double rank;
        uint64_t id;
        uint32_t index;
        bool wasShown;
    };
    const double margin = std::max(0.0, options.marginPx);
    std::vector<Entry> entries;
    entries.reserve(candidates.size());
    for (size_t i = 0; i < candidates.size(); ++i) {
        const LabelCandidate& c = candidates[i];
        const bool wasShown = std::binary_search(shown_.begin(), shown_.end(), c.id);
        const double grow = wasShown ? 0.0 : margin;
        if (!finiteBox(c) || c.min.x - grow < 0.0 || c.min.y - grow < 0.0 || c.max.x + grow > screen.x ||
            c.max.y + grow > screen.y) {
            ++stats_.rejectedOffscreen;
            continue;
        }
        double rank = c.priority + (wasShown ? options.priorityHysteresis : 0.0);
        if (!std::isfinite(rank)) rank = -std::numeric_limits<double>::infinity();
        entries.push_back({rank, c.id, uint32_t(i), wasShown});
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        if (a.rank != b.rank) return a.rank > b.rank;
        if (a.wasShown != b.wasShown) return a.wasShown;
        if (a.id != b.id) return a.id < b.id;
        return a.index < b.index;
    });

    // Greedy: an old label needs its own box clear, a new one its box grown by the margin.
    std::vector<uint64_t> shownNow;
    std::unordered_set<uint64_t> placedIds;
    for (const Entry& e : entries) {
        const LabelCandidate& c = candidates[e.index];
        const double grow = e.wasShown ? 0.0 : margin;
        if (overlapsPlaced(Box{c.min - grow, c.max + grow})) {
            ++stats_.rejectedOverlap;
            continue;
        }
        if (!placedIds.insert(c.id).second) {   // a repeated id
            ++stats_.rejectedOverlap;
            continue;
        }
        insert(Box{c.min, c.max});
        shownNow.push_back(c.id);
        out.push_back(e.index);
        ++(e.wasShown ? stats_.kept : stats_.appeared);
    }
    stats_.placed = out.size();
    std::sort(shownNow.begin(), shownNow.end());
    shown_ = std::move(shownNow);
    return out;
}

}  // namespace orbis::vector
