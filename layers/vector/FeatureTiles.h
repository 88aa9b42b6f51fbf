#pragma once
// The feature tiles of a vector source, loaded on the engine's worker pool as the view asks for
// them and kept within a memory budget, so that only what is seen is in memory (the vector
// layer's pager). A tile holds the source's features near it (OGR's spatial filter: a source with
// a spatial index reads only those), clipped to the tile and simplified for its texel. No Vulkan.
//
// Main thread: request() each tile a frame needs, then poll() once a frame. Loads run on the
// pool; a load that no frame asked for since it was queued is cancelled; past the budget, the
// tiles least recently requested go first (never one requested this frame).

#include "base/ThreadPool.h"
#include "globe/TileKey.h"
#include "layers/vector/VectorReader.h"

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace orbis::vector {

struct FeatureTile {
    globe::TileKey key;
    std::vector<Feature> features;   ///< clipped to the tile, simplified for its texel
    uint64_t bytes = 0;              ///< what the features hold (estimated)
    std::vector<std::string> warnings;
};

struct FeatureTilesOptions {
    VectorReadOptions read;           ///< source, layers, where or sql (within is set per tile)
    double tilePixels = 256.0;        ///< a tile's texels across: the simplification tolerance is its size / this
    uint64_t budgetBytes = 256ull << 20;
};

class FeatureTiles {
public:
    FeatureTiles(FeatureTilesOptions options, jobs::ThreadPool& pool);
    ~FeatureTiles();

    /// The tile if loaded (and marks it used this frame); else queues its load at `priority`
    /// (higher first) and returns null. A tile that failed to load returns null and is not
    /// retried; its error is in errors().
    const FeatureTile* request(const globe::TileKey& key, double priority, uint64_t frame);
    /// Takes finished loads, cancels loads no frame asked for since `frame - 1`, and evicts past
    /// the budget. Main thread, once a frame.
    void poll(uint64_t frame);

    uint64_t bytes() const { return bytes_; }
    size_t loadedCount() const;
    size_t pendingCount() const;
    const std::vector<std::string>& errors() const { return errors_; }

private:
    struct Entry {
        std::shared_ptr<FeatureTile> tile;   ///< null while loading or after a failure
        jobs::Job<Result<FeatureTile>> job;
        jobs::CancelToken cancel;
        uint64_t lastFrame = 0;
        bool failed = false;
    };

    FeatureTilesOptions options_;
    jobs::ThreadPool& pool_;
    std::unordered_map<globe::TileKey, Entry, globe::TileKeyHash> entries_;
    uint64_t bytes_ = 0;
    std::vector<std::string> errors_;
};

/// One tile's features (what a load job does): read within its extent, clipped, simplified.
Result<FeatureTile> loadFeatureTile(const FeatureTilesOptions& options, const globe::TileKey& key);

}  // namespace orbis::vector
