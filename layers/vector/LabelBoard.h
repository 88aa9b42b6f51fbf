#pragma once
// The labels of every vector layer of a scene placed together, so that one layer's labels never
// cover another's (the cities' names over the countries'), ranked by the same rule (points
// first, then size) whatever layer they come from. No Vulkan. Main thread only.
//
// Each frame, each layer gathers its candidates (VectorLabels::gather, in its update) and
// submits them; the first `resolve` of the frame (the first layer's recordTransfers, after every
// update) places them all with one LabelPlacer, which keeps the hysteresis from frame to frame,
// and hands each layer its chosen labels (VectorLabels::build). A submission lives for its frame
// only: a layer destroyed between frames leaves nothing behind.

#include "engine/scene/FrameContext.h"
#include "layers/vector/LabelPlacement.h"

#include <cstdint>
#include <vector>

namespace orbis::vector {

class VectorLabels;

class LabelBoard {
public:
    /// Adds `labels`' candidates for frame `frameNumber` (a new number forgets the last frame's
    /// submissions). `labels` must live until this frame is resolved.
    void submit(uint64_t frameNumber, VectorLabels& labels);
    /// Places this frame's submissions together, once: later calls for the same frame do
    /// nothing. The terrain test uses `frame`'s eye and ground.
    void resolve(uint64_t frameNumber, const scene::FrameContext& frame, const LabelPlacementOptions& options);

    const LabelPlacementStats& stats() const { return placer_.stats(); }

private:
    uint64_t frame_ = ~uint64_t(0);
    bool resolved_ = false;
    std::vector<VectorLabels*> submitted_;
    LabelPlacer placer_;
    std::vector<LabelCandidate> candidates_;
    std::vector<uint32_t> from_;    ///< per candidate: its submission
    std::vector<uint32_t> first_;   ///< per submission: its first candidate
};

}  // namespace orbis::vector
