#pragma once
// The vector layer's pager: a large source kept as feature tiles on the globe's quadtree, read
// as the view asks for them and held within a memory budget, so that only what is seen is in
// memory. A page holds the source's features near its tile (OGR's spatial filter: a source with
// a spatial index, GeoPackage, FlatGeobuf, Shapefile with .qix, reads only those), clipped to
// the tile grown by a margin and simplified for the tile's texel, with their styles bound and
// their times worked out (a VectorContent of its own). No Vulkan.
//
// Pages are read on the thread that asks (the terrain's workers, painting drape tiles): a tile
// of level L takes the page of its ancestor at min(L, pageLevel), and the tiles coarser than
// the finest one that holds the whole source take that one's page (the overview). Features are
// clipped and simplified as they are read, so a read holds what its page keeps, not what it
// scans. The finest pages keep every vertex, as they serve every finer tile. Two threads asking for one page share one read. Past
// the budget the pages least recently asked for go (a painter holding one keeps it until done).
//
// The margin is a quarter of the tile on each side: a drape tile paints strokes and markers
// that reach up to about a sixth of it past its edge, so the seams that clipping cuts along a
// page's edge (a polygon's clipped outline) lie outside anything a tile of that page paints.

#include "base/ThreadPool.h"
#include "globe/TileKey.h"
#include "layers/vector/VectorContent.h"

#include <chrono>
#include <cstdint>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <span>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace orbis::vector {

struct FeatureTile {
    globe::TileKey key;
    /// The features near the tile, clipped to its extent grown by the margin and simplified;
    /// each layer's style bound and times worked out as for the whole source.
    std::shared_ptr<const VectorContent> content;
    uint64_t bytes = 0;   ///< what the features hold (estimated)
    /// A hash of what was read (geometries, attributes, fids): a page read again with the same
    /// fingerprint shows the same thing.
    uint64_t fingerprint = 0;
};

/// A page that invalidate leaves outdated until `when` (FeatureTiles::invalidate).
struct DeferredRead {
    globe::GeoExtent extent;   ///< the page's, grown by the margin
    std::chrono::steady_clock::time_point when;
};

/// What FeatureTiles::refresh did.
struct PageRefresh {
    /// The pages whose content changed (read again with another fingerprint), and those that were
    /// being read, had failed, or had left memory since the last refresh of everything: each
    /// one's extent grown by the margin, where drape tiles must be painted again.
    std::vector<globe::GeoExtent> changed;
    size_t pagesRead = 0;
    /// Pages that could not be read again (they keep their old content): the first message.
    size_t failed = 0;
    std::string error;
};

struct FeatureTilesOptions {
    VectorContentOptions content;     ///< source, layers, where or sql (within is set per page), style, times
    uint32_t pageLevel = 12;          ///< the finest pages (about 5 km at level 12); finer tiles use them
    double tilePixels = 256.0;        ///< a coarser page is simplified to half its size / this
    double margin = 0.25;             ///< of the tile's size, on each side
    uint64_t budgetBytes = 256ull << 20;
    /// The source's extent, when known: tiles coarser than the finest one whose page holds the
    /// whole source share that page (one read for every overview).
    std::optional<LonLatBounds> sourceBounds;
    /// Each feature in the one tile that holds the centre of its box, whole (neither clipped
    /// nor simplified, no margin): what meshes need, a building drawn once and entire.
    bool owned = false;
    /// invalidate: a page whose last read took longer is read again only after four times that
    /// (FeatureTiles::invalidate).
    std::chrono::microseconds quickRead{25000};
};

class FeatureTiles {
public:
    explicit FeatureTiles(FeatureTilesOptions options);

    /// The page holding what tiles of `key` need, read on this thread when it is not in
    /// memory (another thread reading it: waited for, `cancel` checked meanwhile, throwing
    /// jobs::Cancelled). A page that failed to read fails again without a new read until
    /// kRetryDelay (doubling with each failure in a row) has passed; its error is in errors().
    /// Any thread.
    Result<std::shared_ptr<const FeatureTile>> acquire(const globe::TileKey& key, const jobs::CancelToken* cancel = nullptr);
    /// The page a tile of `key` takes.
    globe::TileKey pageFor(const globe::TileKey& key) const;

    const FeatureTilesOptions& options() const { return options_; }
    uint64_t bytes() const;
    size_t loadedCount() const;
    uint64_t reads() const;   ///< pages read since the start (reads again after eviction count)
    /// The last few read errors (kErrorsKept), oldest first.
    std::vector<std::string> errors() const;
    /// Pages whose last read failed (until they are read again), and the last error.
    size_t failingCount() const;
    std::string lastError() const;
    /// The pages in memory now.
    std::vector<std::shared_ptr<const FeatureTile>> loaded() const;
    /// Counts the pages read, replaced and dropped: what is in memory changed when it did.
    uint64_t changes() const;

    /// The source changed within `boxes` (lon/lat): the pages in memory they reach are read
    /// again by the next acquire (the first asking reads, the others wait for it), their old
    /// content in loaded() until then, and served again if that read fails; pages being read
    /// are not kept; failed ones are forgotten. Quick: no read here. Any thread.
    /// A page that took long to read (more than options().quickRead) is read again only after
    /// four times its read time: the result names these, with when (tiles painted before then
    /// show the old content: paint them again at that time).
    std::vector<DeferredRead> invalidate(std::span<const LonLatBounds> boxes);

    /// The source changed within `boxes` (lon/lat; empty: anywhere). Each page in memory that
    /// reaches into a box is read again on this thread and replaced when its fingerprint
    /// differs (a page that cannot be read keeps its content: the error is in the result);
    /// a page being read or one that failed is forgotten, so that the next acquire reads it
    /// anew. Whoever holds an old page keeps it. With `boxes` empty, the result also names
    /// the pages evicted since the last such refresh (tiles painted from them may be stale).
    PageRefresh refresh(std::span<const LonLatBounds> boxes, const jobs::CancelToken* cancel = nullptr);

    /// A page whose read failed is read again when asked for after this long (then twice
    /// that, up to 8 times): a server that was down comes back.
    static constexpr std::chrono::milliseconds kRetryDelay{1000};

private:
    using Loaded = Result<std::shared_ptr<const FeatureTile>>;
    struct Entry {
        std::shared_future<Loaded> future;
        std::list<globe::TileKey>::iterator use;   ///< its place in uses_ (most recent first)
        uint64_t bytes = 0;
        bool done = false;
        /// The source changed while it was being read: not kept when done.
        bool stale = false;
        /// Outdated (invalidate): the content shown until a read replaces it; the next
        /// acquire reads it again.
        std::shared_ptr<const FeatureTile> shown;
        std::chrono::microseconds readTime{0};   ///< how long its last read took
        /// Failed reads in a row, and when the next may start.
        uint32_t failures = 0;
        std::chrono::steady_clock::time_point retryAt{};
    };
    void evictLocked(const globe::TileKey& keep);
    void noteErrorLocked(std::string message);
    /// The page's extent grown by the margin (what its read covers).
    globe::GeoExtent grownExtent(const globe::TileKey& page) const;

    FeatureTilesOptions options_;
    std::optional<globe::TileKey> overview_;   ///< the page of every tile at its level or coarser
    mutable std::mutex mutex_;
    std::unordered_map<globe::TileKey, Entry, globe::TileKeyHash> entries_;
    std::list<globe::TileKey> uses_;
    uint64_t bytes_ = 0, reads_ = 0, changes_ = 0;
    std::vector<std::string> errors_;   ///< the last few
    std::string lastError_;
    static constexpr size_t kErrorsKept = 8;
    /// Pages evicted since the last refresh of everything (at most kEvictedKept; past that,
    /// everything).
    std::vector<globe::TileKey> evicted_;
    bool evictedOverflow_ = false;
    static constexpr size_t kEvictedKept = 4096;
};

/// The labelled features of `pages` as one content, each feature once (by layer and fid: the
/// piece from the finest page, the largest among pages of one level; features without a fid
/// from every page), with their times and own styles: what labels need of a paged source.
/// `style`: the layer's style as the scene has it (its rules switched on or off), bound to the
/// pages' fields.
std::shared_ptr<VectorContent> labelledFeatures(std::span<const std::shared_ptr<const FeatureTile>> pages, const VectorStyle& style);

/// One page (what acquire reads): the features near `key`'s extent grown by the margin, clipped
/// to it, simplified for its level (not at pageLevel or finer), styled and timed.
Result<FeatureTile> loadFeatureTile(const FeatureTilesOptions& options, const globe::TileKey& key);

}  // namespace orbis::vector
