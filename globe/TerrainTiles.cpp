#include "globe/TerrainTiles.h"

#include "base/Log.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

namespace orbis::globe {
namespace {

constexpr uint32_t kPinnedLevels = 1;   // levels 0 and 1 stay cached: every tile's last resort

double priorityFor(uint32_t level, double distance) {
    // Coarse first, then near first (distances up to 1e9 m stay below one level's step).
    return -(double(level) * 1.0e6 + std::min(std::max(distance, 0.0), 9.9e8) / 1.0e3);
}

struct SrgbTables {
    std::array<float, 256> toLinear{};
    std::array<uint8_t, 4096> toSrgb{};
    SrgbTables() {
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            toLinear[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        for (int i = 0; i < 4096; ++i) {
            const double l = i / 4095.0;
            const double s = l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
            toSrgb[size_t(i)] = uint8_t(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
        }
    }
};
const SrgbTables& srgb() {
    static const SrgbTables tables;
    return tables;
}

/// A tile's heights and gradients from the composited samples `g` ((n + 2)^2, a one-sample
/// border, NaN where no source had data), holes and border filled from `parent` (the nearest
/// loaded ancestor, at `sb` within it) or the ellipsoid.
std::shared_ptr<ElevationData> fillElevation(std::vector<float> g, int n, const ElevationData* parent, const glm::dvec4& sb) {
    const int m = n + 2;
    auto data = std::make_shared<ElevationData>();
    data->size = n;
    // Holes: the nearest loaded ancestor's heights at the same place, else the ellipsoid.
    // Never a spike.
    const auto at = [&](int i, int j) -> float& { return g[size_t((j + 1) * m + (i + 1))]; };   // i, j in -1..n
    std::vector<float> h(size_t(n) * size_t(n));
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float& v = at(i, j);
            if (!std::isfinite(v)) {
                const double u = double(i) / (n - 1), w = double(j) / (n - 1);
                v = parent ? parent->sample(u * sb.x + sb.z, w * sb.y + sb.w) : 0.0f;
            }
            h[size_t(j * n + i)] = v;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    // Border samples without data: the ancestor's where it reaches them (as for holes), else
    // (beyond a pole or the antimeridian, past every DEM) extrapolated linearly, which makes the
    // difference there one-sided.
    if (parent) {
        const auto fill = [&](int i, int j) {
            float& v = at(i, j);
            const double u = (double(i) / (n - 1)) * sb.x + sb.z, w = (double(j) / (n - 1)) * sb.y + sb.w;
            if (!std::isfinite(v) && u >= 0.0 && u <= 1.0 && w >= 0.0 && w <= 1.0) v = parent->sample(u, w);
        };
        for (int k = 0; k < n; ++k) fill(-1, k), fill(n, k), fill(k, -1), fill(k, n);
    }
    for (int k = 0; k < n; ++k) {
        if (!std::isfinite(at(-1, k))) at(-1, k) = 2.0f * at(0, k) - at(1, k);
        if (!std::isfinite(at(n, k))) at(n, k) = 2.0f * at(n - 1, k) - at(n - 2, k);
        if (!std::isfinite(at(k, -1))) at(k, -1) = 2.0f * at(k, 0) - at(k, 1);
        if (!std::isfinite(at(k, n))) at(k, n) = 2.0f * at(k, n - 1) - at(k, n - 2);
    }
    data->gradients.resize(size_t(n) * size_t(n) * 2);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            data->gradients[size_t(j * n + i) * 2] = 0.5f * (at(i + 1, j) - at(i - 1, j));
            data->gradients[size_t(j * n + i) * 2 + 1] = 0.5f * (at(i, j + 1) - at(i, j - 1));
        }
    data->heights = std::move(h);
    data->minHeight = lo;
    data->maxHeight = hi;
    return data;
}

}  // namespace

float ElevationData::sample(double u, double v) const {
    const double x = std::clamp(u, 0.0, 1.0) * (size - 1), y = std::clamp(v, 0.0, 1.0) * (size - 1);
    const int x0 = std::min(int(x), size - 2), y0 = std::min(int(y), size - 2);
    const double fx = x - x0, fy = y - y0;
    const auto h = [&](int i, int j) { return double(heights[size_t(j * size + i)]); };
    return float((h(x0, y0) * (1 - fx) + h(x0 + 1, y0) * fx) * (1 - fy) +
                 (h(x0, y0 + 1) * (1 - fx) + h(x0 + 1, y0 + 1) * fx) * fy);
}

ImageryData buildImageryMips(int size, std::vector<uint8_t> level0) {
    ImageryData out;
    out.size = size;
    out.rgba = std::move(level0);
    out.mipOffsets.push_back(0);
    const SrgbTables& t = srgb();
    int s = size;
    size_t src = 0;
    while (s > 1) {
        const int d = s / 2;
        const size_t dst = out.rgba.size();
        out.mipOffsets.push_back(dst);
        out.rgba.resize(dst + size_t(d) * size_t(d) * 4);
        for (int y = 0; y < d; ++y)
            for (int x = 0; x < d; ++x) {
                float c[3] = {0, 0, 0}, a = 0;
                for (int k = 0; k < 4; ++k) {
                    const size_t p = src + (size_t(2 * y + (k >> 1)) * size_t(s) + size_t(2 * x + (k & 1))) * 4;
                    const float w = out.rgba[p + 3] / 255.0f;
                    for (int ch = 0; ch < 3; ++ch) c[ch] += t.toLinear[out.rgba[p + size_t(ch)]] * w;
                    a += w;
                }
                uint8_t* o = &out.rgba[dst + (size_t(y) * size_t(d) + size_t(x)) * 4];
                for (int ch = 0; ch < 3; ++ch)
                    o[ch] = a > 0 ? t.toSrgb[size_t(std::lround(std::clamp(c[ch] / a, 0.0f, 1.0f) * 4095.0f))] : 0;
                o[3] = uint8_t(std::lround(a / 4.0f * 255.0f));
            }
        src = dst;
        s = d;
    }
    return out;
}

TerrainTiles::TerrainTiles(const TerrainTilesSettings& settings, std::vector<std::shared_ptr<RasterSource>> elevation,
                           std::vector<std::shared_ptr<const TileImageSource>> imagery, jobs::ThreadPool* pool)
    : settings_(settings), elevation_(std::move(elevation)), imagery_(std::move(imagery)), pool_(pool) {
    // Finest first: its samples win, coarser sources only fill its holes.
    std::stable_sort(elevation_.begin(), elevation_.end(),
                     [](const auto& a, const auto& b) { return a->resolutionDeg() < b->resolutionDeg(); });
}

uint32_t TerrainTiles::addImagery(std::shared_ptr<const TileImageSource> source) {
    imagery_.push_back(std::move(source));
    return uint32_t(imagery_.size());
}

void TerrainTiles::replaceImagery(uint32_t layer, std::shared_ptr<const TileImageSource> source) {
    repaint(layer, std::move(source), nullptr, 0.0);
}

void TerrainTiles::repaintImagery(uint32_t layer, std::shared_ptr<const TileImageSource> source,
                                  std::span<const GeoExtent> regions, double tileMargin) {
    if (layer == 0 || layer > imagery_.size()) return;
    // Another finest level: every tile again (see repaint).
    const bool sameLevels = source->maxLevel(settings_.imageSize) == imagery_[layer - 1]->maxLevel(settings_.imageSize);
    repaint(layer, std::move(source), sameLevels ? &regions : nullptr, tileMargin);
}

void TerrainTiles::repaint(uint32_t layer, std::shared_ptr<const TileImageSource> source, const std::span<const GeoExtent>* regions,
                           double tileMargin) {
    if (layer == 0 || layer > imagery_.size()) return;
    const uint32_t previous = currentGeneration(layer);
    imagery_[layer - 1] = std::move(source);
    if (generations_.size() <= layer) generations_.resize(layer + 1, 0);
    const uint32_t now = ++generations_[layer];
    // Whether the change reaches a tile: its extent, grown by the margin, meets a region (a
    // turn either way included). Without regions, every tile.
    const auto reached = [&](const TileKey& tile) {
        if (!regions) return true;
        GeoExtent e = tile.extent();
        const double m = tileMargin * tile.sizeDeg();
        e = {e.west - m, e.south - m, e.east + m, e.north + m};
        return std::any_of(regions->begin(), regions->end(), [&](const GeoExtent& r) { return e.meetsWithTurns(r); });
    };
    // Tiles finer than the new source paints are never asked for again: were they kept, their
    // old images would stand in for their ancestors' new ones for good.
    const uint32_t finest = maxDataLevel(layer);
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& e = it->second;
        if (it->first.layer != layer) {
            ++it;
            continue;
        }
        if (!reached(it->first.tile)) {
            // The new source paints this tile as the last one did: what it has (or is painting)
            // from the last source stays right.
            if (e.generation == previous) e.generation = now;
            if (e.busy() && e.loadingGeneration == previous) e.loadingGeneration = now;
            ++it;
            continue;
        }
        if (e.busy()) {
            // A running load holds its own source; it finishes on its own and its result is
            // dropped (kept until then: it uses this object).
            e.job.cancel();
            if (!e.job.ready()) orphans_.push_back(std::move(e.job));
            e.job = {};
            --loadingCount_;
            ++stats_.cancelled;
            e.refreshing = false;
        }
        // What was painted stays on show until its repaint arrives (request starts it); what
        // had nothing yet, or failed, starts again.
        if ((e.state == DataState::Ready || e.state == DataState::Empty) && it->first.tile.level <= finest) {
            ++it;
            continue;
        }
        cpuBytes_ -= e.bytes;
        it = entries_.erase(it);
    }
    stats_.loading = loadingCount_;
}

uint32_t TerrainTiles::dataGeneration(uint32_t layer, const TileKey& tile) const {
    const Entry* e = find(layer, tile);
    return e ? e->paintedGeneration : 0;
}

TerrainTiles::~TerrainTiles() {
    for (auto& [key, e] : entries_)
        if (e.busy()) e.job.cancel();
    for (auto& [key, e] : entries_)
        if (e.busy()) e.job.wait();
    for (auto& job : orphans_) job.wait();
}

uint32_t TerrainTiles::maxDataLevel(uint32_t layer) const {
    uint32_t level = 0;
    if (layer == 0) {
        for (const auto& s : elevation_) level = std::max(level, s->maxLevel(settings_.gridSize));
    } else if (layer - 1 < imagery_.size()) {
        level = imagery_[layer - 1]->maxLevel(settings_.imageSize);
    }
    return std::min(level, settings_.maxLevel);
}

uint32_t TerrainTiles::minDataLevel(uint32_t layer) const {
    uint32_t level = std::numeric_limits<uint32_t>::max();
    if (layer == 0) {
        for (const auto& s : elevation_) level = std::min(level, s->minLevel());
    } else if (layer - 1 < imagery_.size()) {
        level = imagery_[layer - 1]->minLevel();
    }
    return level == std::numeric_limits<uint32_t>::max() ? 0 : level;
}

const TerrainTiles::Entry* TerrainTiles::find(uint32_t layer, const TileKey& tile) const {
    const auto it = entries_.find(DataKey{layer, tile});
    return it == entries_.end() ? nullptr : &it->second;
}

DataState TerrainTiles::state(uint32_t layer, const TileKey& tile) const {
    const Entry* e = find(layer, tile);
    return e ? e->state : DataState::Missing;
}

std::optional<TileKey> TerrainTiles::readyAncestor(uint32_t layer, const TileKey& tile, bool emptyIsFinal) const {
    for (int level = int(tile.level); level >= 0; --level) {
        const TileKey k = tile.ancestor(uint32_t(level));
        const Entry* e = find(layer, k);
        if (e && e->state == DataState::Ready) return k;
        if (e && emptyIsFinal && e->state == DataState::Empty) return std::nullopt;
    }
    return std::nullopt;
}

std::shared_ptr<const ElevationData> TerrainTiles::elevation(const TileKey& tile) const {
    const Entry* e = find(0, tile);
    return e && e->state == DataState::Ready ? e->elevation : nullptr;
}

std::shared_ptr<const ImageryData> TerrainTiles::imagery(uint32_t layer, const TileKey& tile) const {
    const Entry* e = find(layer, tile);
    return e && e->state == DataState::Ready ? e->imagery : nullptr;
}

void TerrainTiles::beginFrame(uint64_t frameNumber) {
    frame_ = frameNumber;
    collectFinished();
}

void TerrainTiles::request(uint32_t layer, const TileKey& tile, double distance) {
    if (layer >= layerCount() || (layer == 0 && elevation_.empty())) return;
    const uint32_t maxLevel = std::min(tile.level, maxDataLevel(layer));
    // Walk down from the coarsest readable level: touch what is ready, stop at the first level
    // that is not.
    for (uint32_t level = minDataLevel(layer); level <= maxLevel; ++level) {
        const DataKey key{layer, tile.ancestor(level)};
        Entry& e = entries_[key];
        e.lastUsed = frame_;
        // Data from a replaced source serves while it is painted again.
        const bool stale = (e.state == DataState::Ready || e.state == DataState::Empty) && e.generation != currentGeneration(layer);
        if (stale && e.refreshing) e.job.setPriority(priorityFor(level, distance));
        if (stale && !e.refreshing) startLoad(key, e, priorityFor(level, distance), true);
        switch (e.state) {
            case DataState::Ready:
                continue;
            case DataState::Empty:
                if (e.descend) continue;   // nothing here, but finer tiles may have data
                return;                    // nothing finer below
            case DataState::Failed:
                // Tried again after a back-off (a server that was down, a timeout), a few times.
                if (e.failures <= kTileRetries && std::chrono::steady_clock::now() >= e.retryAt) {
                    ++stats_.retried;
                    startLoad(key, e, priorityFor(level, distance));
                    if (e.state == DataState::Ready) continue;
                }
                return;
            case DataState::Loading:
                e.job.setPriority(priorityFor(level, distance));
                return;
            case DataState::Missing:
                startLoad(key, e, priorityFor(level, distance));
                if (e.state != DataState::Ready) return;   // inline loads may finish at once
                continue;
        }
    }
}

void TerrainTiles::startLoad(const DataKey& key, Entry& entry, double priority, bool refresh) {
    ++stats_.started;
    std::shared_ptr<const ElevationData> parent;
    uint32_t parentLevel = 0;
    if (key.layer == 0 && key.tile.level > 0)
        if (auto a = readyAncestor(0, key.tile.parent())) {
            parent = elevation(*a);
            parentLevel = a->level;
        }
    // The job holds its image source: the layer's source may be replaced while it runs.
    std::shared_ptr<const TileImageSource> image = key.layer == 0 ? nullptr : imagery_[key.layer - 1];
    auto work = [this, key, parent, parentLevel, image](const jobs::CancelToken& cancel) -> LoadResult {
        const auto t0 = std::chrono::steady_clock::now();
        LoadResult r = key.layer == 0 ? loadElevation(key.tile, parent, parentLevel, cancel)
                                      : loadImagery(*image, key.tile, cancel);
        r.nanoseconds = uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count());
        return r;
    };
    entry.loadingGeneration = currentGeneration(key.layer);
    if (!pool_) {
        finishLoad(key, entry, work(jobs::CancelToken{}));
        return;
    }
    if (refresh) entry.refreshing = true;
    else entry.state = DataState::Loading;
    entry.job = pool_->submit(priority, jobs::CancelToken{}, std::move(work));
    ++loadingCount_;
}

void TerrainTiles::finishLoad(const DataKey& key, Entry& e, LoadResult r) {
    stats_.loadNanoseconds += r.nanoseconds;
    // A repaint replaces the data it served meanwhile.
    cpuBytes_ -= e.bytes;
    e.bytes = 0;
    e.elevation.reset();
    e.imagery.reset();
    e.refreshing = false;
    e.generation = e.paintedGeneration = e.loadingGeneration;
    if (!r.error.empty()) {
        e.state = DataState::Failed;
        ++stats_.failed;
        // 1 s, 2 s, 4 s, ... before the next attempt; after kTileRetries of them it stays failed
        // until it leaves the view and comes back.
        ++e.failures;
        e.retryAt = std::chrono::steady_clock::now() + kTileRetryDelay * (1u << std::min(e.failures - 1, 10u));
        noteError(r.error);
        return;
    }
    e.failures = 0;
    ++stats_.completed;
    if (r.empty) {
        e.state = DataState::Empty;
        e.descend = r.descend;
        ++stats_.empty;
        e.bytes = sizeof(Entry);
    } else {
        e.state = DataState::Ready;
        e.elevation = std::move(r.elevation);
        e.imagery = std::move(r.imagery);
        e.bytes = sizeof(Entry) + (e.elevation ? e.elevation->bytes() : 0) + (e.imagery ? e.imagery->bytes() : 0);
        if (key.layer == 0) deepestElevation_ = std::max(deepestElevation_, key.tile.level);
    }
    cpuBytes_ += e.bytes;
}

void TerrainTiles::collectFinished() {
    std::erase_if(orphans_, [](const jobs::Job<LoadResult>& job) { return job.ready(); });
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& e = it->second;
        if (e.busy() && e.job.ready()) {
            --loadingCount_;
            // A cancelled load leaves nothing; a cancelled repaint leaves the old data.
            const auto cancelled = [&] {
                ++stats_.cancelled;
                if (e.refreshing) {
                    e.refreshing = false;
                    e.job = {};
                    ++it;
                } else {
                    it = entries_.erase(it);
                }
            };
            if (e.job.cancelled()) {
                cancelled();
                continue;
            }
            LoadResult r;
            try {
                r = e.job.get();
            } catch (const jobs::Cancelled&) {
                cancelled();
                continue;
            } catch (const std::exception& ex) {
                r.error = std::string("tile load failed: ") + ex.what();
            }
            e.job = {};
            finishLoad(it->first, e, std::move(r));
        }
        ++it;
    }
    stats_.loading = loadingCount_;
}

void TerrainTiles::endFrame() {
    // Loads nobody asked for this frame are no longer wanted: drop them from the queue (a
    // running one finishes and its result is kept if it arrives before the entry is gone).
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& e = it->second;
        if (e.busy() && e.lastUsed < frame_) {
            e.job.cancel();
            if (e.job.ready() && e.refreshing) {   // a repaint cancelled while queued: the old data stays
                --loadingCount_;
                ++stats_.cancelled;
                e.refreshing = false;
                e.job = {};
            } else if (e.job.ready()) {   // cancelled while queued: gone now
                --loadingCount_;
                ++stats_.cancelled;
                it = entries_.erase(it);
                continue;
            }
        } else if (e.state == DataState::Missing) {
            it = entries_.erase(it);
            continue;
        }
        ++it;
    }
    stats_.loading = loadingCount_;
    trim();
}

void TerrainTiles::trim() {
    if (cpuBytes_ <= settings_.cpuBudgetBytes) return;
    std::vector<std::pair<uint64_t, DataKey>> candidates;
    for (const auto& [key, e] : entries_)
        if ((e.state == DataState::Ready || e.state == DataState::Empty || e.state == DataState::Failed) && !e.refreshing &&
            e.lastUsed < frame_ && key.tile.level > kPinnedLevels)
            candidates.emplace_back(e.lastUsed * 64 + (63 - std::min<uint64_t>(key.tile.level, 63)), key);
    // Oldest first; among equals, the finest first (a parent outlives its children).
    std::sort(candidates.begin(), candidates.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [age, key] : candidates) {
        if (cpuBytes_ <= settings_.cpuBudgetBytes) break;
        auto it = entries_.find(key);
        cpuBytes_ -= it->second.bytes;
        entries_.erase(it);
        ++stats_.evicted;
    }
}

std::vector<DataKey> TerrainTiles::loadedKeys() const {
    std::vector<DataKey> keys;
    for (const auto& [key, e] : entries_)
        if (e.state == DataState::Ready || e.state == DataState::Empty) keys.push_back(key);
    return keys;
}

void TerrainTiles::waitIdle() {
    while (loadingCount_ > 0) {
        for (auto& [key, e] : entries_)
            if (e.busy()) e.job.wait();
        collectFinished();
    }
}

std::optional<double> TerrainTiles::heightAt(double lonDeg, double latDeg) const {
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg) || latDeg < -90.0 || latDeg > 90.0) return std::nullopt;
    const double lon = lonDeg >= 180.0 ? lonDeg - 360.0 : lonDeg < -180.0 ? lonDeg + 360.0 : lonDeg;
    for (int level = int(deepestElevation_); level >= 0; --level) {
        const TileKey k = TileKey::containing(lon, latDeg, uint32_t(level));
        const Entry* e = find(0, k);
        if (!e) continue;
        if (e->state == DataState::Ready) {
            const GeoExtent x = k.extent();
            return e->elevation->sample((lon - x.west) / x.width(), (x.north - latDeg) / x.height());
        }
        if (e->state == DataState::Empty) return 0.0;   // no DEM covers it: the ellipsoid
    }
    return std::nullopt;
}

TileHeightRange TerrainTiles::heightRange(const TileKey& tile) const {
    if (elevation_.empty()) return {0.0, 0.0};
    for (int level = int(tile.level); level >= 0; --level) {
        const Entry* e = find(0, tile.ancestor(uint32_t(level)));
        if (!e) continue;
        if (e->state == DataState::Empty) return {0.0, 0.0};
        if (e->state == DataState::Ready) {
            const double lo = e->elevation->minHeight, hi = e->elevation->maxHeight;
            if (level == int(tile.level)) return {lo, hi};
            // An ancestor's samples are sparser than the tile's: allow for peaks between them.
            const double pad = 0.25 * (hi - lo) + 10.0;
            return {lo - pad, hi + pad};
        }
    }
    return {-500.0, 9000.0};   // nothing known yet: anything from the Dead Sea shore to Everest
}

TerrainTiles::LoadResult TerrainTiles::loadElevation(const TileKey& tile, std::shared_ptr<const ElevationData> parent,
                                                     uint32_t parentLevel, const jobs::CancelToken& cancel) const {
    LoadResult out;
    const int n = settings_.gridSize;
    const GeoExtent extent = tile.extent();
    // Read with a one-sample border (n + 2 samples over the extent grown by one sample spacing:
    // the same sample positions inside), for gradients that match the neighbours'.
    const int m = n + 2;
    const double dx = extent.width() / (n - 1), dy = extent.height() / (n - 1);
    const GeoExtent grown{extent.west - dx, extent.south - dy, extent.east + dx, extent.north + dy};
    std::vector<float> g(size_t(m) * size_t(m), std::numeric_limits<float>::quiet_NaN());
    bool covered = false;
    for (const auto& source : elevation_) {
        if (!source->covers(extent) || tile.level < source->minLevel()) continue;
        covered = true;
        if (cancel.cancelled()) throw jobs::Cancelled();
        auto r = source->readElevation(grown, m, &cancel);
        if (!r) {
            if (cancel.cancelled()) throw jobs::Cancelled();
            out.error = r.message();
            return out;
        }
        if (!r->anyValid) continue;
        for (size_t i = 0; i < g.size(); ++i)
            if (std::isnan(g[i]) && std::isfinite(r->heights[i])) g[i] = r->heights[i];
    }
    // No source reaches this tile: nor any of its descendants. A source that reaches it but
    // has no sample here (a small DEM between the coarse grid's samples, a nodata area) still
    // gives a tile, filled from coarser data, so that finer levels are loaded below it.
    if (!covered) {
        out.empty = true;
        return out;
    }
    const glm::dvec4 sb = parent ? tile.scaleBiasWithin(tile.ancestor(parentLevel)) : glm::dvec4(1, 1, 0, 0);
    out.elevation = fillElevation(std::move(g), n, parent.get(), sb);
    return out;
}

TerrainTiles::LoadResult TerrainTiles::loadImagery(const TileImageSource& source, const TileKey& tile,
                                                   const jobs::CancelToken& cancel) const {
    LoadResult out;
    const GeoExtent extent = tile.extent();
    if (!source.covers(extent)) {
        out.empty = true;
        return out;
    }
    auto r = source.readTile({extent, settings_.imageSize, settings_.tilePixelsPerScreenPixel}, &cancel);
    if (!r) {
        if (cancel.cancelled()) throw jobs::Cancelled();
        out.error = r.message();
        return out;
    }
    if (!r->anyValid) {
        out.empty = true;
        out.descend = true;   // the source reaches here: finer tiles may hit its pixels
        return out;
    }
    out.imagery = std::make_shared<ImageryData>(buildImageryMips(r->size, std::move(r->rgba)));
    return out;
}

void TerrainTiles::noteError(const std::string& message) {
    if (errors_.size() < 16) {
        errors_.push_back(message);
        log::error(message);
    }
}

}  // namespace orbis::globe
