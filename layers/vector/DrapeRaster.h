#pragma once
// Vector features painted into one terrain imagery tile on the CPU ("draping"): the tile is
// then blended over the terrain's imagery like any other imagery layer, so lines and fills
// follow the ground at every level. No Vulkan; any thread (each call has its own buffers), so
// the terrain's pager can run it next to its GDAL reads on the worker pool.
//
//   std::vector<DrapeItem> items;                     // painted in order, each over the ones before
//   for (size_t i = 0; i < features.size(); ++i) items.push_back({&features[i], &styles[i]});
//   DrapeTileOptions o{.extent = key.extent(), .size = 256, .pixelScale = 1.0};
//   std::vector<uint8_t> rgba;
//   if (rasterizeDrapeTile(items, o, rgba)) { ... }   // straight-alpha sRGB RGBA8, row 0 north
//
// Polygons are filled with exact area coverage (the signed-area accumulation of font
// rasterisers), holes empty whatever way their rings were stored, the polygons of one feature
// unioned; then, with `outline`, each ring is stroked. Lines are antialiased strokes with round
// joins, one feature's coverage combined with max so that its joints are not darker. Points are
// disks of the icon's size with a thin dark outline, or the item's icon image that high. Each
// feature is composited once ("over", straight alpha); a point feature's markers one by one.
//
// Longitudes unwrapped across the antimeridian (179 .. 181) are painted at every whole-turn
// shift that reaches the tile; a ring around a pole is closed through the pole for its fill, and
// its outline follows only the stored ring (no line along the pole or the 180 seam).
//
// The cost is linear in the vertices plus the cells the remaining edges cross: each part is
// thinned in pixel space in one pass (to 1/8 px, and a run of vertices wholly beyond one side of
// the tile keeps only its ends), and one still denser than the tile can show goes through
// Douglas-Peucker to 0.5 px (Simplify.h). An edge touches only the cells it crosses, a stroke
// segment only the pixels near it. Non-finite coordinates are skipped.

#include "base/Png.h"
#include "globe/TileKey.h"
#include "layers/vector/VectorReader.h"
#include "layers/vector/VectorStyle.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace orbis::vector {

/// One feature to paint and its resolved style; a null style, or one not visible, is skipped.
struct DrapeItem {
    const Feature* feature = nullptr;
    const FeatureStyle* style = nullptr;
    /// A point feature's icon (IconCache), drawn `iconSize` px high instead of the marker.
    const ImageRgba8* icon = nullptr;
};

struct DrapeTileOptions {
    globe::GeoExtent extent;   ///< the tile, lon/lat degrees
    /// Pixels a side (1 .. kMaxDrapeTileSize). PIXEL-CENTRED like globe::ImageryTile: pixel i
    /// covers [west + i * dx, west + (i + 1) * dx]; row 0 is north.
    int size = 256;
    /// Tile pixels per screen pixel: line widths and marker sizes (screen px) are multiplied by it.
    double pixelScale = 1.0;
    /// Douglas-Peucker tolerance (tile px) for a part denser than the tile can show; above the
    /// default every part is simplified to it (the quality knob "simplifyPx" of the layer).
    double simplifyPx = 0.5;
    /// The camera's range (m) from which the tile is drawn: icons that scale with it
    /// (FeatureStyle::iconSizeAt).
    double rangeM = 0.0;
};

/// The largest tile side, as for RasterSource::readImagery: the RGBA and two float coverage
/// buffers of 4096^2 are 192 MiB.
inline constexpr int kMaxDrapeTileSize = 4096;

struct DrapeTileStats {
    size_t featuresPainted = 0;   ///< items that changed at least one pixel
    size_t segments = 0;          ///< fill edges and stroke segments that reached the tile
};

/// Paints the items in order (each over the ones before) into `rgba`: resized to size*size*4
/// and cleared to 0 first; empty when the options are invalid (a size out of range; an extent
/// that is empty, narrower than 1e-12 degrees, or past 10^4 degrees). True when any pixel got
/// alpha > 0. Any thread.
bool rasterizeDrapeTile(std::span<const DrapeItem> items, const DrapeTileOptions& options, std::vector<uint8_t>& rgba,
                        DrapeTileStats* stats = nullptr);

}  // namespace orbis::vector
