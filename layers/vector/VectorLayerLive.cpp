// The vector layer's live sources (VectorLayer.h, "Live sources"): the changes a PostgreSQL
// trigger announces (PgListener) or the polling clock finds, applied page by page.
#include "layers/vector/VectorLayer.h"

#include "base/Log.h"

#include <algorithm>

namespace orbis::layers {
namespace {

/// At most this many boxes are told apart; past that, their union.
constexpr size_t kBoxesKept = 256;
/// Drape versions whose changed regions are kept for the ground (drapeChangedSince).
constexpr size_t kDrapeChangesKept = 64;

globe::GeoExtent extentOf(const vector::LonLatBounds& b) { return {b.west, b.south, b.east, b.north}; }

vector::LonLatBounds unionOf(const vector::LonLatBounds& a, const vector::LonLatBounds& b) {
    return {std::min(a.west, b.west), std::min(a.south, b.south), std::max(a.east, b.east), std::max(a.north, b.north), false};
}

}  // namespace

void VectorLayer::pollRefresh() {
    using Clock = std::chrono::steady_clock;
    if (refreshing_ && refreshJob_.ready()) {
        refreshing_ = false;
        vector::PageRefresh done;
        bool ok = true;
        try {
            done = refreshJob_.get();
        } catch (const std::exception& e) {
            ok = false;
            refreshError_ = e.what();
        }
        refreshJob_ = {};
        if (ok) {
            refreshError_ = done.error;
            if (done.failed > 0) {
                // Tried again a second later (the server may be restarting): until then the old
                // features stay on show and the status says why.
                log::warn("vector layer \"", displayName(), "\": ", done.failed, " feature tile(s) not read again: ", done.error);
                retryBoxes_ = refreshingBoxes_;
                retryRefreshAt_ = Clock::now() + std::chrono::seconds(1);
            }
            // Where to paint again: what changed in memory, and the boxes the server named (tiles
            // painted from pages no longer in memory).
            std::vector<globe::GeoExtent> regions = std::move(done.changed);
            for (const vector::LonLatBounds& b : refreshingBoxes_) regions.push_back(extentOf(b));
            applyChanges(std::move(regions));
        }
        refreshingBoxes_.clear();
    }
    if (listener_) {
        bool grew = false;
        for (const vector::DatabaseChange& change : listener_->take()) {
            if (!change.box) refreshAnywhere_ = true;
            else refreshBoxes_.push_back(*change.box);
            // Tiles are read within the source's box: a row moved or inserted out of it grows
            // it (a change anywhere, or one whose box was lost, lifts it).
            if (pagedBounds_) grew = (change.box ? growBounds(*change.box) : (pagedBounds_.reset(), true)) || grew;
        }
        if (grew) republish();
    }
    // Pages read slowly, left outdated a while: their tiles are painted again when they may be read.
    const auto now = Clock::now();
    std::vector<globe::GeoExtent> due;
    std::erase_if(deferredRepaints_, [&](const vector::DeferredRead& d) {
        if (d.when > now) return false;
        due.push_back(d.extent);
        return true;
    });
    if (!due.empty() && pages_) applyChanges(std::move(due));
    if (pages_ && !refreshAnywhere_ && !refreshBoxes_.empty()) {
        // Boxes the server named: the pages they reach are read again by the painters of the
        // tiles painted again now (no wait for a read before the repaint starts).
        auto deferred = pages_->invalidate(refreshBoxes_);
        deferredRepaints_.insert(deferredRepaints_.end(), deferred.begin(), deferred.end());
        if (deferredRepaints_.size() > kBoxesKept) deferredRepaints_.erase(deferredRepaints_.begin(), deferredRepaints_.end() - kBoxesKept);
        std::vector<globe::GeoExtent> regions;
        for (const vector::LonLatBounds& b : refreshBoxes_) regions.push_back(extentOf(b));
        refreshBoxes_.clear();
        applyChanges(std::move(regions));
    }
    if (retryRefreshAt_ && Clock::now() >= *retryRefreshAt_) {
        retryRefreshAt_.reset();
        if (retryBoxes_.empty()) refreshAnywhere_ = true;
        refreshBoxes_.insert(refreshBoxes_.end(), retryBoxes_.begin(), retryBoxes_.end());
        retryBoxes_.clear();
    }
    if (settings_.refresh.everySeconds > 0.0 && Clock::now() >= nextPoll_) {
        if (nextPoll_ != Clock::time_point{}) refreshAnywhere_ = true;
        nextPoll_ = Clock::now() + std::chrono::milliseconds(int64_t(settings_.refresh.everySeconds * 1000.0));
    }
    if (!pages_) {
        // Not open yet: the first reads see the source as it is.
        refreshBoxes_.clear();
        refreshAnywhere_ = false;
        return;
    }
    if (refreshing_ || !refreshQueued()) return;
    if (refreshBoxes_.size() > kBoxesKept) {
        vector::LonLatBounds all = refreshBoxes_.front();
        for (const vector::LonLatBounds& b : refreshBoxes_)
            all = unionOf(all, b);
        refreshBoxes_ = {all};
    }
    if (refreshAnywhere_) refreshBoxes_.clear();
    refreshingBoxes_ = std::exchange(refreshBoxes_, {});
    refreshAnywhere_ = false;
    refreshing_ = true;
    refreshJob_ = services_.jobs().submit(1e9, jobs::CancelToken{},   // before the tiles it repaints
                                          [pages = pages_, boxes = refreshingBoxes_](const jobs::CancelToken& cancel) {
                                              return pages->refresh(boxes, &cancel);
                                          });
}

bool VectorLayer::growBounds(const vector::LonLatBounds& box) {
    if (box.empty || !pagedBounds_) return false;
    vector::LonLatBounds& b = *pagedBounds_;
    if (!b.empty && b.west <= box.west && box.east <= b.east && b.south <= box.south && box.north <= b.north) return false;
    if (b.empty) b = box;
    else b = unionOf(b, box);
    return true;
}

void VectorLayer::applyChanges(std::vector<globe::GeoExtent> regions) {
    ++refreshesApplied_;
    // The meshes of the tiles the regions reach are built again (the old ones drawn meanwhile).
    for (auto& [key, tile] : tileMeshes_) {
        const globe::GeoExtent e = key.extent();
        const bool reached =
            std::any_of(regions.begin(), regions.end(), [&](const globe::GeoExtent& r) { return e.meetsWithTurns(r); });
        if (!reached) continue;
        tile.generation = 0;
        meshTileChanged_[key] = refreshesApplied_;
        failedTiles_.erase(key);
    }
    if (!regions.empty()) drapeChangedIn(std::move(regions));
}

void VectorLayer::drapeChangedIn(std::vector<globe::GeoExtent> regions) {
    if (!drape_) return;
    ++version_;
    drapeChanges_.emplace_back(version_, std::move(regions));
    while (drapeChanges_.size() > kDrapeChangesKept) drapeChanges_.pop_front();
}

std::optional<std::vector<globe::GeoExtent>> VectorLayer::drapeChangedSince(uint64_t version) const {
    std::vector<globe::GeoExtent> out;
    if (version >= version_) return out;
    // Every version after `version` must be known, each with its regions.
    if (drapeChanges_.empty() || drapeChanges_.front().first > version + 1) return std::nullopt;
    for (const auto& [v, regions] : drapeChanges_) {
        if (v <= version) continue;
        if (!regions) return std::nullopt;
        out.insert(out.end(), regions->begin(), regions->end());
    }
    if (out.size() > 4 * kBoxesKept) return std::nullopt;
    return out;
}

double VectorLayer::drapeReach() const { return pages_ ? pages_->options().margin : 0.5; }

}  // namespace orbis::layers
