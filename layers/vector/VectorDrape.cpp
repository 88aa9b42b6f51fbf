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

FeatureStyle highlighted(FeatureStyle s) {
    s.visible = true;
    s.color = {1.0, 0.95, 0.1};
    s.opacity = 1.0;
    s.widthPx += 3.0;
    s.fill = {1.0, 0.95, 0.1};
    s.fillOpacity = std::max(s.fillOpacity, 0.35);
    s.outline = true;
    s.iconSizePx += 6.0;
    return s;
}

VectorDrape::VectorDrape(DrapeState state, std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles)
    : state_(std::move(state)), content_(std::move(content)), styles_(std::move(styles)) {
    for (const std::vector<FeatureStyle>& layer : *styles_)
        for (const FeatureStyle& s : layer) reachPx_ = std::max(reachPx_, featureReachPx(s));
    const auto& h = state_.highlight;
    if (h && h->layer < styles_->size() && h->feature < (*styles_)[h->layer].size())
        highlightStyle_ = highlighted((*styles_)[h->layer][h->feature]);
    else
        state_.highlight.reset();
}

VectorDrape::VectorDrape(DrapeState state, std::shared_ptr<FeatureTiles> pages, const VectorStyle& style,
                         std::optional<LonLatBounds> bounds)
    : state_(std::move(state)), pages_(std::move(pages)), bounds_(bounds), maxRangeM_(style.maxRangeM()) {
    reachPx_ = std::max(reachPx_, style.reachPx());
    for (size_t i = 0; i < style.ruleCount(); ++i) rulesOn_.push_back(style.ruleEnabled(i));
}

bool VectorDrape::covers(const globe::GeoExtent& extent) const {
    // Strokes and markers reach a little past the features' boxes: a margin of a tenth of the
    // extent (at least a few pixels of any tile that asks).
    const double margin = 0.1 * extent.width();
    const globe::GeoExtent grown{extent.west - margin, extent.south - margin, extent.east + margin, extent.north + margin};
    if (pages_) return !bounds_ || meets(*bounds_, grown);
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
    std::deque<FeatureStyle> evaluated;
    std::shared_ptr<const FeatureTile> page;   // held while painting
    if (!pages_) {
        collect(*content_, styles_.get(), grown, range, evaluated, items);
    } else if (range <= maxRangeM_) {
        // The tile's key from its extent (the quadtree's tiles are 180 / 2^level degrees).
        const auto level = uint32_t(std::clamp(std::lround(std::log2(180.0 / e.height())), 0l, long(globe::TileKey::kMaxLevel)));
        auto got = pages_->acquire(globe::TileKey::containing(0.5 * (e.west + e.east), 0.5 * (e.south + e.north), level), cancel);
        if (!got) return got.error();
        page = std::move(*got);
        collect(*page->content, nullptr, grown, range, evaluated, items);
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
    options.simplifyPx = state_.simplifyPx;
    options.rangeM = range;
    tile.anyValid = rasterizeDrapeTile(ordered, options, tile.rgba);
    return tile;
}

void VectorDrape::collect(const VectorContent& content, const ContentStyles* styles, const globe::GeoExtent& grown, double range,
                          std::deque<FeatureStyle>& evaluated, std::vector<std::pair<int, DrapeItem>>& items) const {
    const std::optional<DrapeFeature>& h = state_.highlight;
    for (size_t l = 0; l < content.layers.size(); ++l) {
        const ContentLayer& layer = content.layers[l];
        if (!meets(layer.data.bounds, grown)) continue;
        // A page's style, its rules switched as the layer has them now.
        std::optional<VectorStyle> style;
        if (!styles) {
            style = layer.style;
            for (size_t i = 0; i < rulesOn_.size() && i < style->ruleCount(); ++i) style->setRuleEnabled(i, rulesOn_[i]);
        }
        for (size_t i = 0; i < layer.data.features.size(); ++i) {
            const Feature& f = layer.data.features[i];
            if (!meets(f.bounds, grown)) continue;
            if (layer.times.timed() && !layer.times.spans[i].shows(state_.time)) continue;
            const bool lit = h && h->layer == l && (styles ? h->feature == i : h->fid == f.fid && f.fid >= 0);
            const FeatureStyle* s = nullptr;
            if (styles) {
                s = lit ? &highlightStyle_ : &(*styles)[l][i];
            } else {
                const SourceStyle* own = f.style >= 0 && size_t(f.style) < layer.data.styles.size() ? &layer.data.styles[size_t(f.style)] : nullptr;
                FeatureStyle featureStyle = style->evaluate(f.attributes, own);
                if (!featureStyle.visible && !lit) continue;
                if (state_.meshes && drawnIn3d(f, featureStyle, *state_.meshes)) continue;
                s = &evaluated.emplace_back(lit ? highlighted(std::move(featureStyle)) : std::move(featureStyle));
            }
            if (!s->visible || range < s->minRangeM || range > s->maxRangeM) continue;
            const ImageRgba8* icon = nullptr;
            if (f.kind == GeometryKind::Points && !s->icon.empty() && state_.icons) icon = state_.icons->get(s->icon).get();
            items.push_back({lit ? 3 : kindOrder(f.kind), DrapeItem{&f, s, icon}});
        }
    }
}

}  // namespace orbis::vector
