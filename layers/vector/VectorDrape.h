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
//
// A large source is paged (FeatureTiles): each tile paints from the page that holds its area,
// read by the painting thread the first time a tile of it is asked for.

#include "globe/TileImageSource.h"
#include "layers/vector/DrapeRaster.h"
#include "layers/vector/FeatureMesh.h"
#include "layers/vector/FeatureTiles.h"
#include "layers/vector/IconCache.h"
#include "layers/vector/VectorContent.h"

#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace orbis::vector {

/// A feature of a drape's content: by its index in its layer (a whole source) or, for a
/// paged source, by its fid (its index differs from page to page).
struct DrapeFeature {
    size_t layer = 0;
    size_t feature = 0;
    int64_t fid = -1;
};

/// What one state of a drape paints, besides the features.
struct DrapeState {
    std::string name;               ///< for messages
    TimeNs time = 0;
    uint32_t maxLevel = 18;         ///< the finest tile level painted (finer tiles magnify it)
    double simplifyPx = 0.5;        ///< DrapeTileOptions::simplifyPx
    std::shared_ptr<IconCache> icons;   ///< where the points' icons are read (none: markers)
    std::optional<DrapeFeature> highlight;   ///< painted last, in the highlight's colours
    /// Paged: the features drawn as meshes in this altitude mode are left out (a whole
    /// source's styles hide them already).
    std::optional<AltitudeMode> meshes;
};

class VectorDrape : public globe::TileImageSource {
public:
    /// A whole source in memory, each feature's style given.
    VectorDrape(DrapeState state, std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles);
    /// A paged source: each tile paints the features of its page (read on the painting thread
    /// when it is not in memory), styled by `style` (its rules switched as the layer has them)
    /// over each page's bound style. `bounds`: the source's extent, when OGR knows it. Tiles
    /// seen from farther than any style shows a feature read no page.
    VectorDrape(DrapeState state, std::shared_ptr<FeatureTiles> pages, const VectorStyle& style, std::optional<LonLatBounds> bounds);

    const std::string& name() const override { return state_.name; }
    uint32_t maxLevel(int) const override { return state_.maxLevel; }
    uint32_t minLevel() const override { return 0; }
    bool covers(const globe::GeoExtent& extent) const override;
    Result<globe::ImageryTile> readTile(const globe::TileImageRequest& request, const jobs::CancelToken* cancel) const override;

    /// About the camera range (m) from which tiles of `extent`'s size are drawn with
    /// `tilePixelsPerScreenPixel`, `size` pixels a side.
    static double rangeForTile(const globe::GeoExtent& extent, int size, double tilePixelsPerScreenPixel);

private:
    /// The features of `content` within `grown` shown at `range`, with their styles (given, or
    /// evaluated into `evaluated`), appended to `items` with their paint order.
    void collect(const VectorContent& content, const ContentStyles* styles, const globe::GeoExtent& grown, double range,
                 std::deque<FeatureStyle>& evaluated, std::vector<std::pair<int, DrapeItem>>& items) const;

    DrapeState state_;
    std::shared_ptr<const VectorContent> content_;
    std::shared_ptr<const ContentStyles> styles_;
    std::shared_ptr<FeatureTiles> pages_;
    std::vector<bool> rulesOn_;                 ///< paged: the rules switched on
    std::optional<LonLatBounds> bounds_;        ///< paged: the source's extent
    double maxRangeM_ = std::numeric_limits<double>::infinity();
    double reachPx_ = 32.0;   ///< how far (screen px) a stroke, marker or icon reaches past its feature
    FeatureStyle highlightStyle_;   ///< whole: the highlighted feature's
};

/// A feature's style made to stand out: bright yellow, wider, filled.
FeatureStyle highlighted(FeatureStyle style);

}  // namespace orbis::vector
