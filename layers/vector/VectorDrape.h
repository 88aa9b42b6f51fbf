#pragma once
// A vector layer's content clamped to the terrain: each terrain tile's image is painted from the
// features that meet the tile (DrapeRaster), on the terrain's worker threads, and the terrain
// blends it over its imagery. So lines and polygons lie exactly on the surface drawn at every
// zoom: they cannot float above it, cut into hills or z-fight with it. One source paints one
// state of the content (features, styles, the time); a new state is a new source.
//
// Visibility by camera range (a style's minRange/maxRange) is taken per tile: a tile of level
// L is drawn from about rangeForLevel(L) (the terrain refines tiles by screen-space error), so
// a feature shows in the tiles whose range is within its own.

#include "globe/TileImageSource.h"
#include "layers/vector/IconCache.h"
#include "layers/vector/VectorContent.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace orbis::vector {

class VectorDrape : public globe::TileImageSource {
public:
    /// `maxLevel`: the finest tile level painted (finer tiles magnify it).
    /// `highlight`: a feature (layer, index) painted last, in the highlight's colours.
    /// `simplifyPx`: DrapeTileOptions::simplifyPx. `icons`: where the points' icons are read
    /// (shared by the layer's drapes; none: markers).
    VectorDrape(std::string name, std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles,
                TimeNs time, uint32_t maxLevel, std::optional<std::pair<size_t, size_t>> highlight = std::nullopt,
                double simplifyPx = 0.5, std::shared_ptr<IconCache> icons = nullptr);

    const std::string& name() const override { return name_; }
    uint32_t maxLevel(int) const override { return maxLevel_; }
    uint32_t minLevel() const override { return 0; }
    bool covers(const globe::GeoExtent& extent) const override;
    Result<globe::ImageryTile> readTile(const globe::TileImageRequest& request, const jobs::CancelToken* cancel) const override;

    /// About the camera range (m) from which tiles of `extent`'s size are drawn with
    /// `tilePixelsPerScreenPixel`, `size` pixels a side.
    static double rangeForTile(const globe::GeoExtent& extent, int size, double tilePixelsPerScreenPixel);

private:
    std::string name_;
    std::shared_ptr<const VectorContent> content_;
    std::shared_ptr<const ContentStyles> styles_;
    TimeNs time_;
    uint32_t maxLevel_;
    double simplifyPx_;
    std::shared_ptr<IconCache> icons_;
    double reachPx_ = 32.0;   ///< how far (screen px) a stroke, marker or icon reaches past its feature
    std::optional<std::pair<size_t, size_t>> highlight_;
    FeatureStyle highlightStyle_;
};

}  // namespace orbis::vector
