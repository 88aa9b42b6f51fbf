#include "layers/vector/LabelBoard.h"

#include "layers/vector/VectorLabels.h"

#include <algorithm>
#include <chrono>

namespace orbis::vector {

void LabelBoard::submit(uint64_t frameNumber, VectorLabels& labels) {
    if (frameNumber != frame_) {
        frame_ = frameNumber;
        resolved_ = false;
        submitted_.clear();
    }
    if (std::find(submitted_.begin(), submitted_.end(), &labels) == submitted_.end()) submitted_.push_back(&labels);
}

void LabelBoard::resolve(uint64_t frameNumber, const scene::FrameContext& frame, const LabelPlacementOptions& options) {
    if (frameNumber != frame_ || resolved_) return;
    resolved_ = true;
    const auto t0 = std::chrono::steady_clock::now();
    candidates_.clear();
    from_.clear();
    first_.clear();
    for (uint32_t s = 0; s < submitted_.size(); ++s) {
        first_.push_back(uint32_t(candidates_.size()));
        const auto own = submitted_[s]->candidates();
        candidates_.insert(candidates_.end(), own.begin(), own.end());
        from_.insert(from_.end(), own.size(), s);
    }
    const auto visible = [&](uint32_t i) { return !submitted_[from_[i]]->hiddenByGround(i - first_[from_[i]], frame); };
    const std::vector<uint32_t> chosen =
        frame.groundHeight ? placer_.place(candidates_, options, visible) : placer_.place(candidates_, options);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // Each layer's own, by index into its candidates, in rank order.
    std::vector<std::vector<uint32_t>> perLayer(submitted_.size());
    for (uint32_t i : chosen) perLayer[from_[i]].push_back(i - first_[from_[i]]);
    for (uint32_t s = 0; s < submitted_.size(); ++s) submitted_[s]->build(perLayer[s], ms, placer_.stats().rejectedHidden);
    submitted_.clear();
}

}  // namespace orbis::vector
