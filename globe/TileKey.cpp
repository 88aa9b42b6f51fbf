#include "globe/TileKey.h"

#include <algorithm>
#include <cmath>

namespace orbis::globe {

TileKey TileKey::containing(double lonDeg, double latDeg, uint32_t level) {
    const double size = 180.0 / double(1u << level);
    const double fx = std::floor((lonDeg + 180.0) / size);
    const double fy = std::floor((90.0 - latDeg) / size);
    const auto clampTo = [](double v, uint32_t n) { return uint32_t(std::clamp(v, 0.0, double(n - 1))); };
    return TileKey{level, clampTo(fx, tilesX(level)), clampTo(fy, tilesY(level))};
}

std::optional<TileKey> TileKey::fromQuadKey(std::string_view q) {
    if (q.empty() || q.size() > kMaxLevel + 1 || (q[0] != '0' && q[0] != '1')) return std::nullopt;
    TileKey k{0, uint32_t(q[0] - '0'), 0};
    for (size_t i = 1; i < q.size(); ++i) {
        if (q[i] < '0' || q[i] > '3') return std::nullopt;
        k = k.children()[size_t(q[i] - '0')];
    }
    return k;
}

GeoExtent TileKey::extent() const {
    const double size = sizeDeg();
    GeoExtent e;
    e.west = -180.0 + double(x) * size;
    e.east = x + 1 == tilesX(level) ? 180.0 : -180.0 + double(x + 1) * size;
    e.north = 90.0 - double(y) * size;
    e.south = y + 1 == tilesY(level) ? -90.0 : 90.0 - double(y + 1) * size;
    return e;
}

std::array<TileKey, 4> TileKey::children() const {
    const uint32_t l = level + 1, cx = x * 2, cy = y * 2;
    return {TileKey{l, cx, cy}, TileKey{l, cx + 1, cy}, TileKey{l, cx, cy + 1}, TileKey{l, cx + 1, cy + 1}};
}

TileKey TileKey::ancestor(uint32_t ancestorLevel) const {
    if (ancestorLevel >= level) return *this;
    const uint32_t shift = level - ancestorLevel;
    return TileKey{ancestorLevel, x >> shift, y >> shift};
}

bool TileKey::isAncestorOf(const TileKey& other) const {
    return other.level > level && other.ancestor(level) == *this;
}

std::optional<TileKey> TileKey::neighbour(int dx, int dy) const {
    const int64_t ny = int64_t(y) + dy;
    if (ny < 0 || ny >= int64_t(tilesY(level))) return std::nullopt;
    const int64_t n = tilesX(level);
    const int64_t nx = ((int64_t(x) + dx) % n + n) % n;
    return TileKey{level, uint32_t(nx), uint32_t(ny)};
}

glm::dvec4 TileKey::scaleBiasWithin(const TileKey& a) const {
    if (a.level >= level) return {1.0, 1.0, 0.0, 0.0};
    const uint32_t shift = level - a.level;
    const double scale = 1.0 / double(1u << shift);
    const double bu = double(x - (a.x << shift)) * scale;
    const double bv = double(y - (a.y << shift)) * scale;
    return {scale, scale, bu, bv};
}

std::string TileKey::quadKey() const {
    std::string q(level + 1, '0');
    q[0] = char('0' + (x >> level));
    for (uint32_t l = 1; l <= level; ++l) {
        const uint32_t shift = level - l;
        q[l] = char('0' + (((x >> shift) & 1u) | (((y >> shift) & 1u) << 1)));
    }
    return q;
}

std::string TileKey::toString() const {
    return std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y);
}

}  // namespace orbis::globe
