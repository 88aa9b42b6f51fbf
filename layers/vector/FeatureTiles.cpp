#include "layers/vector/FeatureTiles.h"
#include "layers/vector/LonLatGeometry.h"

#include "base/Secrets.h"
#include "layers/vector/FeatureClip.h"
#include "layers/vector/Simplify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <variant>

namespace orbis::vector {
namespace {

/// Bytes counted for a page besides its features (the entry, an empty page's content).
constexpr uint64_t kPageOverhead = 512;

/// Adds `more`'s features to `data`, layer by layer, but for those `data` has already (the same
/// fid: a feature met by both boxes of a page across the antimeridian).
void merge(VectorData& data, VectorData&& more) {
    for (size_t l = 0; l < data.layers.size() && l < more.layers.size(); ++l) {
        VectorLayer& into = data.layers[l];
        std::unordered_set<int64_t> have;
        for (const Feature& f : into.features) have.insert(f.fid);
        for (Feature& f : more.layers[l].features)
            if (f.fid < 0 || !have.contains(f.fid)) into.features.push_back(std::move(f));
    }
}

/// FNV-1a over what a read gave: a page read again with the same value shows the same thing.
class Fingerprint {
public:
    void bytes(const void* data, size_t n) {
        const auto* p = static_cast<const uint8_t*>(data);
        for (size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
    }
    template <class T>
    void value(const T& v) { bytes(&v, sizeof v); }
    void text(const std::string& t) {
        value(t.size());
        bytes(t.data(), t.size());
    }
    uint64_t get() const { return h_; }

private:
    uint64_t h_ = 14695981039346656037ull;
};

uint64_t fingerprintOf(const VectorData& data) {
    Fingerprint f;
    for (const VectorLayer& layer : data.layers) {
        f.text(layer.name);
        f.value(layer.features.size());
        for (const Feature& feature : layer.features) {
            f.value(feature.fid);
            f.value(feature.kind);
            f.value(feature.style);
            f.value(feature.coords.size());
            f.bytes(feature.coords.data(), feature.coords.size() * sizeof(glm::dvec3));
            f.value(feature.parts.size());
            f.bytes(feature.parts.data(), feature.parts.size() * sizeof(uint32_t));
            f.value(feature.polygons.size());
            f.bytes(feature.polygons.data(), feature.polygons.size() * sizeof(uint32_t));
            for (const AttributeValue& a : feature.attributes) {
                f.value(a.index());
                if (const auto* i = std::get_if<int64_t>(&a)) f.value(*i);
                else if (const auto* d = std::get_if<double>(&a)) f.value(*d);
                else if (const auto* t = std::get_if<std::string>(&a)) f.text(*t);
            }
        }
    }
    return f.get();
}

/// Whether `box` (lon/lat, longitudes continuous) meets `e`, a turn either way included.
bool meets(const LonLatBounds& box, const globe::GeoExtent& e) {
    if (box.empty || box.north < e.south || box.south > e.north) return false;
    if (box.spansAllLongitudes()) return true;
    return e.meetsWithTurns({box.west, box.south, box.east, box.north});
}

}  // namespace

Result<FeatureTile> loadFeatureTile(const FeatureTilesOptions& options, const globe::TileKey& key) {
    const globe::GeoExtent e = key.extent();
    const double m = options.owned ? 0.0 : options.margin * key.sizeDeg();
    const globe::GeoExtent grown{e.west - m, std::max(e.south - m, -90.0), e.east + m, std::min(e.north + m, 90.0)};
    // OGR is asked for boxes within -180..180: a margin past the antimeridian is a second box.
    std::vector<LonLatBounds> boxes{{std::max(grown.west, -180.0), grown.south, std::min(grown.east, 180.0), grown.north, false}};
    if (grown.west < -180.0) boxes.push_back({grown.west + 360.0, grown.south, 180.0, grown.north, false});
    if (grown.east > 180.0) boxes.push_back({-180.0, grown.south, grown.east - 360.0, grown.north, false});
    // Each feature is clipped and simplified as it is read: a read holds only what the page keeps.
    // The finest pages serve every finer tile: every vertex stays.
    const double tolerance =
        key.level < options.pageLevel && !options.owned ? 0.5 * key.sizeDeg() / std::max(1.0, options.tilePixels) : 0.0;
    const auto shape = [&grown, &e, tolerance, owned = options.owned](Feature& f) {
        if (owned) {
            // The centre of its box, its longitude within [-180, 180): in this tile or not.
            double lon = 0.5 * (f.bounds.west + f.bounds.east);
            lon -= 360.0 * std::floor((lon + 180.0) / 360.0);
            const double lat = 0.5 * (f.bounds.south + f.bounds.north);
            return lon >= e.west && lon < e.east && lat >= e.south && (lat < e.north || e.north >= 90.0);
        }
        auto piece = clipFeature(f, grown);
        if (piece && tolerance > 0.0) piece = simplifyFeature(*piece, tolerance);
        if (!piece) return false;
        f = std::move(*piece);
        f.bounds = partBounds(f.coords);   // all within the grown tile: one box
        return true;
    };
    VectorData data;
    for (size_t b = 0; b < boxes.size(); ++b) {
        VectorReadOptions read = options.content.read;
        read.within = boxes[b];
        read.shape = shape;
        read.reuseDataset = true;   // a pager reads the source many times
        auto part = readVector(read);
        if (!part) return part.error();
        if (b == 0) data = std::move(*part);
        else merge(data, std::move(*part));
    }
    // In the source's order (a spatial filter reads in its index's order), so that pages paint
    // overlapping features in the order the whole source does.
    for (VectorLayer& layer : data.layers)
        std::stable_sort(layer.features.begin(), layer.features.end(), [](const Feature& a, const Feature& b) { return a.fid < b.fid; });
    const uint64_t fingerprint = fingerprintOf(data);
    auto content = contentFromData(std::move(data), options.content);
    if (!content) return content.error();
    FeatureTile tile;
    tile.key = key;
    tile.fingerprint = fingerprint;
    tile.bytes = (*content)->bytes + kPageOverhead;
    tile.content = std::move(*content);
    return tile;
}

FeatureTiles::FeatureTiles(FeatureTilesOptions options) : options_(std::move(options)) {
    // The finest tile whose page holds the whole source: coarser tiles share its page.
    const std::optional<LonLatBounds>& b = options_.sourceBounds;
    if (!b || b->empty || b->east > 180.0) return;
    for (uint32_t level = options_.pageLevel + 1; level-- > 0;) {
        const globe::TileKey k = globe::TileKey::containing(0.5 * (b->west + b->east), 0.5 * (b->south + b->north), level);
        const globe::GeoExtent e = k.extent();
        const double m = options_.margin * k.sizeDeg();
        if (b->west >= e.west - m && b->east <= e.east + m && b->south >= e.south - m && b->north <= e.north + m) {
            overview_ = k;
            break;
        }
    }
}

globe::TileKey FeatureTiles::pageFor(const globe::TileKey& key) const {
    if (overview_ && key.level <= overview_->level) return *overview_;
    return key.level <= options_.pageLevel ? key : key.ancestor(options_.pageLevel);
}

globe::GeoExtent FeatureTiles::grownExtent(const globe::TileKey& page) const {
    const globe::GeoExtent e = page.extent();
    const double m = options_.owned ? 0.0 : options_.margin * page.sizeDeg();
    return {e.west - m, std::max(e.south - m, -90.0), e.east + m, std::min(e.north + m, 90.0)};
}

Result<std::shared_ptr<const FeatureTile>> FeatureTiles::acquire(const globe::TileKey& key, const jobs::CancelToken* cancel) {
    const globe::TileKey page = pageFor(key);
    std::shared_future<Loaded> future;
    std::promise<Loaded> promise;
    bool reader = false;
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(page);
        uint32_t failures = 0;
        if (it != entries_.end() && it->second.done && it->second.bytes == 0 &&
            std::chrono::steady_clock::now() >= it->second.retryAt) {
            // It failed a while ago: read it again (the server may be back).
            failures = it->second.failures;
            uses_.erase(it->second.use);
            entries_.erase(it);
            it = entries_.end();
        }
        if (it != entries_.end() && it->second.done && it->second.shown && std::chrono::steady_clock::now() >= it->second.retryAt) {
            // Outdated (invalidate): this thread reads it again; loaded() shows the old content
            // meanwhile, and whoever asks waits for the new.
            Entry& e = it->second;
            e.future = future = promise.get_future().share();
            e.done = false;
            uses_.splice(uses_.begin(), uses_, e.use);
            reader = true;
            ++reads_;
        } else if (it != entries_.end()) {
            future = it->second.future;
            uses_.splice(uses_.begin(), uses_, it->second.use);
        } else {
            uses_.push_front(page);
            Entry entry;
            entry.future = future = promise.get_future().share();
            entry.use = uses_.begin();
            entry.failures = failures;
            entries_.emplace(page, std::move(entry));
            reader = true;
            ++reads_;
        }
    }
    if (!reader) {
        while (future.wait_for(std::chrono::milliseconds(10)) != std::future_status::ready)
            if (cancel && cancel->cancelled()) throw jobs::Cancelled();
        return future.get();
    }
    // This thread reads it; whoever asks meanwhile waits for this read.
    const auto readStart = std::chrono::steady_clock::now();
    Loaded loaded = makeError("not read");
    try {
        auto tile = loadFeatureTile(options_, page);
        if (tile) loaded = std::shared_ptr<const FeatureTile>(std::make_shared<FeatureTile>(std::move(*tile)));
        else loaded = tile.error();
    } catch (const std::exception& e) {
        loaded = makeError(redactSecrets(options_.content.read.source) + ": " + e.what());
    }
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(page);   // reads in progress are never evicted nor erased
        Entry& entry = it->second;
        entry.done = true;
        entry.readTime = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - readStart);
        const bool stale = std::exchange(entry.stale, false);
        if (stale && !loaded && !entry.shown) {
            // A first read that failed while the source changed: forgotten.
            uses_.erase(entry.use);
            entries_.erase(it);
        } else if (loaded) {
            bytes_ = bytes_ - entry.bytes + (*loaded)->bytes;
            entry.bytes = (*loaded)->bytes;
            entry.failures = 0;
            // The source changed while it was read: kept, but outdated (its waiters take it;
            // the next acquire reads it again).
            entry.shown = stale ? *loaded : nullptr;
            entry.retryAt = {};
            ++changes_;
            evictLocked(page);
        } else {
            ++entry.failures;
            entry.retryAt = std::chrono::steady_clock::now() + kRetryDelay * (1u << std::min(entry.failures - 1, 3u));
            noteErrorLocked("feature tile " + page.toString() + ": " + loaded.message());
            if (entry.shown) {
                // An outdated page that cannot be read again (the server went away): its old
                // features serve until a read succeeds.
                std::promise<Loaded> old;
                old.set_value(entry.shown);
                entry.future = old.get_future().share();
                loaded = entry.shown;
            }
        }
    }
    promise.set_value(loaded);
    return loaded;
}

void FeatureTiles::noteErrorLocked(std::string message) {
    lastError_ = message;
    if (errors_.size() >= kErrorsKept) errors_.erase(errors_.begin());
    errors_.push_back(std::move(message));
}

size_t FeatureTiles::failingCount() const {
    std::lock_guard lock(mutex_);
    return size_t(std::count_if(entries_.begin(), entries_.end(),
                                [](const auto& e) { return e.second.done && e.second.bytes == 0; }));
}

std::string FeatureTiles::lastError() const {
    std::lock_guard lock(mutex_);
    return lastError_;
}

std::vector<DeferredRead> FeatureTiles::invalidate(std::span<const LonLatBounds> boxes) {
    std::vector<DeferredRead> deferred;
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& e = it->second;
        const globe::GeoExtent g = grownExtent(it->first);
        if (!std::any_of(boxes.begin(), boxes.end(), [&](const LonLatBounds& b) { return meets(b, g); })) {
            ++it;
            continue;
        }
        if (!e.done) {
            e.stale = true;
        } else if (e.bytes == 0) {   // failed: forgotten
            uses_.erase(e.use);
            it = entries_.erase(it);
            continue;
        } else if (!e.shown) {
            e.shown = *e.future.get();
            // A page that takes long to read (a coarse one over much of a large source) is read
            // again at most a fifth of the time: the change shows there a little later.
            e.retryAt = {};
            if (e.readTime > options_.quickRead) {
                e.retryAt = now + 4 * e.readTime;
                deferred.push_back({g, e.retryAt});
            }
        }
        ++it;
    }
    return deferred;
}

PageRefresh FeatureTiles::refresh(std::span<const LonLatBounds> boxes, const jobs::CancelToken* cancel) {
    PageRefresh out;
    const auto touched = [&](const globe::TileKey& page) {
        if (boxes.empty()) return true;
        const globe::GeoExtent g = grownExtent(page);
        return std::any_of(boxes.begin(), boxes.end(), [&](const LonLatBounds& b) { return meets(b, g); });
    };
    // What to read again: the pages in memory that the change reaches. Pages being read are
    // marked (not kept when done); failed ones are forgotten.
    std::vector<std::pair<globe::TileKey, uint64_t>> again;   // page, its fingerprint now
    {
        std::lock_guard lock(mutex_);
        for (auto it = entries_.begin(); it != entries_.end();) {
            Entry& e = it->second;
            if (!touched(it->first)) {
                ++it;
                continue;
            }
            if (!e.done) {
                e.stale = true;
                out.changed.push_back(grownExtent(it->first));
            } else if (e.bytes == 0) {
                out.changed.push_back(grownExtent(it->first));
                uses_.erase(e.use);
                it = entries_.erase(it);
                continue;
            } else {
                again.emplace_back(it->first, (*e.future.get())->fingerprint);
                e.shown.reset();   // read again below, whatever invalidate said
            }
            ++it;
        }
        if (boxes.empty()) {
            if (evictedOverflow_) out.changed.push_back({-540.0, -90.0, 540.0, 90.0});
            else
                for (const globe::TileKey& k : evicted_) out.changed.push_back(grownExtent(k));
            evicted_.clear();
            evictedOverflow_ = false;
        }
    }
    for (const auto& [page, fingerprint] : again) {
        if (cancel && cancel->cancelled()) throw jobs::Cancelled();
        Result<FeatureTile> tile = makeError("not read");
        try {
            tile = loadFeatureTile(options_, page);
        } catch (const std::exception& e) {
            tile = makeError(redactSecrets(options_.content.read.source) + ": " + e.what());
        }
        ++out.pagesRead;
        std::lock_guard lock(mutex_);
        ++reads_;
        if (!tile) {
            // The old content stays on show; the error is reported.
            if (out.failed++ == 0) out.error = tile.message();
            noteErrorLocked("feature tile " + page.toString() + ": " + tile.message());
            continue;
        }
        if (tile->fingerprint == fingerprint) continue;
        out.changed.push_back(grownExtent(page));
        auto it = entries_.find(page);
        if (it == entries_.end() || !it->second.done || it->second.bytes == 0) continue;   // gone or read anew meanwhile
        std::promise<Loaded> replaced;
        const uint64_t bytes = tile->bytes;
        replaced.set_value(std::shared_ptr<const FeatureTile>(std::make_shared<FeatureTile>(std::move(*tile))));
        it->second.future = replaced.get_future().share();
        bytes_ = bytes_ - it->second.bytes + bytes;
        it->second.bytes = bytes;
        ++changes_;
        evictLocked(page);
    }
    return out;
}

void FeatureTiles::evictLocked(const globe::TileKey& keep) {
    for (auto it = uses_.end(); bytes_ > options_.budgetBytes && it != uses_.begin();) {
        --it;
        const auto entry = entries_.find(*it);
        if (*it == keep || !entry->second.done || entry->second.bytes == 0) continue;   // being read, or failed (kept)
        bytes_ -= entry->second.bytes;
        entries_.erase(entry);
        ++changes_;
        if (evicted_.size() < kEvictedKept) evicted_.push_back(*it);
        else evictedOverflow_ = true;
        it = uses_.erase(it);
    }
}

uint64_t FeatureTiles::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

size_t FeatureTiles::loadedCount() const {
    std::lock_guard lock(mutex_);
    return size_t(std::count_if(entries_.begin(), entries_.end(), [](const auto& e) { return e.second.bytes > 0; }));
}

uint64_t FeatureTiles::reads() const {
    std::lock_guard lock(mutex_);
    return reads_;
}

std::vector<std::string> FeatureTiles::errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
}

std::vector<std::shared_ptr<const FeatureTile>> FeatureTiles::loaded() const {
    std::lock_guard lock(mutex_);
    std::vector<std::shared_ptr<const FeatureTile>> out;
    for (const auto& [key, entry] : entries_)
        if (entry.bytes > 0) out.push_back(entry.done && !entry.shown ? *entry.future.get() : entry.shown);
    return out;
}

uint64_t FeatureTiles::changes() const {
    std::lock_guard lock(mutex_);
    return changes_;
}

std::shared_ptr<VectorContent> labelledFeatures(std::span<const std::shared_ptr<const FeatureTile>> pages, const VectorStyle& style) {
    auto out = std::make_shared<VectorContent>();
    // Each labelled feature's best piece: (page, layer, index) by (layer, fid).
    struct Piece {
        size_t page, feature;
        uint32_t level;
        size_t size;
    };
    std::vector<std::unordered_map<int64_t, Piece>> best;
    std::vector<std::vector<Piece>> unnamed;   // no fid: every piece
    for (size_t p = 0; p < pages.size(); ++p) {
        const VectorContent& content = *pages[p]->content;
        if (out->layers.size() < content.layers.size()) {
            out->source = content.source;
            out->layers.resize(content.layers.size());
            best.resize(content.layers.size());
            unnamed.resize(content.layers.size());
        }
        for (size_t l = 0; l < content.layers.size(); ++l) {
            const ContentLayer& layer = content.layers[l];
            ContentLayer& into = out->layers[l];
            if (into.data.name.empty()) {
                into.data.name = layer.data.name, into.data.fields = layer.data.fields;
                into.data.geometryType = layer.data.geometryType, into.data.crs = layer.data.crs, into.data.crsName = layer.data.crsName;
                into.style = style;
                if (!into.style.bind(layer.data.fields, layer.data.name)) into.style = layer.style;   // as the page was read
            }
            for (size_t i = 0; i < layer.data.features.size(); ++i) {
                const Feature& f = layer.data.features[i];
                const SourceStyle* own = f.style >= 0 && size_t(f.style) < layer.data.styles.size() ? &layer.data.styles[size_t(f.style)] : nullptr;
                const FeatureStyle s = into.style.evaluate(f.attributes, own);
                if (!s.visible || s.label.empty()) continue;
                const Piece piece{p, i, pages[p]->key.level, f.coords.size()};
                if (f.fid < 0) {
                    unnamed[l].push_back(piece);
                    continue;
                }
                auto [it, added] = best[l].try_emplace(f.fid, piece);
                if (!added && (piece.level > it->second.level || (piece.level == it->second.level && piece.size > it->second.size)))
                    it->second = piece;
            }
        }
    }
    for (size_t l = 0; l < out->layers.size(); ++l) {
        std::vector<Piece> chosen = std::move(unnamed[l]);
        for (const auto& [fid, piece] : best[l]) chosen.push_back(piece);
        ContentLayer& into = out->layers[l];
        std::vector<LonLatBounds> boxes;
        std::map<std::pair<size_t, int32_t>, int32_t> ownStyles;   // (page, its style) -> ours
        for (const Piece& piece : chosen) {
            const ContentLayer& from = pages[piece.page]->content->layers[l];
            Feature f = from.data.features[piece.feature];
            if (f.style >= 0 && size_t(f.style) < from.data.styles.size()) {
                auto [it, added] = ownStyles.try_emplace({piece.page, f.style}, int32_t(into.data.styles.size()));
                if (added) into.data.styles.push_back(from.data.styles[size_t(f.style)]);
                f.style = it->second;
            }
            if (from.times.timed()) into.times.spans.push_back(from.times.spans[piece.feature]);
            boxes.push_back(f.bounds);
            into.data.vertexCount += f.coords.size();
            out->bytes += featureBytes(f);
            into.data.features.push_back(std::move(f));
        }
        into.data.bounds = coverBounds(boxes);
        out->featureCount += into.data.features.size();
        out->vertexCount += into.data.vertexCount;
    }
    return out;
}

}  // namespace orbis::vector
