#pragma once
// The terrain's tiles on the CPU: the raster sources, the tile pager (loads on the engine's
// worker pool with priorities and cancellation) and the LRU tile cache with a byte budget. It
// knows which tile data is ready, which ancestor stands in for missing data (scale/bias
// fallback), the height range of a tile for culling, and answers heightAt() over the loaded
// data. No Vulkan: the terrain layer uploads what this holds.
//
// Data layers: layer 0 is elevation (every DEM composited: the finest source wins, its holes
// are filled by coarser sources, then by the parent tile, then by the ellipsoid); layers
// 1..N are the image layers (TileImageSource: the scene's imagery files, then what other
// layers drape on the ground), in the order they were added.
//
// Loading goes one level at a time down each tile's chain of ancestors, so coarse data always
// arrives first and every tile has an ancestor to stand in for it.

#include "base/ThreadPool.h"
#include "globe/RasterSource.h"
#include "globe/TileImageSource.h"
#include "globe/TileKey.h"
#include "globe/TileSelector.h"

#include <atomic>
#include <cstdint>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <span>
#include <vector>

namespace orbis::globe {

/// Heights of a tile's corner-aligned grid (row 0 north), never NaN, and their gradients.
struct ElevationData {
    int size = 0;
    std::vector<float> heights;
    /// Per sample: the height change per sample step east, then south (central differences
    /// that reach one sample into the neighbouring tiles, so that normals interpolated from them
    /// match across tile edges; one-sided where the neighbour has no data).
    std::vector<float> gradients;
    float minHeight = 0.0f, maxHeight = 0.0f;
    size_t bytes() const { return sizeof(*this) + (heights.size() + gradients.size()) * sizeof(float); }
    /// Bilinear height at tile texture coordinates (u east, v south, 0..1, corner-aligned).
    float sample(double u, double v) const;
};

/// An imagery tile with its full mip chain (sRGB RGBA8, level 0 first, each level tightly packed).
struct ImageryData {
    int size = 0;
    std::vector<uint8_t> rgba;
    std::vector<size_t> mipOffsets;   ///< byte offset of each level in rgba
    size_t bytes() const { return sizeof(*this) + rgba.size(); }
    int mipLevels() const { return int(mipOffsets.size()); }
};

/// Builds the mip chain of a square RGBA8 sRGB image (box filter in linear light, alpha-weighted).
ImageryData buildImageryMips(int size, std::vector<uint8_t> rgbaLevel0);

struct DataKey {
    uint32_t layer = 0;
    TileKey tile;
    bool operator==(const DataKey&) const = default;
};
struct DataKeyHash {
    size_t operator()(const DataKey& k) const noexcept { return TileKeyHash{}(k.tile) * 31u + k.layer; }
};

enum class DataState { Missing, Loading, Ready, Empty, Failed };

struct TerrainTilesSettings {
    int gridSize = 65;                           ///< elevation samples per tile side
    int imageSize = 256;                         ///< imagery pixels per tile side
    uint64_t cpuBudgetBytes = 256ull << 20;      ///< tile data kept in memory
    uint32_t maxLevel = 22;
    /// Passed to image sources (TileImageRequest): tile pixels per screen pixel where tiles
    /// are drawn.
    double tilePixelsPerScreenPixel = 1.0;
};

/// A tile whose load failed (a server down, a timeout, a damaged file) is tried again while it
/// stays wanted, after kTileRetryDelay, then twice that, and so on, kTileRetries times.
inline constexpr uint32_t kTileRetries = 4;
inline constexpr std::chrono::milliseconds kTileRetryDelay{1000};

struct PagerStats {
    uint64_t started = 0, completed = 0, cancelled = 0, failed = 0, empty = 0;
    uint64_t retried = 0;        ///< loads started again after a failure
    uint64_t evicted = 0;
    size_t loading = 0;          ///< jobs queued or running now
    uint64_t loadNanoseconds = 0;  ///< summed time inside load functions (worker threads)
};

class TerrainTiles {
public:
    /// `pool` may be null: loads then run inline inside request() (tests, tools).
    TerrainTiles(const TerrainTilesSettings& settings, std::vector<std::shared_ptr<RasterSource>> elevation,
                 std::vector<std::shared_ptr<const TileImageSource>> imagery, jobs::ThreadPool* pool);
    ~TerrainTiles();
    TerrainTiles(const TerrainTiles&) = delete;
    TerrainTiles& operator=(const TerrainTiles&) = delete;

    const TerrainTilesSettings& settings() const { return settings_; }
    uint32_t layerCount() const { return uint32_t(1 + imagery_.size()); }
    bool hasElevation() const { return !elevation_.empty(); }
    /// Deepest level at which a layer has data worth loading.
    uint32_t maxDataLevel(uint32_t layer) const;
    /// Coarsest level a layer can be read at (huge files without overviews start deeper).
    uint32_t minDataLevel(uint32_t layer) const;

    /// Adds an image layer after the others; returns its layer number. Main thread.
    uint32_t addImagery(std::shared_ptr<const TileImageSource> source);
    /// Replaces an image layer's source (what it paints changed): loads in flight are
    /// cancelled, and each cached tile is painted again when it is next requested, its old
    /// image served meanwhile (stale while repainting: a repaint never shows a hole). A tile's
    /// dataGeneration tells which source its data came from. Main thread.
    void replaceImagery(uint32_t layer, std::shared_ptr<const TileImageSource> source);
    /// The same when the new source paints differently only within `regions` (lon/lat; any
    /// turn): only the tiles whose extent, grown by `tileMargin` of their size on each side
    /// (what a tile's painting reaches past its edge), meets a region are painted again; the
    /// others keep their images and their GPU slots. Falls back to replaceImagery when the new
    /// source's finest level differs. Main thread.
    void repaintImagery(uint32_t layer, std::shared_ptr<const TileImageSource> source, std::span<const GeoExtent> regions,
                        double tileMargin);
    /// How many times the layer's source was replaced before the tile's data was loaded (0 for
    /// elevation, and for a tile not loaded).
    uint32_t dataGeneration(uint32_t layer, const TileKey& tile) const;

    bool hasPool() const { return pool_ != nullptr; }
    /// Loads run on `pool` from now on (a source added later needs it). Main thread.
    void setPool(jobs::ThreadPool* pool) { pool_ = pool; }

    /// Starts a frame: collects finished loads into the cache. Main thread.
    void beginFrame(uint64_t frameNumber);
    /// Asks for `tile`'s data in `layer`. Loads the next missing level on the way down from
    /// the deepest ready ancestor (coarse first), with a priority from the level and the
    /// distance to the camera (near first). Marks the data in use this frame (LRU).
    void request(uint32_t layer, const TileKey& tile, double distance);
    /// Ends a frame: cancels loads that nobody asked for this frame, trims the cache to its budget.
    void endFrame();

    DataState state(uint32_t layer, const TileKey& tile) const;
    /// The deepest ancestor-or-self of `tile` whose data in `layer` is ready, if any. With
    /// `emptyIsFinal` (a drape: nothing painted means transparent), an empty tile on the way up
    /// ends the search with nothing: a coarser tile's painting must not show through it.
    std::optional<TileKey> readyAncestor(uint32_t layer, const TileKey& tile, bool emptyIsFinal = false) const;
    std::shared_ptr<const ElevationData> elevation(const TileKey& tile) const;
    std::shared_ptr<const ImageryData> imagery(uint32_t layer, const TileKey& tile) const;

    /// Terrain height above the ellipsoid (metres, unexaggerated) from the finest loaded data;
    /// nothing when no loaded elevation tile covers the point.
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    /// Conservative height range of a tile from its own or an ancestor's loaded data.
    TileHeightRange heightRange(const TileKey& tile) const;

    /// Every piece of data loaded so far (Ready or Empty), for benchmarks.
    std::vector<DataKey> loadedKeys() const;
    /// The sources, finest elevation first.
    const std::vector<std::shared_ptr<RasterSource>>& elevationSources() const { return elevation_; }
    const std::vector<std::shared_ptr<const TileImageSource>>& imagerySources() const { return imagery_; }
    /// Blocks until every load in flight has finished and been collected (tests, batch renders).
    void waitIdle();
    bool loading() const { return loadingCount_ > 0; }
    uint64_t cpuBytes() const { return cpuBytes_; }
    const PagerStats& stats() const { return stats_; }
    /// Errors met so far, one line each (first few only).
    const std::vector<std::string>& errors() const { return errors_; }

private:
    struct LoadResult {
        std::shared_ptr<const ElevationData> elevation;
        std::shared_ptr<const ImageryData> imagery;
        bool empty = false;
        bool descend = false;   ///< empty here, but finer levels may have data
        std::string error;
        uint64_t nanoseconds = 0;
    };
    struct Entry {
        DataState state = DataState::Missing;
        std::shared_ptr<const ElevationData> elevation;
        std::shared_ptr<const ImageryData> imagery;
        size_t bytes = 0;
        bool descend = false;
        uint64_t lastUsed = 0;
        jobs::Job<LoadResult> job;   ///< while Loading, or refreshing
        /// Ready or Empty data from an older source, being painted again (job runs).
        bool refreshing = false;
        uint32_t generation = 0;          ///< the latest source generation the data is right for
        uint32_t paintedGeneration = 0;   ///< the generation whose load made the data (what GPU slots compare)
        uint32_t loadingGeneration = 0;   ///< the generation the running job paints
        /// Failed loads so far, and when the next attempt may start (back-off).
        uint32_t failures = 0;
        std::chrono::steady_clock::time_point retryAt{};
        bool busy() const { return state == DataState::Loading || refreshing; }
    };

    const Entry* find(uint32_t layer, const TileKey& tile) const;
    /// replaceImagery (regions null) and repaintImagery: the new source, and its tiles that the
    /// regions reach painted again.
    void repaint(uint32_t layer, std::shared_ptr<const TileImageSource> source, const std::span<const GeoExtent>* regions,
                 double tileMargin);
    /// Starts loading `key` (a Missing entry, or with `refresh` a stale Ready or Empty one, which
    /// keeps its data until the new arrives).
    void startLoad(const DataKey& key, Entry& entry, double priority, bool refresh = false);
    uint32_t currentGeneration(uint32_t layer) const { return layer < generations_.size() ? generations_[layer] : 0; }
    void finishLoad(const DataKey& key, Entry& entry, LoadResult result);
    void collectFinished();
    void trim();
    LoadResult loadElevation(const TileKey& tile, std::shared_ptr<const ElevationData> ancestor, uint32_t ancestorLevel,
                             const jobs::CancelToken& cancel) const;
    LoadResult loadImagery(const TileImageSource& source, const TileKey& tile, const jobs::CancelToken& cancel) const;
    void noteError(const std::string& message);

    TerrainTilesSettings settings_;
    std::vector<std::shared_ptr<RasterSource>> elevation_;   // finest first
    std::vector<std::shared_ptr<const TileImageSource>> imagery_;
    jobs::ThreadPool* pool_;
    std::unordered_map<DataKey, Entry, DataKeyHash> entries_;
    std::vector<jobs::Job<LoadResult>> orphans_;   ///< loads of replaced sources, still running
    uint64_t frame_ = 0;
    uint64_t cpuBytes_ = 0;
    size_t loadingCount_ = 0;
    std::vector<uint32_t> generations_;   ///< per layer: how many times its source was replaced
    uint32_t deepestElevation_ = 0;
    PagerStats stats_;
    std::vector<std::string> errors_;
};

}  // namespace orbis::globe
