#pragma once
// The geodetic tiling profile: two root tiles (west and east hemispheres, 180 x 180 degrees)
// split as a quadtree. Level L has 2^(L+1) x 2^L tiles; x counts from the antimeridian (-180)
// eastward, y from the north pole southward (the row order of an image). No Vulkan.

#include <glm/glm.hpp>

#include <array>
#include <compare>
#include <cstdint>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace orbis::globe {

/// A lon/lat rectangle in degrees (west < east; geodetic tiles never cross the antimeridian).
struct GeoExtent {
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;

    double width() const { return east - west; }
    double height() const { return north - south; }
    double centerLon() const { return 0.5 * (west + east); }
    double centerLat() const { return 0.5 * (south + north); }
    bool contains(double lonDeg, double latDeg) const {
        return lonDeg >= west && lonDeg <= east && latDeg >= south && latDeg <= north;
    }
    bool intersects(const GeoExtent& o) const {
        return west < o.east && o.west < east && south < o.north && o.south < north;
    }
    bool valid() const { return west < east && south < north; }
    /// Whether the closed boxes touch, `o` moved a turn (360 degrees) either way included: for
    /// boxes whose longitudes run on past +-180 (a change region, a tile grown by a margin).
    bool meetsWithTurns(const GeoExtent& o) const {
        if (o.north < south || o.south > north) return false;
        for (double turn : {-360.0, 0.0, 360.0})
            if (o.west + turn <= east && o.east + turn >= west) return true;
        return false;
    }
    bool operator==(const GeoExtent&) const = default;
};

struct TileKey {
    static constexpr uint32_t kMaxLevel = 30;

    uint32_t level = 0, x = 0, y = 0;

    static uint32_t tilesX(uint32_t level) { return 2u << level; }
    static uint32_t tilesY(uint32_t level) { return 1u << level; }
    static std::array<TileKey, 2> roots() { return {TileKey{0, 0, 0}, TileKey{0, 1, 0}}; }
    /// The tile of `level` that contains the point (east and south edges belong to the next tile,
    /// except at +180 and -90).
    static TileKey containing(double lonDeg, double latDeg, uint32_t level);
    /// Parses a quadkey ("0", "1", then one digit 0-3 per level); nothing when malformed.
    static std::optional<TileKey> fromQuadKey(std::string_view quadKey);

    bool valid() const { return level <= kMaxLevel && x < tilesX(level) && y < tilesY(level); }
    GeoExtent extent() const;
    /// Size of the tile in degrees (square: width == height).
    double sizeDeg() const { return 180.0 / double(1u << level); }

    /// The parent; a root is its own parent.
    TileKey parent() const { return level == 0 ? *this : TileKey{level - 1, x >> 1, y >> 1}; }
    /// Children in the order north-west, north-east, south-west, south-east.
    std::array<TileKey, 4> children() const;
    /// Which child of its parent this tile is (0 NW, 1 NE, 2 SW, 3 SE); 0 for a root.
    int childIndex() const { return level == 0 ? 0 : int((x & 1u) | ((y & 1u) << 1)); }
    /// The ancestor at `ancestorLevel` (<= level).
    TileKey ancestor(uint32_t ancestorLevel) const;
    bool isAncestorOf(const TileKey& other) const;
    /// The neighbour dx tiles east and dy tiles south at the same level. x wraps across the
    /// antimeridian; there is no neighbour beyond a pole.
    std::optional<TileKey> neighbour(int dx, int dy) const;

    /// Maps this tile's texture coordinates (u east, v south, both 0..1) into those of
    /// `ancestor`: ancestorUv = uv * scale + bias. Returns (scaleU, scaleV, biasU, biasV).
    glm::dvec4 scaleBiasWithin(const TileKey& ancestor) const;

    std::string quadKey() const;
    std::string toString() const;   ///< "L/x/y"

    auto operator<=>(const TileKey&) const = default;
};

struct TileKeyHash {
    size_t operator()(const TileKey& k) const noexcept {
        uint64_t h = (uint64_t(k.level) << 58) ^ (uint64_t(k.x) << 29) ^ uint64_t(k.y);
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdULL;
        h ^= h >> 33;
        return size_t(h);
    }
};

}  // namespace orbis::globe
