#include "layers/vector/DrapeRaster.h"

#include "layers/vector/DrapeCoverage.h"
#include "layers/vector/FeatureClip.h"
#include "layers/vector/Simplify.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace orbis::vector {
namespace {

using drape::AreaCoverage;
using drape::StrokeCoverage;

/// Longitudes past 32 turns (and latitudes past this) are no place on the globe: skipped like
/// NaN, which also bounds the whole-turn copies of a feature to about 65.
constexpr double kMaxLonDeg = 32 * 360.0;
constexpr double kMaxLatDeg = 1e6;
/// Every part is thinned to this (px) in one pass: nothing visible changes.
constexpr double kNearPx = 0.125;
/// A part still denser than the tile can show (more vertices than this many per pixel of the
/// tile's side) goes through Douglas-Peucker (DrapeTileOptions::simplifyPx), in chunks of this many.
constexpr size_t kDenseVerticesPerSide = 4, kSimplifyChunk = 256;
/// A marker's dark outline (px), at most this share of its radius on small markers.
constexpr double kMarkerOutlinePx = 1.0, kMarkerOutlineShare = 0.25;

bool usable(const glm::dvec3& c) { return std::abs(c.x) <= kMaxLonDeg && std::abs(c.y) <= kMaxLatDeg; }   // false for NaN

/// A style value in 0..1; NaN is 0.
double unit(double v) { return v >= 0.0 ? std::min(v, 1.0) : 0.0; }

/// A part's lon/lat box over its usable vertices.
struct PartBox {
    double west = 0.0, east = 0.0, south = 0.0, north = 0.0;
    bool empty = true;
};

PartBox boxOf(std::span<const glm::dvec3> part) {
    PartBox b;
    for (const glm::dvec3& c : part) {
        if (!usable(c)) continue;
        if (b.empty) b = {c.x, c.x, c.y, c.y, false};
        b.west = std::min(b.west, c.x), b.east = std::max(b.east, c.x);
        b.south = std::min(b.south, c.y), b.north = std::max(b.north, c.y);
    }
    return b;
}

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

/// Linear-time thinning (Zhao and Saalfeld's sleeve fitting): from the last kept vertex, the
/// cone of directions that pass within `tolerance` of every vertex since narrows with each one;
/// the vertex before the first that leaves it (or that turns back) is kept. A dropped vertex
/// lies within about 1.4 x `tolerance` of the kept path. Streams: `emit` gets the kept ones.
class Sleeve {
public:
    explicit Sleeve(double tolerance) : tolerance_(tolerance) {}

    template <typename Emit>
    void push(glm::dvec3 p, Emit&& emit) {
        if (!started_) {
            emit(p);
            anchor_ = p, started_ = true;
            return;
        }
        if (!narrow(p)) {   // restart from the vertex before: p always fits a fresh cone
            emit(last_);
            anchor_ = last_, open_ = false, farthest2_ = back2_ = 0.0;
            narrow(p);
        }
        last_ = p, pending_ = true;
    }
    template <typename Emit>
    void finish(Emit&& emit) {
        if (pending_) emit(last_);
    }

private:
    bool narrow(glm::dvec3 point) {
        const glm::dvec2 p(point), v = p - glm::dvec2(anchor_);
        const double d2 = glm::dot(v, v), t2 = tolerance_ * tolerance_;
        if (d2 < back2_) return false;   // turning back
        if (d2 <= t2) return true;
        if (open_ && (cross(right_, v) < 0.0 || cross(v, left_) < 0.0)) return false;   // outside the cone
        // The tangents from the anchor to the circle of the tolerance around p, scaled by d^2
        // (only their directions matter): v rotated by +-asin(tolerance / d).
        const double c = std::sqrt(d2 - t2);
        const glm::dvec2 across{-v.y * tolerance_, v.x * tolerance_};
        const glm::dvec2 left = v * c + across, right = v * c - across;
        if (!open_) left_ = left, right_ = right, open_ = true;
        if (cross(left, left_) > 0.0) left_ = left;
        if (cross(right_, right) > 0.0) right_ = right;
        if (d2 > farthest2_) {
            farthest2_ = d2;
            const double back = std::sqrt(d2) - tolerance_;
            back2_ = back > 0.0 ? back * back : 0.0;
        }
        return true;
    }

    double tolerance_;
    glm::dvec3 anchor_{}, last_{};   ///< z rides along (the distance along the part)
    glm::dvec2 left_{}, right_{};
    double farthest2_ = 0.0, back2_ = 0.0;   ///< the farthest vertex since the anchor; nearer than back2_ turns back
    bool started_ = false, pending_ = false, open_ = false;
};

/// An edge a ring has only because its source cut the globe there: along the 180 meridian (in
/// any turn) or along a pole. Outlines leave them out.
bool isSeam(const glm::dvec3& a, const glm::dvec3& b) {
    if (a.y == b.y && std::abs(a.y) >= 90.0) return true;
    return a.x == b.x && std::abs(std::abs(std::remainder(a.x, 360.0)) - 180.0) < 1e-9;
}

bool hasSeam(std::span<const glm::dvec3> ring) {
    for (size_t i = 0; i + 1 < ring.size(); ++i)
        if (isSeam(ring[i], ring[i + 1])) return true;
    return ring.size() > 2 && isSeam(ring.back(), ring.front());
}

/// Paints one tile: the features' paths in pixel space, thinned to what the tile can show, into
/// the coverage buffers, each feature composited once.
class TilePainter {
public:
    TilePainter(const DrapeTileOptions& o, std::vector<uint8_t>& rgba)
        : extent_(o.extent), size_(o.size), pxPerLon_(o.size / o.extent.width()), pxPerLat_(o.size / o.extent.height()),
          pixelScale_(std::isfinite(o.pixelScale) && o.pixelScale > 0.0 ? o.pixelScale : 1.0), rgba_(rgba), area_(o.size),
          stroke_(o.size), simplifyPx_(std::isfinite(o.simplifyPx) && o.simplifyPx > 0.0 ? o.simplifyPx : 0.5), rangeM_(o.rangeM) {
        // A pixel's ground width over its height at the tile's middle latitude (bounded: near a
        // pole a stroke would span the tile across).
        xScale_ = std::clamp(std::cos(glm::radians(0.5 * (o.extent.south + o.extent.north))), 1.0 / 16.0, 1.0);
        stroke_.setXScale(xScale_);
    }

    /// True when the feature changed a pixel.
    bool paint(const Feature& f, const FeatureStyle& s, const ImageRgba8* icon) {
        if (f.kind == GeometryKind::Points) return paintPoints(f, s, icon);
        partBoxes(f);
        if (f.kind == GeometryKind::Lines) return paintLines(f, s);
        return paintPolygons(f, s);
    }
    size_t segments() const { return area_.edges() + stroke_.segments(); }

private:
    struct Stroke {
        double radius = 0.0;
        float scale = 0.0f;
        glm::dvec2 dash{0.0};   ///< on, off (tile px along the path); 0: solid
        bool valid() const { return radius > 0.0; }
    };

    glm::dvec2 toPixel(double lon, double lat) const { return {(lon - extent_.west) * pxPerLon_, (extent_.north - lat) * pxPerLat_}; }

    /// Widths under 1 px draw 1 px with alpha scaled by the width (a hairline fades, it does not
    /// vanish); the widest is two tiles, which bounds a segment's cost to the tile's pixels.
    Stroke strokeFor(const FeatureStyle& s) const {
        const double w = std::min(s.widthPx * pixelScale_, 2.0 * size_);
        if (!(w > 0.0)) return {};
        Stroke stroke = w >= 1.0 ? Stroke{0.5 * w + 0.5, 1.0f} : Stroke{1.0, float(w)};
        if (s.dashPx.x > 0.0 && s.dashPx.y > 0.0) stroke.dash = s.dashPx * pixelScale_;
        return stroke;
    }

    /// The whole turns k for which the box moved by 360 k meets the tile grown by `marginPx`.
    std::pair<int, int> turnsMeeting(const PartBox& b, double marginPx) const {
        const double mLon = marginPx / (pxPerLon_ * xScale_), mLat = marginPx / pxPerLat_;
        if (b.empty || b.south > extent_.north + mLat || b.north < extent_.south - mLat) return {1, 0};
        return {int(std::ceil((extent_.west - mLon - b.east) / 360.0)), int(std::floor((extent_.east + mLon - b.west) / 360.0))};
    }

    void partBoxes(const Feature& f) {
        boxes_.resize(f.parts.size());
        for (size_t p = 0; p < f.parts.size(); ++p) boxes_[p] = boxOf(f.part(p));
    }

    double thinPath(std::span<const glm::dvec3> part, double shiftDeg, double marginPx);
    void simplifyDense();
    void strokePath(const Stroke& s);
    void strokeRing(std::span<const glm::dvec3> ring, bool aroundPole, double shiftDeg, const Stroke& s);
    bool paintPolygons(const Feature& f, const FeatureStyle& s);
    bool paintLines(const Feature& f, const FeatureStyle& s);
    bool paintPoints(const Feature& f, const FeatureStyle& s, const ImageRgba8* icon);

    globe::GeoExtent extent_;
    int size_;
    double pxPerLon_, pxPerLat_, pixelScale_;
    double xScale_ = 1.0;   ///< a pixel's ground width over its height
    std::vector<uint8_t>& rgba_;
    AreaCoverage area_;
    StrokeCoverage stroke_;
    double simplifyPx_;
    double rangeM_;
    std::vector<PartBox> boxes_;
    std::vector<glm::dvec3> path_, spare_, poleRing_;   // reused between parts: no allocation per part once grown
};

/// `part` moved by `shiftDeg`, in pixel space (into path_), less what the tile cannot show:
/// sleeve-thinned to kNearPx, then a run of vertices all beyond one side of the tile grown by
/// `marginPx` keeps only its ends (the run's own edges and the chord between its ends add the
/// same to the fill inside the tile, and neither reaches it with a stroke). Non-usable vertices
/// are skipped. Returns twice the part's signed area in degrees: its orientation.
double TilePainter::thinPath(std::span<const glm::dvec3> part, double shiftDeg, double marginPx) {
    path_.clear();
    const double lo = -marginPx, hi = size_ + marginPx;
    const double loX = -marginPx / xScale_, hiX = size_ + marginPx / xScale_;
    unsigned runSides = 0;
    bool runOpen = false;
    const auto append = [&](glm::dvec3 p) {
        const unsigned sides = unsigned(p.x < loX) | unsigned(p.x > hiX) << 1 | unsigned(p.y < lo) << 2 | unsigned(p.y > hi) << 3;
        if (!path_.empty() && (sides & runSides) != 0) {   // still beyond a side the run shares
            if (runOpen) path_.back() = p;
            else path_.push_back(p), runOpen = true;
            runSides &= sides;
            return;
        }
        path_.push_back(p);
        runSides = sides, runOpen = false;
    };
    Sleeve sleeve(kNearPx);
    bool started = false;
    glm::dvec2 first{}, previous{};
    double area2 = 0.0;
    // The distance along the part from its first vertex, on the ground, in pixels of latitude
    // at this tile's level (the same in every tile of the level: dashes join across tiles).
    double along = 0.0;
    for (const glm::dvec3& c : part) {
        if (!usable(c)) continue;
        const glm::dvec2 g(c);
        if (!started) first = previous = g, started = true;
        area2 += (previous.x - first.x) * (g.y - first.y) - (g.x - first.x) * (previous.y - first.y);
        along += glm::length(glm::dvec2((g.x - previous.x) * std::cos(glm::radians(0.5 * (g.y + previous.y))), g.y - previous.y)) * pxPerLat_;
        previous = g;
        sleeve.push(glm::dvec3(toPixel(c.x + shiftDeg, c.y), along), append);
    }
    sleeve.finish(append);
    return area2;
}

/// Douglas-Peucker (Simplify.h, here in pixels) when the thinned path is still denser than the
/// tile can show (jagged or self-overlapping detail finer than a pixel). In chunks, because its
/// cost is quadratic at worst (a spiral): at most kSimplifyChunk distance checks a vertex,
/// whatever the input, for one more kept vertex a chunk.
void TilePainter::simplifyDense() {
    if (simplifyPx_ <= 0.5 && path_.size() <= kDenseVerticesPerSide * size_t(size_)) return;
    spare_.clear();
    for (size_t begin = 0; begin + 1 < path_.size(); begin += kSimplifyChunk) {
        const size_t last = std::min(begin + kSimplifyChunk, path_.size() - 1);
        const std::span<const glm::dvec3> chunk(path_.data() + begin, last - begin + 1);
        const std::vector<uint32_t> kept = simplifyPart(chunk, simplifyPx_, false);
        for (size_t i = 0; i + 1 < kept.size(); ++i) spare_.push_back(chunk[kept[i]]);   // its last starts the next chunk
    }
    spare_.push_back(path_.back());
    path_.swap(spare_);
}

void TilePainter::strokePath(const Stroke& s) {
    // Dashes under a pixel long would be a grey line: drawn solid.
    if (s.dash.x <= 0.0 || s.dash.x + s.dash.y < 1.0) {
        for (size_t i = 0; i + 1 < path_.size(); ++i) stroke_.addSegment(glm::dvec2(path_[i]), glm::dvec2(path_[i + 1]), s.radius, s.scale);
        return;
    }
    // Dashed: the "on" stretches of each segment, by the distance along the part that its
    // vertices carry (z), only over the segment's stretch that can reach the tile.
    const double period = s.dash.x + s.dash.y;
    for (size_t i = 0; i + 1 < path_.size(); ++i) {
        const glm::dvec2 a(path_[i]), b(path_[i + 1]), d = b - a;
        const double da = path_[i].z, length = path_[i + 1].z - da;
        double t0 = 0.0, t1 = 1.0;
        if (!stroke_.reach(a, b, s.radius, t0, t1)) continue;
        if (!(length > 0.0)) {   // no length along the part: on or off as its start is
            if (std::fmod(da, period) < s.dash.x) stroke_.addSegment(a + d * t0, a + d * t1, s.radius, s.scale);
            continue;
        }
        // Each dash is drawn `on` long with its round caps: its axis is shorter by the caps
        // (a dash shorter than its width is a dot).
        const double cap = std::max(s.radius - 0.5, 0.0), from = da + t0 * length, to = da + t1 * length;
        for (double start = std::floor((from - cap) / period) * period; start < to + cap; start += period) {
            double on0 = start + cap, on1 = start + s.dash.x - cap;
            if (on0 > on1) on0 = on1 = start + 0.5 * s.dash.x;
            on0 = std::max(on0, da), on1 = std::min(on1, da + length);
            if (on0 <= on1) stroke_.addSegment(a + d * ((on0 - da) / length), a + d * ((on1 - da) / length), s.radius, s.scale);
        }
    }
}

/// A ring's outline: its stored edges but the seams (pole, 180), in runs between them, and its
/// closing edge when it is not stored closed. A ring around a pole closes through the pole,
/// which is no edge of the land it bounds, so it has none.
void TilePainter::strokeRing(std::span<const glm::dvec3> ring, bool aroundPole, double shiftDeg, const Stroke& s) {
    const double margin = s.radius + 1.0;
    const auto strokeRun = [&](std::span<const glm::dvec3> run) {
        if (run.size() < 2) return;
        thinPath(run, shiftDeg, margin);
        simplifyDense();
        strokePath(s);
    };
    size_t start = 0;
    for (size_t i = 0; i + 1 < ring.size(); ++i)
        if (isSeam(ring[i], ring[i + 1])) strokeRun(ring.subspan(start, i + 1 - start)), start = i + 1;
    strokeRun(ring.subspan(start));
    if (!aroundPole && ring.size() > 2 && ring.front() != ring.back() && !isSeam(ring.back(), ring.front())) {
        const glm::dvec3 closing[2] = {ring.back(), ring.front()};
        strokeRun(closing);
    }
}

bool TilePainter::paintPolygons(const Feature& f, const FeatureStyle& s) {
    const auto poleOf = [&](size_t p) { return p < f.containsPole.size() ? f.containsPole[p] : int8_t(0); };
    const size_t polygons = f.polygons.empty() ? f.parts.size() : f.polygons.size();   // none listed: each ring its own
    const auto rings = [&](size_t k) -> std::pair<size_t, size_t> {
        if (f.polygons.empty()) return {k, k + 1};
        const size_t begin = std::min<size_t>(f.polygons[k], f.parts.size());
        return {begin, std::clamp<size_t>(f.polygonEnd(k), begin, f.parts.size())};
    };
    const auto fillBox = [&](size_t p) {   // a polar ring's fill reaches its pole
        PartBox b = boxes_[p];
        if (poleOf(p) > 0) b.north = 90.0;
        if (poleOf(p) < 0) b.south = -90.0;
        return b;
    };
    const double fillAlpha = unit(s.fillOpacity), alpha = unit(s.opacity);
    const Stroke stroke = s.outline && alpha > 0.0 ? strokeFor(s) : Stroke{};
    if (fillAlpha <= 0.0 && !stroke.valid()) return false;
    // One margin for both, so that a ring thinned for its fill is stroked from the same path.
    const double margin = stroke.valid() ? stroke.radius + 1.0 : 1.0;
    const auto meets = [&](const PartBox& b, double shift) {
        const double mLon = margin / (pxPerLon_ * xScale_), mLat = margin / pxPerLat_;
        return !b.empty && b.west + shift <= extent_.east + mLon && b.east + shift >= extent_.west - mLon &&
               b.south <= extent_.north + mLat && b.north >= extent_.south - mLat;
    };
    for (size_t k = 0; k < polygons; ++k) {
        const auto [begin, end] = rings(k);
        if (begin == end) continue;
        const auto [k0, k1] = turnsMeeting(fillBox(begin), margin);   // holes lie within their outer ring
        for (int turn = k0; turn <= k1; ++turn) {
            const double shift = 360.0 * turn;
            for (size_t p = begin; p < end; ++p) {
                if (p > begin && !meets(fillBox(p), shift)) continue;   // a hole away from the tile changes nothing there
                const std::span<const glm::dvec3> stored = f.part(p);
                const int8_t pole = poleOf(p);
                if (fillAlpha > 0.0) {
                    std::span<const glm::dvec3> ring = stored;
                    if (pole != 0) {   // closed through the pole, so that it bounds the polar cap
                        poleRing_.assign(ring.begin(), ring.end());
                        closeThroughPole(poleRing_, pole);
                        ring = poleRing_;
                    }
                    const double area2 = thinPath(ring, shift, margin);
                    simplifyDense();
                    // Outer rings add, holes subtract, whatever way they were stored.
                    const float sign = (area2 >= 0.0 ? 1.0f : -1.0f) * (p == begin ? 1.0f : -1.0f);
                    for (size_t i = 0; i < path_.size(); ++i)
                        area_.addEdge(glm::dvec2(path_[i]), glm::dvec2(path_[(i + 1) % path_.size()]), sign);
                }
                if (!stroke.valid()) continue;
                if (fillAlpha > 0.0 && pole == 0 && !hasSeam(stored)) {   // the fill's path, closed
                    strokePath(stroke);
                    if (path_.size() > 2 && path_.front() != path_.back())
                        stroke_.addSegment(glm::dvec2(path_.back()), glm::dvec2(path_.front()), stroke.radius, stroke.scale);
                } else {
                    strokeRing(stored, pole != 0, shift, stroke);
                }
            }
        }
    }
    // The fill first, then the outlines over it: two composites, each buffer of its own.
    const bool filled = fillAlpha > 0.0 && area_.compositeInto(rgba_, s.fill, fillAlpha);
    return (stroke.valid() && stroke_.compositeInto(rgba_, s.color, alpha)) || filled;
}

bool TilePainter::paintLines(const Feature& f, const FeatureStyle& s) {
    const Stroke stroke = strokeFor(s);
    const double alpha = unit(s.opacity);
    if (!stroke.valid() || alpha <= 0.0) return false;
    const double margin = stroke.radius + 1.0;
    for (size_t p = 0; p < f.parts.size(); ++p) {
        const auto [k0, k1] = turnsMeeting(boxes_[p], margin);
        for (int turn = k0; turn <= k1; ++turn) {
            thinPath(f.part(p), 360.0 * turn, margin);
            simplifyDense();
            strokePath(stroke);
        }
    }
    return stroke_.compositeInto(rgba_, s.color, alpha);
}

/// Each point is its own marker, composited in turn, like icons.
bool TilePainter::paintPoints(const Feature& f, const FeatureStyle& s, const ImageRgba8* icon) {
    const double diameter = std::min(s.iconSizeAt(rangeM_) * pixelScale_, 2.0 * size_);
    const double alpha = unit(s.opacity);
    if (!(diameter > 0.0) || alpha <= 0.0) return false;
    const double radius = 0.5 * diameter, outline = std::min(kMarkerOutlinePx, kMarkerOutlineShare * radius);
    bool changed = false;
    for (const glm::dvec3& c : f.coords) {
        if (!usable(c)) continue;
        const double reach = icon && icon->height > 0 ? 0.5 * diameter * std::max(1.0, double(icon->width) / icon->height) / xScale_ : radius;
        const auto [k0, k1] = turnsMeeting(PartBox{c.x, c.x, c.y, c.y, false}, reach + 1.0);
        for (int turn = k0; turn <= k1; ++turn) {
            const glm::dvec2 centre = toPixel(c.x + 360.0 * turn, c.y);
            changed = (icon ? drape::paintIcon(rgba_, size_, centre, diameter, icon->pixels.data(), int(icon->width), int(icon->height),
                                               alpha, xScale_)
                            : drape::paintMarker(rgba_, size_, centre, radius, outline, s.color, alpha, xScale_)) ||
                      changed;
        }
    }
    return changed;
}

/// An extent whose pixel coordinates of any usable vertex stay finite (and far from overflow:
/// below 10^25 px), and whose whole-turn counts fit an int.
bool validOptions(const DrapeTileOptions& o) {
    const globe::GeoExtent& e = o.extent;
    const auto sane = [](double deg) { return std::abs(deg) <= 1e4; };   // false for NaN
    return o.size >= 1 && o.size <= kMaxDrapeTileSize && sane(e.west) && sane(e.east) && sane(e.south) && sane(e.north) &&
           e.width() >= 1e-12 && e.height() >= 1e-12;
}

}  // namespace

bool rasterizeDrapeTile(std::span<const DrapeItem> items, const DrapeTileOptions& options, std::vector<uint8_t>& rgba,
                        DrapeTileStats* stats) {
    if (stats) *stats = {};
    if (!validOptions(options)) {
        rgba.clear();
        return false;
    }
    rgba.assign(size_t(options.size) * size_t(options.size) * 4, 0);
    TilePainter painter(options, rgba);
    size_t painted = 0;
    for (const DrapeItem& item : items) {
        if (!item.feature || !item.style || !item.style->visible) continue;
        if (painter.paint(*item.feature, *item.style, item.icon)) ++painted;
    }
    if (stats) *stats = {.featuresPainted = painted, .segments = painter.segments()};
    return painted > 0;   // a composite that ran set alpha >= 1 (it skips alphas under half a step)
}

}  // namespace orbis::vector
