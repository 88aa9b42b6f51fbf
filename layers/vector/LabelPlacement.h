#pragma once
// Choosing which labels to draw this frame: no two drawn labels overlap, and the choice is
// stable while the camera moves. No Vulkan, no fonts: a label is a screen rectangle with a
// priority and a stable id; the caller has already dropped labels hidden behind the globe or
// the terrain.
//
// Greedy by rank, over a uniform grid of the screen (one cell list per 64 x 64 pixels), so a
// frame of N candidates costs O(N log N) for the sort plus O(N) overlap tests of a few
// neighbours each.
//
// Hysteresis, so that labels do not flicker:
//   - A label drawn last frame ranks above every label that was not (within the same priority
//     plus `priorityHysteresis`): a new label displaces an old one only when it is clearly more
//     important.
//   - An old label stays while its own rectangle is clear and on screen. A new label appears
//     only when its rectangle grown by `marginPx` on every side is clear of the labels placed
//     so far and inside the screen by `marginPx`. A label that moves slowly therefore changes
//     its state only when a gap or the screen edge passes the margin, not at every pixel of
//     motion where two rectangles touch.
// The placer keeps last frame's set: one LabelPlacer per view.
//
// A test too costly for every candidate (is the terrain between the eye and the label?) can be
// left to `place`: it asks `visible` only about a candidate that has room, just before placing
// it, so only the labels that would be drawn (and a few more) pay for it.

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace orbis::vector {

/// One label that could be drawn.
struct LabelCandidate {
    uint64_t id = 0;          ///< stable across frames (e.g. the layer's index << 40 | the feature's)
    double priority = 0.0;    ///< larger first (e.g. population, rank, rule order)
    glm::dvec2 min{0.0};      ///< the label's box in pixels (x right, y down), icon and halo included
    glm::dvec2 max{0.0};
};

struct LabelPlacementOptions {
    glm::dvec2 screen{0.0};          ///< the viewport (pixels): a label is drawn only if inside it
    double marginPx = 4.0;           ///< clear space a new label needs around it (the hysteresis)
    double priorityHysteresis = 0.0; ///< how much more important a new label must be to rank above an old one
    double cellPx = 64.0;            ///< grid cell (pixels)
};

struct LabelPlacementStats {
    size_t candidates = 0, placed = 0, kept = 0, appeared = 0, rejectedOverlap = 0, rejectedOffscreen = 0, rejectedHidden = 0;
};

class LabelPlacer {
public:
    /// The candidates to draw this frame, by index into `candidates`, in rank order. Ids must be
    /// unique within a call (a repeated id is placed at most once). `visible`, when given, is
    /// asked (by index) about each candidate that has room before it is placed; one it refuses
    /// takes no room and is not drawn.
    std::vector<uint32_t> place(std::span<const LabelCandidate> candidates, const LabelPlacementOptions& options,
                                const std::function<bool(uint32_t)>& visible = {});

    const LabelPlacementStats& stats() const { return stats_; }
    /// Forgets last frame (a new scene, a jump of the camera).
    void reset() { shown_.assign({}); }

private:
    struct Box {
        glm::dvec2 min, max;
    };
    bool overlapsPlaced(const Box& box) const;
    void insert(const Box& box);

    /// A set of ids: open addressing, at most half full.
    class IdSet {
    public:
        void assign(std::span<const uint64_t> ids);
        bool contains(uint64_t id) const;

    private:
        uint64_t slotOf(uint64_t id) const;
        std::vector<uint64_t> ids_;
        std::vector<uint8_t> used_;
    };

    /// A candidate that can be drawn, with its rank as one integer.
    struct Entry {
        uint64_t key;     ///< descending rank as an ascending integer
        uint32_t index;   ///< into the candidates
        bool wasShown;
    };

    IdSet shown_;   ///< ids drawn last frame
    std::vector<Entry> entries_, scratch_;   ///< this frame's, kept for their capacity
    LabelPlacementStats stats_;
    // The grid of the current frame: for each cell, the placed boxes that touch it.
    glm::ivec2 cells_{0};
    double cellPx_ = 64.0;
    std::vector<std::vector<uint32_t>> grid_;
    std::vector<Box> placed_;
};

}  // namespace orbis::vector
