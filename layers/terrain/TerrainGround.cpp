#include "layers/terrain/TerrainGround.h"

#include <cmath>

namespace orbis::layers {
namespace {

globe::TerrainTilesSettings groundSettings(int gridSize, uint32_t maxLevel, uint64_t cacheBytes) {
    globe::TerrainTilesSettings s;
    s.gridSize = gridSize;
    s.maxLevel = maxLevel;
    s.cpuBudgetBytes = cacheBytes;
    return s;
}

}  // namespace

TerrainGround::TerrainGround(int gridSize, uint32_t maxLevel, std::vector<std::shared_ptr<globe::RasterSource>> dems,
                             uint64_t cacheBytes)
    : budget_(cacheBytes), tiles_(groundSettings(gridSize, maxLevel, cacheBytes), std::move(dems), {}, nullptr) {
    level_ = tiles_.hasElevation() ? tiles_.maxDataLevel(0) : 0;
    tiles_.beginFrame(frame_);
}

void TerrainGround::newFrameLocked() const {
    tiles_.endFrame();   // trims to the budget what the ending frame did not use
    tiles_.beginFrame(++frame_);
}

void TerrainGround::endFrame() {
    std::lock_guard lock(mutex_);
    newFrameLocked();
}

std::optional<double> TerrainGround::heightAt(double lonDeg, double latDeg) const {
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg) || latDeg < -90.0 || latDeg > 90.0) return std::nullopt;
    if (!tiles_.hasElevation()) return std::nullopt;   // no DEM: the layer knows no ground
    const double lon = lonDeg >= 180.0 ? lonDeg - 360.0 : lonDeg < -180.0 ? lonDeg + 360.0 : lonDeg;
    if (lon < -180.0 || lon >= 180.0) return std::nullopt;
    const globe::TileKey key = globe::TileKey::containing(lon, latDeg, level_);
    std::lock_guard lock(mutex_);
    if (!(last_ && key == lastKey_)) {
        // Over twice the budget inside one frame: evict now (before this query's tiles load).
        if (tiles_.cpuBytes() > 2 * budget_) newFrameLocked();
        tiles_.request(0, key, 0.0);
        last_ = tiles_.elevation(key);   // null unless the tile at the query level is ready
        lastKey_ = key;
        // Not ready: no DEM here (an empty ancestor: the ellipsoid) or a read failed (the
        // finest ancestor read, the same every time).
        if (!last_) return tiles_.heightAt(lon, latDeg);
    }
    const globe::GeoExtent x = key.extent();
    return last_->sample((lon - x.west) / x.width(), (x.north - latDeg) / x.height());
}

uint64_t TerrainGround::cacheBytes() const {
    std::lock_guard lock(mutex_);
    return tiles_.cpuBytes();
}

uint64_t TerrainGround::tilesRead() const {
    std::lock_guard lock(mutex_);
    return tiles_.stats().completed;
}

}  // namespace orbis::layers
