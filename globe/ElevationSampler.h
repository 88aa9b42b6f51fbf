#pragma once
// Heights at any lon/lat from an elevation source at its own resolution, for analysis (terrain
// profiles, lines of sight): not the tiles the view has streamed, whose level follows the
// camera. The source is read in tiles of `tileSize` samples at its finest level
// (RasterSource::maxLevel: tile pixels no larger than the source's), kept in a small cache
// (least recently used first out), and interpolated bilinearly between the four samples
// around the point. No data (nodata, outside the coverage, a read that failed): none.
//
// Thread-safe: a mutex guards the cache; reads happen outside it (two threads may read the
// same tile once each). The first read error is kept (error()).

#include "globe/RasterSource.h"
#include "globe/TerrainAnalysis.h"
#include "globe/TileKey.h"

#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace orbis::globe {

class ElevationSampler {
public:
    explicit ElevationSampler(std::shared_ptr<const RasterSource> source, int tileSize = 256, size_t cacheTiles = 64);

    /// The ground at a point (metres above the source's datum); none where there is no data.
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    /// As a function for TerrainAnalysis (shares this sampler).
    static HeightAt function(std::shared_ptr<const ElevationSampler> sampler);

    uint32_t level() const { return level_; }
    uint64_t tilesRead() const;
    std::string error() const;

private:
    std::shared_ptr<const ElevationTile> tile(const TileKey& key) const;

    std::shared_ptr<const RasterSource> source_;
    int tileSize_;
    size_t cacheTiles_;
    uint32_t level_;
    mutable std::mutex mutex_;
    mutable std::list<TileKey> recent_;   ///< most recent first
    mutable std::map<TileKey, std::pair<std::shared_ptr<const ElevationTile>, std::list<TileKey>::iterator>> tiles_;
    mutable uint64_t reads_ = 0;
    mutable std::string error_;
};

}  // namespace orbis::globe
