#include "globe/ElevationSampler.h"

#include <algorithm>
#include <cmath>

namespace orbis::globe {

ElevationSampler::ElevationSampler(std::shared_ptr<const RasterSource> source, int tileSize, size_t cacheTiles)
    : source_(std::move(source)), tileSize_(std::clamp(tileSize, 2, 4096)), cacheTiles_(std::max<size_t>(cacheTiles, 1)),
      level_(source_ ? source_->maxLevel(tileSize_) : 0) {}

std::shared_ptr<const ElevationTile> ElevationSampler::tile(const TileKey& key) const {
    {
        std::lock_guard lock(mutex_);
        if (const auto it = tiles_.find(key); it != tiles_.end()) {
            recent_.splice(recent_.begin(), recent_, it->second.second);
            return it->second.first;
        }
    }
    auto read = source_->readElevation(key.extent(), tileSize_);
    std::shared_ptr<const ElevationTile> got;
    std::lock_guard lock(mutex_);
    ++reads_;
    if (!read) {
        if (error_.empty()) error_ = read.message();
        got = std::make_shared<const ElevationTile>();   // no data there: not read again
    } else {
        got = std::make_shared<const ElevationTile>(std::move(*read));
    }
    if (tiles_.contains(key)) return tiles_.at(key).first;
    recent_.push_front(key);
    tiles_.emplace(key, std::make_pair(got, recent_.begin()));
    while (tiles_.size() > cacheTiles_) {
        tiles_.erase(recent_.back());
        recent_.pop_back();
    }
    return got;
}

std::optional<double> ElevationSampler::heightAt(double lonDeg, double latDeg) const {
    if (!source_ || !std::isfinite(lonDeg) || !std::isfinite(latDeg) || latDeg < -90.0 || latDeg > 90.0) return std::nullopt;
    lonDeg = wrapLongitude(lonDeg);
    const TileKey key = TileKey::containing(lonDeg, latDeg, level_);
    const auto t = tile(key);
    if (!t->anyValid || t->size < 2) return std::nullopt;
    // Corner-aligned: sample (i, j) at west + i * width / (size - 1), north - j * height / (size - 1).
    const GeoExtent e = key.extent();
    const double n = double(t->size - 1);
    const double x = std::clamp((lonDeg - e.west) / (e.east - e.west) * n, 0.0, n);
    const double y = std::clamp((e.north - latDeg) / (e.north - e.south) * n, 0.0, n);
    const int i = std::min(int(x), t->size - 2), j = std::min(int(y), t->size - 2);
    const double fx = x - i, fy = y - j;
    const auto at = [&](int di, int dj) { return double(t->heights[size_t(j + dj) * size_t(t->size) + size_t(i + di)]); };
    const double h00 = at(0, 0), h10 = at(1, 0), h01 = at(0, 1), h11 = at(1, 1);
    // Where a neighbour has no data, the nearest sample alone (none when it has none).
    if (std::isnan(h00) || std::isnan(h10) || std::isnan(h01) || std::isnan(h11)) {
        const double nearest = at(fx < 0.5 ? 0 : 1, fy < 0.5 ? 0 : 1);
        if (std::isnan(nearest)) return std::nullopt;
        return nearest;
    }
    return (h00 * (1.0 - fx) + h10 * fx) * (1.0 - fy) + (h01 * (1.0 - fx) + h11 * fx) * fy;
}

HeightAt ElevationSampler::function(std::shared_ptr<const ElevationSampler> sampler) {
    return [sampler = std::move(sampler)](double lonDeg, double latDeg) { return sampler->heightAt(lonDeg, latDeg); };
}

uint64_t ElevationSampler::tilesRead() const {
    std::lock_guard lock(mutex_);
    return reads_;
}

std::string ElevationSampler::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

}  // namespace orbis::globe
