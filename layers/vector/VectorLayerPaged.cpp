// The vector layer's paged sources (see VectorLayer.h, "Paging"): whether to page, the meshes
// of the tiles near the view, the labels of the pages in memory.
#include "layers/vector/VectorLayer.h"

#include "base/Log.h"
#include "globe/Culling.h"
#include "globe/Ellipsoid.h"
#include "layers/vector/LonLatGeometry.h"
#include "layers/vector/MeshRenderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace orbis::layers {

Result<VectorLayer::Loaded> VectorLayer::openPaged(const VectorLayerSettings& settings) {
    Loaded out;
    const vector::VectorStyle& style = settings.content.style;
    if (settings.paging == Paging::Off) return out;
    auto summary = vector::summarizeVector(settings.content.read);
    if (!summary) return summary.error();
    uint64_t count = 0;
    bool counted = true;
    std::vector<vector::LonLatBounds> boxes;
    for (const vector::LayerSummary& layer : *summary) {
        // The style is checked against the fields now: a bad rule is the layer's error, once.
        vector::VectorStyle bound = style;
        if (auto ok = bound.bind(layer.fields, layer.name); !ok) return makeError(settings.content.read.source + ": " + ok.message());
        if (layer.featureCount < 0) counted = false;
        else count += uint64_t(layer.featureCount);
        if (layer.bounds) boxes.push_back(*layer.bounds);
    }
    if (settings.paging == Paging::Auto && (!counted || count <= settings.pageAbove)) return out;
    vector::FeatureTilesOptions options;
    options.content = settings.content;
    options.pageLevel = settings.pageLevel;
    options.budgetBytes = settings.pageBudgetBytes;
    // Pages reach as far past their tile as the widest stroke or icon paints (tiles drawn at up
    // to about 2 tile pixels per screen pixel).
    options.margin = std::clamp(2.0 * style.reachPx() / options.tilePixels, options.margin, 1.0);
    if (boxes.size() == summary->size() && !boxes.empty()) out.bounds = vector::coverBounds(boxes);
    options.sourceBounds = out.bounds;
    out.pages = std::make_shared<vector::FeatureTiles>(std::move(options));
    out.features = count;
    return out;
}

std::vector<globe::TileKey> VectorLayer::wantedMeshTiles(const scene::FrameContext& frame) const {
    const scene::Camera& camera = *frame.camera;
    const glm::dvec3 eye = camera.position();
    const globe::Ellipsoid& ell = globe::Ellipsoid::wgs84();
    const globe::Geodetic at = ell.toGeodetic(eye);
    // The tiles around the camera's ground point, out to the styles' farthest range (and no
    // farther than the horizon of a high camera is worth), within the source's box.
    const double maxRange = settings_.content.style.maxRangeM();
    double reach = std::min(maxRange, std::max(20000.0, 20.0 * std::max(at.height, 0.0)));
    const double size = globe::TileKey{kMeshLevel, 0, 0}.sizeDeg();
    const double cosLat = std::max(0.05, std::cos(glm::radians(at.latDeg)));
    int64_t x0, x1, y0, y1;
    for (;;) {
        double south = at.latDeg - reach / 111320.0, north = at.latDeg + reach / 111320.0;
        double west = at.lonDeg - reach / (111320.0 * cosLat), east = at.lonDeg + reach / (111320.0 * cosLat);
        if (pagedBounds_ && !pagedBounds_->spansAllLongitudes()) {
            south = std::max(south, pagedBounds_->south), north = std::min(north, pagedBounds_->north);
            // The source's box, moved by a turn to the camera's side.
            double bw = pagedBounds_->west, be = pagedBounds_->east;
            while (bw > at.lonDeg + 180.0) bw -= 360.0, be -= 360.0;
            while (be < at.lonDeg - 180.0) bw += 360.0, be += 360.0;
            west = std::max(west, bw), east = std::min(east, be);
        }
        if (!(west <= east && south <= north)) return {};
        x0 = int64_t(std::floor((west + 180.0) / size)), x1 = int64_t(std::floor((east + 180.0) / size));
        y0 = int64_t(std::floor((90.0 - north) / size)), y1 = int64_t(std::floor((90.0 - south) / size));
        if ((x1 - x0 + 1) * (y1 - y0 + 1) <= 4096) break;
        reach *= 0.5;
    }
    const auto frustum = globe::ViewFrustum::perspective(camera.verticalFovRad(), frame.aspect(), camera.nearPlane());
    const glm::dmat3 view(camera.viewRotation());
    const auto nx = int64_t(globe::TileKey::tilesX(kMeshLevel)), ny = int64_t(globe::TileKey::tilesY(kMeshLevel));
    std::vector<std::pair<double, globe::TileKey>> near;
    for (int64_t y = std::max<int64_t>(y0, 0); y <= std::min(y1, ny - 1); ++y)
        for (int64_t x = x0; x <= x1; ++x) {
            const globe::TileKey key{kMeshLevel, uint32_t(((x % nx) + nx) % nx), uint32_t(y)};
            const globe::GeoExtent e = key.extent();
            const glm::dvec3 center = ell.toEcef(0.5 * (e.west + e.east), 0.5 * (e.south + e.north), 0.0);
            // Half the tile's diagonal, and room for tall buildings and the ground under them.
            const double radius = 0.5 * glm::length(ell.toEcef(e.west, e.south, 0.0) - ell.toEcef(e.east, e.north, 0.0)) + 1000.0;
            const double distance = std::max(0.0, glm::length(center - eye) - radius);
            if (distance > maxRange || globe::sphereBelowHorizon(eye, center, radius)) continue;
            if (!frustum.intersectsSphere(view * (center - eye), radius)) continue;
            near.push_back({distance, key});
        }
    std::sort(near.begin(), near.end());
    std::vector<globe::TileKey> out;
    out.reserve(near.size());
    for (const auto& [d, key] : near) out.push_back(key);
    return out;
}

void VectorLayer::updatePagedMeshes(const scene::FrameContext& frame) {
    if (!pagedMeshes_ || !frame.camera) return;
    ++meshFrame_;
    if (frame.groundVersion != groundVersion_) {   // the terrain's exaggeration: every mesh again
        groundVersion_ = frame.groundVersion;
        ++tileMeshGeneration_;
    }
    // Nearest first, while the meshes built so far fit the budget.
    uint64_t bytes = 0;
    std::vector<globe::TileKey> wanted;
    for (const globe::TileKey& key : wantedMeshTiles(frame)) {
        if (bytes > settings_.pageBudgetBytes) break;
        wanted.push_back(key);
        if (auto it = tileMeshes_.find(key); it != tileMeshes_.end()) {
            it->second.lastWanted = meshFrame_;
            bytes += it->second.mesh->bytes();
        }
    }
    // Two builds at a time, the nearest missing (or built for older settings) first.
    tileMeshesPending_ = 0;
    for (const globe::TileKey& key : wanted) {
        const auto it = tileMeshes_.find(key);
        if (it != tileMeshes_.end() && it->second.generation == tileMeshGeneration_) continue;
        if (const auto failed = failedTiles_.find(key); failed != failedTiles_.end() && failed->second == tileMeshGeneration_) continue;
        ++tileMeshesPending_;
        if (tileJobs_.size() >= 2 || std::find(tileJobKeys_.begin(), tileJobKeys_.end(), key) != tileJobKeys_.end()) continue;
        vector::FeatureTilesOptions options;
        options.content = settings_.content;   // the style with its rules switched as now
        options.pageLevel = kMeshLevel;
        options.owned = true;
        const vector::MeshOptions meshOptions{
            .mode = settings_.altitude, .extrusionScale = settings_.extrusionScale, .time = time_, .idsByFid = true, .icons = icons_.get()};
        scene::GroundHeightFn ground = frame.groundSnapshot ? frame.groundSnapshot() : scene::GroundHeightFn{};
        tileJobKeys_.push_back(key);
        tileJobs_.push_back(services_.jobs().submit(
            1.0, jobs::CancelToken{},
            [options = std::move(options), meshOptions, ground = std::move(ground), key,
             generation = tileMeshGeneration_, refreshes = refreshesApplied_](const jobs::CancelToken& cancel) -> TileMeshBuild {
                auto tile = vector::loadFeatureTile(options, key);
                if (!tile) throw std::runtime_error(tile.message());
                const vector::VectorContent& content = *tile->content;
                const vector::ContentStyles styles = vector::styleContent(content);
                vector::MeshGround sampled(content, styles, meshOptions.mode);
                sampled.sample(ground, sampled.samples());
                bool drapes = false;
                for (size_t l = 0; l < content.layers.size() && !drapes; ++l)
                    for (size_t i = 0; i < content.layers[l].data.features.size() && !drapes; ++i)
                        drapes = styles[l][i].visible && !vector::drawnIn3d(content.layers[l].data.features[i], styles[l][i], meshOptions.mode);
                auto mesh = std::make_shared<vector::FeatureMesh>(vector::buildFeatureMesh(content, styles, sampled, meshOptions, &cancel));
                return {key, generation, std::move(mesh), std::make_shared<const vector::FeatureTile>(std::move(*tile)), drapes, refreshes};
            }));
    }
    // Past the budget, the meshes wanted least recently go.
    uint64_t total = 0;
    for (const auto& [key, t] : tileMeshes_) total += t.mesh->bytes();
    while (total > settings_.pageBudgetBytes) {
        auto oldest = tileMeshes_.end();
        for (auto it = tileMeshes_.begin(); it != tileMeshes_.end(); ++it)
            if (it->second.lastWanted < meshFrame_ && (oldest == tileMeshes_.end() || it->second.lastWanted < oldest->second.lastWanted))
                oldest = it;
        if (oldest == tileMeshes_.end()) break;
        total -= oldest->second.mesh->bytes();
        tileMeshes_.erase(oldest);
        tileMeshesChanged_ = true;
    }
    // Drawn together: the wanted tiles' meshes, gathered again when builds came in or the view
    // wants another set of those built (while more are on their way, at most every eighth
    // frame when they are large: each gathering uploads them all again; a live layer's few
    // points go at once).
    std::vector<globe::TileKey> drawable;
    for (const globe::TileKey& key : wanted)
        if (tileMeshes_.contains(key)) drawable.push_back(key);
    if (drawable != composedTiles_) tileMeshesChanged_ = true;
    if (!tileMeshesChanged_ || (!tileJobs_.empty() && meshFrame_ % 8 != 0 && bytes > kComposeAtOnceBytes)) return;
    tileMeshesChanged_ = false;
    composedTiles_ = drawable;
    auto combined = std::make_shared<vector::FeatureMesh>();
    const double now = glideClock();
    for (const globe::TileKey& key : drawable) {
        const auto it = tileMeshes_.find(key);
        // A tile drawn for the first time: its moving points glide from where they are shown.
        if (!it->second.arrived && motion_) motion_->arrive(*it->second.mesh, now);
        it->second.arrived = true;
        const vector::FeatureMesh& m = *it->second.mesh;
        combined->chunks.insert(combined->chunks.end(), m.chunks.begin(), m.chunks.end());
        combined->features += m.features, combined->triangles += m.triangles;
        combined->segments += m.segments, combined->markers += m.markers, combined->forced += m.forced;
    }
    if (motion_) motion_->drawing(*combined, now);
    ++meshesComposed_;
    mesh_ = std::move(combined);
    if (!meshRenderer_ && !mesh_->chunks.empty()) meshRenderer_ = std::make_unique<MeshRenderer>(services_, icons_);
    if (meshRenderer_) meshRenderer_->setMesh(mesh_);
}

double VectorLayer::glideClock() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void VectorLayer::pollPagedMeshes() {
    for (size_t i = 0; i < tileJobs_.size();) {
        if (!tileJobs_[i].ready()) {
            ++i;
            continue;
        }
        try {
            TileMeshBuild build = tileJobs_[i].get();
            if (build.generation == tileMeshGeneration_ || !tileMeshes_.contains(build.key)) {
                for (const std::string& w : build.mesh->warnings) log::warn("vector layer \"", settings_.name, "\": ", w);
                // Started before a change reached it: shown, and built again.
                const auto changed = meshTileChanged_.find(build.key);
                const bool stale = changed != meshTileChanged_.end() && build.refreshes < changed->second;
                tileMeshes_[build.key] = {std::move(build.mesh), stale ? 0 : build.generation, meshFrame_, false, std::move(build.page)};
                if (!stale && changed != meshTileChanged_.end()) meshTileChanged_.erase(changed);
                tileMeshesChanged_ = true;
                if (build.drapes && !pagedDrapes_) {
                    pagedDrapes_ = true;
                    republish();
                }
            }
        } catch (const jobs::Cancelled&) {
        } catch (const std::exception& e) {
            // Reported once, and not tried again for these settings (the rest still load).
            if (error_.empty()) log::error("vector layer \"", settings_.name, "\": tile ", tileJobKeys_[i].toString(), ": ", e.what());
            error_ = settings_.content.read.source + ": tile " + tileJobKeys_[i].toString() + ": " + e.what();
            failedTiles_[tileJobKeys_[i]] = tileMeshGeneration_;
        }
        tileJobs_.erase(tileJobs_.begin() + ptrdiff_t(i));
        tileJobKeys_.erase(tileJobKeys_.begin() + ptrdiff_t(i));
    }
}

void VectorLayer::updatePagedLabels() {
    if (!labels_ || !settings_.labels || pagedLabelLoading_) return;
    const uint64_t changes = pages_->changes();
    if (changes == pagedLabelChanges_ && meshesComposed_ == pagedLabelComposed_ && !pagedLabelsStale_) return;
    pagedLabelChanges_ = changes;
    pagedLabelComposed_ = meshesComposed_;
    pagedLabelsStale_ = false;
    pagedLabelLoading_ = true;
    // The pages in memory hold the draped features; with meshes, the features in 3-D come from
    // the pages the meshes drawn were built from (the drape's pages are read again when a
    // change repaints it; without a drape nothing reads them again, and a moved or deleted
    // feature's old label would stay).
    std::vector<std::shared_ptr<const vector::FeatureTile>> pages;
    if (!pagedMeshes_ || pagedDrapes_) pages = pages_->loaded();
    if (pagedMeshes_)
        for (const globe::TileKey& key : composedTiles_)
            if (const auto it = tileMeshes_.find(key); it != tileMeshes_.end() && it->second.page) pages.push_back(it->second.page);
    pagedLabelJob_ = services_.jobs().submit(0.0, jobs::CancelToken{},
                                             [pages = std::move(pages), style = settings_.content.style](const jobs::CancelToken&) {
                                                 Loaded out;
                                                 out.content = vector::labelledFeatures(pages, style);
                                                 out.anchors = std::make_shared<const vector::ContentAnchors>(vector::labelAnchors(*out.content));
                                                 return out;
                                             });
}

void VectorLayer::pollPagedLabels() {
    if (!pagedLabelLoading_ || !pagedLabelJob_.ready()) return;
    pagedLabelLoading_ = false;
    try {
        Loaded got = pagedLabelJob_.get();
        auto styles = std::make_shared<const vector::ContentStyles>(vector::styleContent(*got.content));
        labels_->setContent(std::move(got.content), std::move(styles), std::move(got.anchors), true);
    } catch (const std::exception& e) {
        labelError_ = e.what();
        log::error("vector layer \"", settings_.name, "\": labels: ", labelError_);
    }
    pagedLabelJob_ = {};
}

}  // namespace orbis::layers
