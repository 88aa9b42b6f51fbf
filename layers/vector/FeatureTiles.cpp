#include "layers/vector/FeatureTiles.h"

#include "layers/vector/FeatureClip.h"
#include "layers/vector/Simplify.h"

#include <algorithm>

namespace orbis::vector {
namespace {

uint64_t featureBytes(const Feature& f) {
    uint64_t bytes = sizeof(Feature) + f.coords.size() * sizeof(glm::dvec3) + (f.parts.size() + f.polygons.size()) * sizeof(uint32_t) +
                     f.containsPole.size() + f.attributes.size() * sizeof(AttributeValue);
    for (const AttributeValue& a : f.attributes)
        if (const auto* s = std::get_if<std::string>(&a)) bytes += s->capacity();
    return bytes;
}

}  // namespace

Result<FeatureTile> loadFeatureTile(const FeatureTilesOptions& options, const globe::TileKey& key) {
    const globe::GeoExtent e = key.extent();
    VectorReadOptions read = options.read;
    read.within = LonLatBounds{.west = e.west, .south = e.south, .east = e.east, .north = e.north, .empty = false};
    auto data = readVector(read);
    if (!data) return data.error();
    FeatureTile tile;
    tile.key = key;
    const double tolerance = key.sizeDeg() / std::max(1.0, options.tilePixels);
    for (VectorLayer& layer : data->layers) {
        for (std::string& w : layer.warnings) tile.warnings.push_back(std::move(w));
        for (const Feature& f : layer.features) {
            auto piece = clipFeature(f, e);
            if (!piece) continue;
            auto simple = simplifyFeature(*piece, tolerance);
            if (!simple) continue;
            tile.bytes += featureBytes(*simple);
            tile.features.push_back(std::move(*simple));
        }
    }
    return tile;
}

FeatureTiles::FeatureTiles(FeatureTilesOptions options, jobs::ThreadPool& pool) : options_(std::move(options)), pool_(pool) {}

FeatureTiles::~FeatureTiles() {
    for (auto& [key, entry] : entries_)
        if (entry.job.valid() && !entry.job.ready()) entry.cancel.cancel();
    for (auto& [key, entry] : entries_)
        if (entry.job.valid()) entry.job.wait();   // the jobs read options_: they end before it goes
}

const FeatureTile* FeatureTiles::request(const globe::TileKey& key, double priority, uint64_t frame) {
    Entry& entry = entries_[key];
    entry.lastFrame = frame;
    if (entry.tile) return entry.tile.get();
    if (entry.failed) return nullptr;
    if (!entry.job.valid()) {
        entry.cancel = jobs::CancelToken::create();
        const FeatureTilesOptions* options = &options_;
        entry.job = pool_.submit(priority, entry.cancel, [options, key](const jobs::CancelToken& cancel) {
            cancel.throwIfCancelled();
            return loadFeatureTile(*options, key);
        });
    } else {
        entry.job.setPriority(priority);
    }
    return nullptr;
}

void FeatureTiles::poll(uint64_t frame) {
    for (auto it = entries_.begin(); it != entries_.end();) {
        Entry& entry = it->second;
        if (entry.job.valid() && entry.job.ready()) {
            if (entry.job.cancelled()) {
                it = entries_.erase(it);   // asked for again later: loaded again
                continue;
            }
            try {
                Result<FeatureTile> loaded = entry.job.get();
                if (loaded) {
                    entry.tile = std::make_shared<FeatureTile>(std::move(*loaded));
                    bytes_ += entry.tile->bytes;
                } else {
                    entry.failed = true;
                    errors_.push_back("tile " + it->first.toString() + ": " + loaded.message());
                }
            } catch (const std::exception& e) {
                entry.failed = true;
                errors_.push_back("tile " + it->first.toString() + ": " + e.what());
            }
            entry.job = {};
        } else if (entry.job.valid() && entry.lastFrame + 1 < frame) {
            entry.cancel.cancel();   // no frame wants it any more
        }
        ++it;
    }
    if (bytes_ <= options_.budgetBytes) return;
    // Least recently requested first; never a tile of this frame.
    std::vector<std::pair<uint64_t, globe::TileKey>> loaded;
    for (const auto& [key, entry] : entries_)
        if (entry.tile && entry.lastFrame < frame) loaded.push_back({entry.lastFrame, key});
    std::sort(loaded.begin(), loaded.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [last, key] : loaded) {
        if (bytes_ <= options_.budgetBytes) break;
        bytes_ -= entries_[key].tile->bytes;
        entries_.erase(key);
    }
}

size_t FeatureTiles::loadedCount() const {
    return size_t(std::count_if(entries_.begin(), entries_.end(), [](const auto& e) { return e.second.tile != nullptr; }));
}

size_t FeatureTiles::pendingCount() const {
    return size_t(std::count_if(entries_.begin(), entries_.end(), [](const auto& e) { return e.second.job.valid(); }));
}

}  // namespace orbis::vector
