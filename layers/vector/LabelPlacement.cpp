#include "layers/vector/LabelPlacement.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace orbis::vector {
namespace {

/// An integer whose ascending order is the descending order of `rank` (not NaN).
uint64_t descendingKey(double rank) {
    const auto bits = std::bit_cast<uint64_t>(rank);
    const uint64_t ascending = (bits >> 63) ? ~bits : bits | (uint64_t(1) << 63);
    return ~ascending;
}

bool finiteBox(const LabelCandidate& c) {
    return std::isfinite(c.min.x) && std::isfinite(c.min.y) && std::isfinite(c.max.x) && std::isfinite(c.max.y) &&
           c.min.x <= c.max.x && c.min.y <= c.max.y;
}

}  // namespace

uint64_t LabelPlacer::IdSet::slotOf(uint64_t id) const {
    // A 64-bit mix (splitmix64's finaliser), then linear probing.
    uint64_t h = id;
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return (h ^ (h >> 31)) & (ids_.size() - 1);
}

void LabelPlacer::IdSet::assign(std::span<const uint64_t> ids) {
    size_t size = 16;
    while (size < 2 * ids.size()) size *= 2;
    ids_.assign(size, 0);
    used_.assign(size, 0);
    for (uint64_t id : ids) {
        uint64_t k = slotOf(id);
        while (used_[k] && ids_[k] != id) k = (k + 1) & (size - 1);
        ids_[k] = id;
        used_[k] = 1;
    }
}

bool LabelPlacer::IdSet::contains(uint64_t id) const {
    if (ids_.empty()) return false;
    for (uint64_t k = slotOf(id);; k = (k + 1) & (ids_.size() - 1)) {
        if (!used_[k]) return false;
        if (ids_[k] == id) return true;
    }
}

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

std::vector<uint32_t> LabelPlacer::place(std::span<const LabelCandidate> candidates, const LabelPlacementOptions& options,
                                        const std::function<bool(uint32_t)>& visible) {
    stats_ = {};
    stats_.candidates = candidates.size();
    std::vector<uint32_t> out;
    const glm::dvec2 screen = options.screen;
    if (!(screen.x > 0.0 && screen.y > 0.0 && std::isfinite(screen.x) && std::isfinite(screen.y))) {
        shown_.assign({});
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
    // hysteresis, then by id (stable). The rank is sorted as one integer key; equal keys fall
    // back to the full order.
    const double margin = std::max(0.0, options.marginPx);
    std::vector<Entry>& entries = entries_;   // kept between frames: no allocation once warm
    entries.clear();
    for (size_t i = 0; i < candidates.size(); ++i) {
        const LabelCandidate& c = candidates[i];
        const bool wasShown = shown_.contains(c.id);
        const double grow = wasShown ? 0.0 : margin;
        if (!finiteBox(c) || c.min.x - grow < 0.0 || c.min.y - grow < 0.0 || c.max.x + grow > screen.x ||
            c.max.y + grow > screen.y) {
            ++stats_.rejectedOffscreen;
            continue;
        }
        double rank = c.priority + (wasShown ? options.priorityHysteresis : 0.0);
        if (!std::isfinite(rank)) rank = -std::numeric_limits<double>::infinity();
        entries.push_back({descendingKey(rank), uint32_t(i), wasShown});
    }
    // By key, least significant byte first (stable; bytes every key shares are skipped), then
    // the rare runs of equal keys by the rest of the order.
    std::vector<Entry>& scratch = scratch_;
    scratch.resize(entries.size());
    for (int shift = 0; shift < 64; shift += 8) {
        size_t counts[257] = {};
        for (const Entry& e : entries) ++counts[((e.key >> shift) & 0xff) + 1];
        if (std::any_of(std::begin(counts) + 1, std::end(counts), [&](size_t n) { return n == entries.size(); })) continue;
        for (int b = 0; b < 256; ++b) counts[b + 1] += counts[b];
        for (const Entry& e : entries) scratch[counts[(e.key >> shift) & 0xff]++] = e;
        entries.swap(scratch);
    }
    for (size_t i = 0; i < entries.size();) {
        size_t j = i + 1;
        while (j < entries.size() && entries[j].key == entries[i].key) ++j;
        const auto before = [&](const Entry& a, const Entry& b) {
            if (a.wasShown != b.wasShown) return a.wasShown;
            const uint64_t ida = candidates[a.index].id, idb = candidates[b.index].id;
            if (ida != idb) return ida < idb;
            return a.index < b.index;
        };
        // A caller that lists its candidates by id (many labels of one rank: a layer's points)
        // leaves long runs already in order: checking is linear, sorting is not.
        const auto first = entries.begin() + ptrdiff_t(i), last = entries.begin() + ptrdiff_t(j);
        if (j - i > 1 && !std::is_sorted(first, last, before)) std::sort(first, last, before);
        i = j;
    }

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
        if (placedIds.count(c.id)) {   // a repeated id
            ++stats_.rejectedOverlap;
            continue;
        }
        if (visible && !visible(e.index)) {
            ++stats_.rejectedHidden;
            continue;
        }
        placedIds.insert(c.id);
        insert(Box{c.min, c.max});
        shownNow.push_back(c.id);
        out.push_back(e.index);
        ++(e.wasShown ? stats_.kept : stats_.appeared);
    }
    stats_.placed = out.size();
    shown_.assign(shownNow);
    return out;
}

}  // namespace orbis::vector
