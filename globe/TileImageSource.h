#pragma once
// What paints the images of terrain tiles: a raster file warped to the tile (RasterSource), or
// content that lies on the ground and is drawn into the tile (vector features clamped to the
// terrain: layers/vector's drape). The terrain's pager (TerrainTiles) asks a source for one
// tile's image on its worker threads and knows nothing else about it. No Vulkan.

#include "base/Result.h"
#include "globe/TileKey.h"

#include <cstdint>
#include <string>
#include <vector>

namespace orbis::jobs {
class CancelToken;
}

namespace orbis::globe {

/// RGBA8 pixels, PIXEL-CENTRED on the extent: pixel i covers [west + i*dx, west + (i+1)*dx],
/// dx = width / size; row 0 is north. Straight alpha, sRGB; alpha 0 where there is no data.
struct ImageryTile {
    int size = 0;
    std::vector<uint8_t> rgba;  ///< size * size * 4
    bool anyValid = false;
};

struct TileImageRequest {
    GeoExtent extent;
    int size = 256;   ///< pixels a side
    /// Tile pixels per screen pixel where the tile is drawn (about: the terrain picks tiles
    /// by screen-space error), so that content sized in screen pixels (a line's width, a
    /// marker) is painted at about that size on the screen.
    double tilePixelsPerScreenPixel = 1.0;
};

class TileImageSource {
public:
    virtual ~TileImageSource() = default;
    /// For messages: a path, a URL, a layer's name.
    virtual const std::string& name() const = 0;
    /// Finest level whose tiles of `tileSize` pixels still add detail.
    virtual uint32_t maxLevel(int tileSize) const = 0;
    /// Coarsest level a tile may be asked for (0 normally).
    virtual uint32_t minLevel() const = 0;
    /// False when no tile within `extent`, nor any finer one, can have a pixel.
    virtual bool covers(const GeoExtent& extent) const = 0;
    /// One tile's image. Any thread, several at once; `cancel` is checked between steps.
    /// anyValid = false: nothing here (finer tiles may still have something).
    virtual Result<ImageryTile> readTile(const TileImageRequest& request, const jobs::CancelToken* cancel) const = 0;
};

}  // namespace orbis::globe
