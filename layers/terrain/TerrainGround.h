#pragma once
// The terrain's ground height for clamping and camera collision (Layer::groundHeightAt), the
// same for the same scene and place whatever the renderer has streamed. No Vulkan.
//
// Why not the renderer's tiles: they answer from the finest tile loaded, which depends on where
// the camera has been and what the cache evicted, so a vehicle clamped to the ground (or a camera
// kept above it) would stand higher or lower after one seek path than after another, and the
// same scene time would not give the same picture.
//
// What instead: a second, small TerrainTiles over the same DEMs (no imagery, no thread pool: its
// loads run inline, on the caller's thread) that is always asked at one level, the DEMs' own
// resolution (TerrainTiles::maxDataLevel(0) for the layer's grid size: the finest the renderer
// ever draws). A query loads that level's tile and its ancestors when they are not cached, then
// samples it bilinearly: the answer depends only on the DEMs and the point. The renderer's
// tiles approximate these heights within their screen-space error, so what stands on them
// stands on what is drawn.
//
// Bounds: the cache keeps at most kGroundCacheBytes between frames (LRU, endFrame()) and
// at most twice that within a frame (a frame that asks for more starts evicting at once). The
// first query in a new place reads a tile chain from GDAL on the calling thread (milliseconds);
// later ones nearby are a hash lookup and a bilinear sample (the last tile is remembered).

#include "globe/RasterSource.h"
#include "globe/TerrainTiles.h"

#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace orbis::layers {

inline constexpr uint64_t kGroundCacheBytes = 32ull << 20;

class TerrainGround {
public:
    /// `gridSize` and `maxLevel` as the renderer's (TerrainSettings); `dems` finest first or not.
    TerrainGround(int gridSize, uint32_t maxLevel, std::vector<std::shared_ptr<globe::RasterSource>> dems,
                  uint64_t cacheBytes = kGroundCacheBytes);

    /// Height above the ellipsoid (metres, unexaggerated) at a point: the ellipsoid (0) where no
    /// DEM covers it; nothing for an invalid point or without any DEM. Any thread (one query at
    /// a time inside); may read the DEMs.
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    /// Lets the cache drop what was not used since the last call. Once per frame, any thread.
    void endFrame();

    uint32_t level() const { return level_; }
    uint64_t cacheBytes() const;
    uint64_t tilesRead() const;

private:
    void newFrameLocked() const;

    uint32_t level_ = 0;
    uint64_t budget_;
    mutable std::mutex mutex_;
    mutable globe::TerrainTiles tiles_;
    mutable uint64_t frame_ = 1;
    mutable globe::TileKey lastKey_;
    mutable std::shared_ptr<const globe::ElevationData> last_;
};

}  // namespace orbis::layers
