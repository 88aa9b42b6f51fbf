#include "layers/vector/VectorDrape.h"

#include "base/ThreadPool.h"
#include "layers/vector/DrapeRaster.h"

#include <algorithm>
#include <cmath>

namespace orbis::vector {
namespace {

/// True when the lon/lat box meets the extent, the box moved by any whole turn.
bool meets(const LonLatBounds& b, const globe::GeoExtent& e) {
    if (b.empty || b.north < e.south || b.south > e.north) return false;
    if (b.spansAllLongitudes()) return true;
    for (double shift : {-360.0, 0.0, 360.0})
        if (b.west + shift <= e.east && b.east + shift >= e.west) return true;
    return false;
}

/// Paint order: fills under lines under points, then source order.
int kindOrder(GeometryKind k) { return k == GeometryKind::Polygons ? 0 : k == GeometryKind::Lines ? 1 : 2; }

}  // namespace

VectorDrape::VectorDrape(std::string name, std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles,
                         TimeNs time, uint32_t maxLevel, std::optional<std::pair<size_t, size_t>> highlight, double simplifyPx,
                         std::shared_ptr<IconCache> icons)
    : name_(std::move(name)), content_(std::move(content)), styles_(std::move(styles)), time_(time), maxLevel_(maxLevel),
      simplifyPx_(simplifyPx), icons_(std::move(icons)), highlight_(highlight) {
    // The widest reach past a feature: half a stroke, half a marker, half an icon up to 4:1 wide
    // (and the highlight's extra), plus a little.
    for (const std::vector<FeatureStyle>& layer : *styles_)
        for (const FeatureStyle& s : layer)
            reachPx_ = std::max(reachPx_, 0.5 * std::max(s.widthPx, s.iconSizePx * (s.icon.empty() ? 1.0 : 4.0)) + 8.0);
    if (highlight_ && highlight_->first < styles_->size() && highlight_->second < (*styles_)[highlight_->first].size()) {
        // The feature's own look, made to stand out: bright yellow, wider, filled.
        highlightStyle_ = (*styles_)[highlight_->first][highlight_->second];
        highlightStyle_.visible = true;
        highlightStyle_.color = {1.0, 0.95, 0.1};
        highlightStyle_.opacity = 1.0;
        highlightStyle_.widthPx += 3.0;
        highlightStyle_.fill = {1.0, 0.95, 0.1};
        highlightStyle_.fillOpacity = std::max(highlightStyle_.fillOpacity, 0.35);
        highlightStyle_.outline = true;
        highlightStyle_.iconSizePx += 6.0;
    } else {
        highlight_.reset();
    }
}

bool VectorDrape::covers(const globe::GeoExtent& extent) const {
    // Strokes and markers reach a little past the features' boxes: a margin of a tenth of the
    // extent (at least a few pixels of any tile that asks).
    const double margin = 0.1 * extent.width();
    const globe::GeoExtent grown{extent.west - margin, extent.south - margin, extent.east + margin, extent.north + margin};
    for (const ContentLayer& layer : content_->layers)
        if (meets(layer.data.bounds, grown)) return true;
    return false;
}

double VectorDrape::rangeForTile(const globe::GeoExtent& extent, int size, double tilePixelsPerScreenPixel) {
    // A tile pixel spans 1 / tilePixelsPerScreenPixel screen pixels, and a screen pixel about a
    // thousandth of a radian (1080 rows over a 60-degree field of view): the distance at which
    // that holds.
    constexpr double kPixelsPerRadian = 1000.0;
    const double pixelMetres = extent.height() / size * 111320.0;
    return pixelMetres * tilePixelsPerScreenPixel * kPixelsPerRadian;
}

Result<globe::ImageryTile> VectorDrape::readTile(const globe::TileImageRequest& request, const jobs::CancelToken* cancel) const {
    const globe::GeoExtent& e = request.extent;
    const double px = e.width() / request.size;
    // Whatever is painted within reach of the tile: the widest stroke, marker or icon.
    const double margin = reachPx_ * request.tilePixelsPerScreenPixel * px;
    const globe::GeoExtent grown{e.west - margin, e.south - margin, e.east + margin, e.north + margin};
    const double range = rangeForTile(e, request.size, request.tilePixelsPerScreenPixel);

    std::vector<std::pair<int, DrapeItem>> items;
    for (size_t l = 0; l < content_->layers.size(); ++l) {
        const ContentLayer& layer = content_->layers[l];
        if (!meets(layer.data.bounds, grown)) continue;
        const std::vector<FeatureStyle>& styles = (*styles_)[l];
        for (size_t i = 0; i < layer.data.features.size(); ++i) {
            const Feature& f = layer.data.features[i];
            const FeatureStyle& s = styles[i];
            if (!s.visible || range < s.minRangeM || range > s.maxRangeM) continue;
            if (layer.times.timed() && !layer.times.spans[i].shows(time_)) continue;
            if (!meets(f.bounds, grown)) continue;
            const bool highlighted = highlight_ && highlight_->first == l && highlight_->second == i;
            const ImageRgba8* icon = nullptr;
            if (f.kind == GeometryKind::Points && !s.icon.empty() && icons_) icon = icons_->get(s.icon).get();
            items.push_back({highlighted ? 3 : kindOrder(f.kind), DrapeItem{&f, highlighted ? &highlightStyle_ : &s, icon}});
        }
    }
    if (cancel && cancel->cancelled()) throw jobs::Cancelled();
    std::stable_sort(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<DrapeItem> ordered;
    ordered.reserve(items.size());
    for (const auto& [order, item] : items) ordered.push_back(item);

    globe::ImageryTile tile;
    tile.size = request.size;
    if (ordered.empty()) return tile;
    DrapeTileOptions options;
    options.extent = e;
    options.size = request.size;
    options.pixelScale = request.tilePixelsPerScreenPixel;
    options.simplifyPx = simplifyPx_;
    options.rangeM = range;
    tile.anyValid = rasterizeDrapeTile(ordered, options, tile.rgba);
    return tile;
}

}  // namespace orbis::vector
