#include "layers/vector/DrapeCoverage.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace orbis::vector::drape {
namespace {

/// Below half a step of an 8-bit alpha a composite changes nothing worth its cost; the prefix
/// sums' float rounding (about 1e-6) also stays under it, so untouched pixels stay exactly 0.
constexpr float kMinAlpha = 0.5f / 255.0f;
/// The marker's outline: near black, so that a marker reads on any imagery.
constexpr glm::vec3 kMarkerOutline{20.0f, 20.0f, 20.0f};

glm::vec3 toBytes(const glm::dvec3& rgb) { return glm::vec3(glm::clamp(rgb, 0.0, 1.0) * 255.0); }

}  // namespace

void compositeOver(uint8_t* dst, const glm::vec3& rgb, float a) {
    const float keep = dst[3] * (1.0f / 255.0f) * (1.0f - a);   // what the pixel below still shows
    const float out = a + keep;
    if (out <= 0.0f) return;
    const float inv = 1.0f / out;
    for (int c = 0; c < 3; ++c) dst[c] = uint8_t(std::clamp((rgb[c] * a + float(dst[c]) * keep) * inv, 0.0f, 255.0f) + 0.5f);
    dst[3] = uint8_t(std::min(out * 255.0f + 0.5f, 255.0f));
}

AreaCoverage::AreaCoverage(int size) : size_(size), stride_(size + 2), acc_(size_t(size + 2) * size_t(size), 0.0f) {
    rowMin_ = size_, colMin_ = size_;
}

void AreaCoverage::addEdge(glm::dvec2 a, glm::dvec2 b, float sign) {
    const double side = size_;
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y)) return;
    if (a.y == b.y) return;   // horizontal: no area to its east changes
    if (a.y > b.y) std::swap(a, b), sign = -sign;
    if (b.y <= 0.0 || a.y >= side || (a.x >= side && b.x >= side)) return;
    // Cut to the tile's rows; parameters, not slopes, so a near-horizontal edge stays finite.
    const glm::dvec2 d = b - a;
    if (a.y < 0.0) a = {a.x + d.x * (-a.y / d.y), 0.0};
    if (b.y > side) b = {b.x - d.x * ((b.y - side) / d.y), side};
    // Split where it crosses the tile's west and east sides.
    double ts[4] = {0.0, 1.0, 1.0, 1.0};
    int n = 1;
    const double dx = b.x - a.x;
    if ((a.x < 0.0) != (b.x < 0.0)) ts[n++] = std::clamp(-a.x / dx, 0.0, 1.0);
    if ((a.x > side) != (b.x > side)) ts[n++] = std::clamp((side - a.x) / dx, 0.0, 1.0);
    ts[n++] = 1.0;
    if (n == 4 && ts[1] > ts[2]) std::swap(ts[1], ts[2]);
    for (int i = 0; i + 1 < n; ++i) {
        const double t0 = ts[i], t1 = ts[i + 1];
        if (t1 <= t0) continue;
        const double midX = a.x + dx * (0.5 * (t0 + t1));
        if (midX >= side) continue;   // east of the tile
        glm::dvec2 p = i == 0 ? a : a + (b - a) * t0, q = i + 2 == n ? b : a + (b - a) * t1;
        if (midX <= 0.0) p.x = q.x = 0.0;   // west of the tile: a vertical edge on its west side
        p.x = std::clamp(p.x, 0.0, side), q.x = std::clamp(q.x, 0.0, side);
        p.y = std::clamp(p.y, 0.0, side), q.y = std::clamp(q.y, 0.0, side);
        if (q.y > p.y) accumulate(p, q, sign);
    }
}

void AreaCoverage::accumulate(glm::dvec2 p0, glm::dvec2 p1, float sign) {
    ++edges_;
    const double side = size_;
    const double dxdy = (p1.x - p0.x) / (p1.y - p0.y);
    double x = p0.x;
    const int yStart = std::clamp(int(p0.y), 0, size_ - 1), yEnd = std::min(size_, int(std::ceil(p1.y)));
    rowMin_ = std::min(rowMin_, yStart), rowMax_ = std::max(rowMax_, yEnd - 1);
    colMin_ = std::min(colMin_, int(std::min(p0.x, p1.x)));
    for (int y = yStart; y < yEnd; ++y) {
        float* row = acc_.data() + size_t(y) * size_t(stride_);
        const double dy = std::min(double(y + 1), p1.y) - std::max(double(y), p0.y);
        const double xNext = std::clamp(x + dxdy * dy, 0.0, side);
        const double d = dy * sign;
        const double x0 = std::min(x, xNext), x1 = std::max(x, xNext);
        const double x0Floor = std::floor(x0), x1Ceil = std::ceil(x1);
        const int x0i = int(x0Floor), x1i = int(x1Ceil);
        if (x1i <= x0i + 1) {   // within one column: split its area by the mean x
            const double xmf = 0.5 * (x + xNext) - x0Floor;
            row[x0i] += float(d - d * xmf);
            row[x0i + 1] += float(d * xmf);
        } else {   // across columns: a triangle, full-slope cells, and a triangle
            const double s = 1.0 / (x1 - x0);
            const double x0f = x0 - x0Floor;
            const double a0 = 0.5 * s * (1.0 - x0f) * (1.0 - x0f);
            const double x1f = x1 - x1Ceil + 1.0;
            const double am = 0.5 * s * x1f * x1f;
            row[x0i] += float(d * a0);
            if (x1i == x0i + 2) {
                row[x0i + 1] += float(d * (1.0 - a0 - am));
            } else {
                const double a1 = s * (1.5 - x0f);
                row[x0i + 1] += float(d * (a1 - a0));
                const auto ds = float(d * s);
                for (int xi = x0i + 2; xi < x1i - 1; ++xi) row[xi] += ds;
                const double a2 = a1 + double(x1i - x0i - 3) * s;
                row[x1i - 1] += float(d * (1.0 - a2 - am));
            }
            row[x1i] += float(d * am);
        }
        x = xNext;
    }
}

bool AreaCoverage::compositeInto(std::vector<uint8_t>& rgba, const glm::dvec3& rgb, double alpha) {
    bool changed = false;
    const glm::vec3 colour = toBytes(rgb);
    const auto a = float(std::clamp(alpha, 0.0, 1.0));
    const int colMin = std::clamp(colMin_, 0, size_);
    for (int y = rowMin_; y <= rowMax_; ++y) {
        float* row = acc_.data() + size_t(y) * size_t(stride_);
        uint8_t* out = rgba.data() + size_t(y) * size_t(size_) * 4;
        float winding = 0.0f;
        for (int x = colMin; x < size_; ++x) {
            winding += row[x];
            row[x] = 0.0f;
            const float coverage = a * std::min(std::abs(winding), 1.0f);
            if (coverage < kMinAlpha) continue;
            compositeOver(out + size_t(x) * 4, colour, coverage);
            changed = true;
        }
        row[size_] = row[size_ + 1] = 0.0f;
    }
    rowMin_ = size_, rowMax_ = -1, colMin_ = size_;
    return changed;
}

StrokeCoverage::StrokeCoverage(int size) : size_(size), coverage_(size_t(size) * size_t(size), 0.0f) {
    x0_ = y0_ = size_;
}

bool StrokeCoverage::reach(glm::dvec2 a, glm::dvec2 b, double radius, double& t0, double& t1) const {
    // Liang-Barsky against the tile grown by the radius: what lies past it cannot reach a pixel
    // centre, and a point of the tile nearest the segment is nearest its clipped part.
    const double rx = radius / xScale_;   // the radius in pixels across, on the ground
    const glm::dvec2 d = b - a;
    t0 = 0.0, t1 = 1.0;
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x + rx, size_ + rx - a.x, a.y + radius, size_ + radius - a.y};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0.0) {
            if (q[k] < 0.0) return false;
            continue;
        }
        const double t = q[k] / p[k];
        if (p[k] < 0.0) t0 = std::max(t0, t);
        else t1 = std::min(t1, t);
        if (t0 > t1) return false;
    }
    return t0 <= t1;   // false for NaN
}

void StrokeCoverage::addSegment(glm::dvec2 a, glm::dvec2 b, double radius, float scale) {
    double t0 = 0.0, t1 = 1.0;
    if (!reach(a, b, radius, t0, t1)) return;
    const double k = xScale_, rx = radius / k;
    const glm::dvec2 d = b - a;
    ++segments_;
    const glm::dvec2 s = a + d * t0, e = a + d * t1, se = e - s;
    const glm::dvec2 seK{se.x * k, se.y};   // on the ground
    const double len2 = glm::dot(seK, seK);
    const double full2 = radius > 1.0 ? (radius - 1.0) * (radius - 1.0) : -1.0, none2 = radius * radius;
    const int jMin = std::max(0, int(std::ceil(std::min(s.y, e.y) - radius - 0.5)));
    const int jMax = std::min(size_ - 1, int(std::floor(std::max(s.y, e.y) + radius - 0.5)));
    for (int j = jMin; j <= jMax; ++j) {
        const double yc = j + 0.5;
        // The segment's x extent over the rows within the radius, widened by the radius.
        double xa = std::min(s.x, e.x), xb = std::max(s.x, e.x);
        if (se.y != 0.0) {
            double ta = (yc - radius - s.y) / se.y, tb = (yc + radius - s.y) / se.y;
            if (ta > tb) std::swap(ta, tb);
            ta = std::max(ta, 0.0), tb = std::min(tb, 1.0);
            if (ta > tb) continue;
            xa = s.x + se.x * ta, xb = s.x + se.x * tb;
            if (xa > xb) std::swap(xa, xb);
        }
        const int iMin = std::max(0, int(std::ceil(xa - rx - 0.5)));
        const int iMax = std::min(size_ - 1, int(std::floor(xb + rx - 0.5)));
        if (iMin > iMax) continue;
        float* row = coverage_.data() + size_t(j) * size_t(size_);
        for (int i = iMin; i <= iMax; ++i) {
            const glm::dvec2 c{(i + 0.5 - s.x) * k, yc - s.y};   // from s, on the ground
            const double t = len2 > 0.0 ? std::clamp(glm::dot(c, seK) / len2, 0.0, 1.0) : 0.0;
            const glm::dvec2 off = c - seK * t;
            const double dist2 = glm::dot(off, off);
            if (dist2 >= none2) continue;
            const float v = dist2 <= full2 ? scale : scale * float(std::min(radius - std::sqrt(dist2), 1.0));
            row[i] = std::max(row[i], v);
        }
        x0_ = std::min(x0_, iMin), x1_ = std::max(x1_, iMax);
        y0_ = std::min(y0_, j), y1_ = std::max(y1_, j);
    }
}

bool StrokeCoverage::compositeInto(std::vector<uint8_t>& rgba, const glm::dvec3& rgb, double alpha) {
    bool changed = false;
    const glm::vec3 colour = toBytes(rgb);
    const auto a = float(std::clamp(alpha, 0.0, 1.0));
    for (int y = y0_; y <= y1_; ++y) {
        float* row = coverage_.data() + size_t(y) * size_t(size_);
        uint8_t* out = rgba.data() + size_t(y) * size_t(size_) * 4;
        for (int x = x0_; x <= x1_; ++x) {
            const float coverage = a * row[x];
            row[x] = 0.0f;
            if (coverage < kMinAlpha) continue;
            compositeOver(out + size_t(x) * 4, colour, coverage);
            changed = true;
        }
    }
    x0_ = y0_ = size_, x1_ = y1_ = -1;
    return changed;
}

bool paintMarker(std::vector<uint8_t>& rgba, int size, glm::dvec2 centre, double radius, double outlinePx,
                 const glm::dvec3& rgb, double alpha, double xScale) {
    const double reach = radius + 0.5, reachX = reach / xScale;
    if (!std::isfinite(centre.x) || !std::isfinite(centre.y) || !(reach > 0.0) || !(xScale > 0.0)) return false;
    const int jMin = int(std::clamp(std::ceil(centre.y - reach - 0.5), 0.0, double(size)));
    const int jMax = int(std::clamp(std::floor(centre.y + reach - 0.5), -1.0, double(size - 1)));
    const int iMin = int(std::clamp(std::ceil(centre.x - reachX - 0.5), 0.0, double(size)));
    const int iMax = int(std::clamp(std::floor(centre.x + reachX - 0.5), -1.0, double(size - 1)));
    const glm::vec3 fill = toBytes(rgb);
    const auto a = float(std::clamp(alpha, 0.0, 1.0));
    bool changed = false;
    for (int j = jMin; j <= jMax; ++j)
        for (int i = iMin; i <= iMax; ++i) {
            const double dist = glm::length(glm::dvec2((i + 0.5 - centre.x) * xScale, j + 0.5 - centre.y));
            const auto outer = float(std::clamp(reach - dist, 0.0, 1.0));
            const float coverage = a * outer;
            if (coverage < kMinAlpha) continue;
            // The outline is the part of the disk outside its inner disk: mix by that share.
            const auto inner = float(std::clamp(reach - outlinePx - dist, 0.0, 1.0));
            compositeOver(&rgba[(size_t(j) * size_t(size) + size_t(i)) * 4], glm::mix(kMarkerOutline, fill, inner / outer), coverage);
            changed = true;
        }
    return changed;
}

bool paintIcon(std::vector<uint8_t>& rgba, int size, glm::dvec2 centre, double heightPx, const uint8_t* icon, int iconWidth,
               int iconHeight, double alpha, double xScale) {
    if (!icon || iconWidth <= 0 || iconHeight <= 0 || !(heightPx > 0.0) || !(xScale > 0.0) || !std::isfinite(centre.x) ||
        !std::isfinite(centre.y))
        return false;
    const double h = heightPx, w = heightPx * iconWidth / iconHeight / xScale;
    const glm::dvec2 corner = centre - 0.5 * glm::dvec2(w, h);
    const int jMin = int(std::clamp(std::floor(corner.y), 0.0, double(size)));
    const int jMax = int(std::clamp(std::ceil(corner.y + h), 0.0, double(size)));
    const int iMin = int(std::clamp(std::floor(corner.x), 0.0, double(size)));
    const int iMax = int(std::clamp(std::ceil(corner.x + w), 0.0, double(size)));
    // Icon texels per pixel, across each way: that many samples a pixel, at most 8.
    const int n = int(std::clamp(std::ceil(std::max(iconWidth / w, iconHeight / h)), 1.0, 8.0));
    const auto texel = [&](int x, int y) { return icon + (size_t(y) * size_t(iconWidth) + size_t(x)) * 4; };
    const auto a = float(std::clamp(alpha, 0.0, 1.0));
    bool changed = false;
    for (int j = jMin; j < jMax; ++j)
        for (int i = iMin; i < iMax; ++i) {
            // Premultiplied sums of the samples (a sample outside the icon is transparent).
            glm::vec4 sum(0.0f);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const double u = (i + (sx + 0.5) / n - corner.x) / w * iconWidth - 0.5;
                    const double v = (j + (sy + 0.5) / n - corner.y) / h * iconHeight - 0.5;
                    if (u < -0.5 || v < -0.5 || u > iconWidth - 0.5 || v > iconHeight - 0.5) continue;
                    const int x0 = std::clamp(int(std::floor(u)), 0, iconWidth - 1), y0 = std::clamp(int(std::floor(v)), 0, iconHeight - 1);
                    const int x1 = std::min(x0 + 1, iconWidth - 1), y1 = std::min(y0 + 1, iconHeight - 1);
                    const auto fx = float(std::clamp(u - x0, 0.0, 1.0)), fy = float(std::clamp(v - y0, 0.0, 1.0));
                    const auto premul = [&](const uint8_t* t) { return glm::vec4(glm::vec3(t[0], t[1], t[2]) * (t[3] / 255.0f), t[3] / 255.0f); };
                    sum += glm::mix(glm::mix(premul(texel(x0, y0)), premul(texel(x1, y0)), fx),
                                    glm::mix(premul(texel(x0, y1)), premul(texel(x1, y1)), fx), fy);
                }
            sum /= float(n * n);
            const float coverage = a * sum.a;
            if (coverage < kMinAlpha) continue;
            compositeOver(&rgba[(size_t(j) * size_t(size) + size_t(i)) * 4], glm::vec3(sum) / sum.a, coverage);
            changed = true;
        }
    return changed;
}

}  // namespace orbis::vector::drape
