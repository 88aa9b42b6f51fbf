#include "layers/vector/Triangulate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace orbis::vector {
namespace {

constexpr uint32_t kNone = 0xffffffffu;

double cross(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

/// Inside or on the counter-clockwise triangle abc.
bool inTriangle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 p) {
    return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

/// Inside the counter-clockwise triangle abc, not on its edges.
bool inTriangleStrictly(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 p) {
    return cross(a, b, p) > 0.0 && cross(b, c, p) > 0.0 && cross(c, a, p) > 0.0;
}

/// The rings as one linked ring per ring, then one ring once the holes are bridged in, then cut.
class EarCutter {
public:
    explicit EarCutter(std::span<const glm::dvec2> points) : points_(points) {}

    /// A ring [begin, end) as a linked ring in the orientation asked for; kNone if it has fewer
    /// than three distinct points.
    uint32_t addRing(uint32_t begin, uint32_t end, bool counterClockwise) {
        const bool ccw = ringArea2(points_.subspan(begin, end - begin)) > 0.0;
        uint32_t last = kNone;
        const auto append = [&](uint32_t i) {
            if (last != kNone && nodes_[last].p == points_[i]) return;   // a repeated point
            last = link(i, last);
        };
        if (ccw == counterClockwise)
            for (uint32_t i = begin; i < end; ++i) append(i);
        else
            for (uint32_t i = end; i-- > begin;) append(i);
        if (last != kNone && nodes_[last].p == nodes_[nodes_[last].next].p) last = remove(last);   // closed ring
        return last == kNone || nodes_[last].next == nodes_[last].prev ? kNone : last;
    }

    /// Joins each hole to the outer ring through a bridge to a vertex it sees, rightmost hole first.
    uint32_t bridgeHoles(uint32_t outer, std::vector<uint32_t> holes) {
        for (uint32_t& h : holes) h = rightmost(h);
        std::sort(holes.begin(), holes.end(), [&](uint32_t a, uint32_t b) { return nodes_[a].p.x > nodes_[b].p.x; });
        for (uint32_t h : holes) {
            const uint32_t visible = visibleVertex(h, outer);
            if (visible == kNone) continue;   // a hole outside its ring: left out
            split(visible, h);
        }
        return outer;
    }

    void cut(uint32_t start, std::vector<uint32_t>& out, TriangulateStats& stats) {
        start = dropCollinear(start);
        size_t remaining = count(start);
        if (remaining < 3) return;
        indexReflex(start, remaining);
        // A ring with no clean ear left first loses the points that cuts left on a line with
        // their neighbours, then gets a pass that lets reflex vertices lie on an ear's edges (the zero-width seams a clip leaves along a tile's edge), then one ear cut
        // without the containment test (a self-intersecting ring); after each cut the search is
        // clean again. The work is bounded: past this many ear tests every remaining ear is cut
        // without the test.
        size_t budget = 8 * remaining + 100000;
        enum class Stage { Clean, Relaxed, Force } stage = Stage::Clean;
        bool exhausted = false;
        uint32_t cur = start, stop = start;
        while (remaining > 3) {
            const uint32_t prev = nodes_[cur].prev, next = nodes_[cur].next;
            const bool forced = stage == Stage::Force || exhausted;
            bool ear = false;
            if (forced) {
                ear = isConvex(cur) || next == stop;   // no convex vertex in a whole pass: any
            } else {
                ear = isEar(cur, stage == Stage::Relaxed);
                exhausted = --budget == 0;
            }
            if (ear) {
                emit(prev, cur, next, out);
                ++(forced ? stats.forced : stats.clean);
                remove(cur);
                --remaining;
                updateReflex(prev);
                updateReflex(next);
                stage = Stage::Clean;
                cur = next;
                stop = prev;
                continue;
            }
            cur = next;
            if (cur == stop) {   // a whole pass without an ear
                // Cuts can leave points on a line with their new neighbours (zero-width spikes
                // and seams): drop them and search again before relaxing the test.
                const size_t before = remaining;
                cur = stop = dropCollinear(cur);
                remaining = count(cur);
                if (remaining < 3) return;
                if (remaining == before) stage = stage == Stage::Clean ? Stage::Relaxed : Stage::Force;
            }
        }
        emit(nodes_[cur].prev, cur, nodes_[cur].next, out);
        ++(stage == Stage::Force || exhausted ? stats.forced : stats.clean);
    }

private:
    struct Node {
        uint32_t index;   // into points_
        glm::dvec2 p;
        uint32_t prev = kNone, next = kNone;
        bool removed = false, reflex = false;
    };

    uint32_t link(uint32_t index, uint32_t last) {
        const auto n = uint32_t(nodes_.size());
        nodes_.push_back({index, points_[index]});
        if (last == kNone) {
            nodes_[n].prev = nodes_[n].next = n;
        } else {
            nodes_[n].next = nodes_[last].next;
            nodes_[n].prev = last;
            nodes_[nodes_[last].next].prev = n;
            nodes_[last].next = n;
        }
        return n;
    }

    /// Unlinks n; returns its predecessor.
    uint32_t remove(uint32_t n) {
        Node& node = nodes_[n];
        nodes_[node.prev].next = node.next;
        nodes_[node.next].prev = node.prev;
        node.removed = true;
        return node.prev;
    }

    size_t count(uint32_t start) const {
        size_t n = 0;
        uint32_t k = start;
        do {
            ++n;
            k = nodes_[k].next;
        } while (k != start);
        return n;
    }

    uint32_t rightmost(uint32_t start) const {
        uint32_t best = start, k = start;
        do {
            const glm::dvec2 p = nodes_[k].p, b = nodes_[best].p;
            if (p.x > b.x || (p.x == b.x && p.y < b.y)) best = k;
            k = nodes_[k].next;
        } while (k != start);
        return best;
    }

    /// A vertex of the outer ring that the hole's rightmost vertex m sees (Eberly): the ray from
    /// m towards +x hits an edge at i; its end p with the larger x is seen unless a reflex vertex
    /// lies in the triangle (m, i, p), in which case the one nearest the ray's direction is.
    uint32_t visibleVertex(uint32_t m, uint32_t outer) const {
        const glm::dvec2 mp = nodes_[m].p;
        double hitX = std::numeric_limits<double>::infinity();
        uint32_t candidate = kNone;
        uint32_t k = outer;
        do {
            const uint32_t n = nodes_[k].next;
            const glm::dvec2 a = nodes_[k].p, b = nodes_[n].p;
            // Edges that go up across the ray (the outer ring is counter-clockwise: the
            // interior is on their left, towards m).
            if (a.y <= mp.y && b.y >= mp.y && a.y != b.y) {
                const double x = a.x + (mp.y - a.y) * (b.x - a.x) / (b.y - a.y);
                if (x >= mp.x && x < hitX) {
                    hitX = x;
                    candidate = a.x > b.x ? k : n;
                    if (x == mp.x) return a.y == mp.y ? k : (b.y == mp.y ? n : candidate);
                }
            }
            k = n;
        } while (k != outer);
        if (candidate == kNone) return kNone;
        const glm::dvec2 hit{hitX, mp.y}, cp = nodes_[candidate].p;
        if (cp == hit) return candidate;
        // Reflex vertices inside (m, hit, candidate) hide the candidate: take the one at the
        // smallest angle from the ray, then the nearest.
        uint32_t best = candidate;
        double bestTan = std::abs(cp.y - mp.y) / std::max(cp.x - mp.x, 1e-300), bestDist = glm::distance(mp, cp);
        const glm::dvec2 t0 = mp, t1 = cp.y < mp.y ? cp : hit, t2 = cp.y < mp.y ? hit : cp;   // counter-clockwise
        k = outer;
        do {
            const glm::dvec2 p = nodes_[k].p;
            if (k != candidate && p.x >= mp.x && p != mp && inTriangle(t0, t1, t2, p) &&
                cross(nodes_[nodes_[k].prev].p, p, nodes_[nodes_[k].next].p) <= 0.0) {
                const double tan = std::abs(p.y - mp.y) / std::max(p.x - mp.x, 1e-300), dist = glm::distance(mp, p);
                if (tan < bestTan || (tan == bestTan && dist < bestDist)) {
                    best = k;
                    bestTan = tan;
                    bestDist = dist;
                }
            }
            k = nodes_[k].next;
        } while (k != outer);
        return best;
    }

    /// The bridge a -> b (a on the outer ring, b on a hole), and back through copies of both.
    void split(uint32_t a, uint32_t b) {
        const auto a2 = uint32_t(nodes_.size());
        nodes_.push_back({nodes_[a].index, nodes_[a].p});
        const auto b2 = uint32_t(nodes_.size());
        nodes_.push_back({nodes_[b].index, nodes_[b].p});
        const uint32_t an = nodes_[a].next, bp = nodes_[b].prev;
        nodes_[a].next = b;
        nodes_[b].prev = a;
        nodes_[a2].next = an;
        nodes_[an].prev = a2;
        nodes_[b2].next = a2;
        nodes_[a2].prev = b2;
        nodes_[bp].next = b2;
        nodes_[b2].prev = bp;
    }

    /// Drops repeated points and points on the line through their neighbours.
    uint32_t dropCollinear(uint32_t start) {
        uint32_t k = start, stop = start;
        for (;;) {
            const uint32_t prev = nodes_[k].prev, next = nodes_[k].next;
            if (next == prev) return k;   // two points left
            if (nodes_[k].p == nodes_[next].p || cross(nodes_[prev].p, nodes_[k].p, nodes_[next].p) == 0.0) {
                remove(k);
                k = stop = prev;   // the neighbour may have become collinear: look again from it
                continue;
            }
            k = next;
            if (k == stop) return k;
        }
    }

    bool isConvex(uint32_t n) const { return cross(nodes_[nodes_[n].prev].p, nodes_[n].p, nodes_[nodes_[n].next].p) > 0.0; }

    void indexReflex(uint32_t start, size_t n) {
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        uint32_t k = start;
        do {
            nodes_[k].reflex = !isConvex(k);
            lo = glm::min(lo, nodes_[k].p);
            hi = glm::max(hi, nodes_[k].p);
            k = nodes_[k].next;
        } while (k != start);
        const double side = std::max(1.0, std::floor(std::sqrt(double(n) / 2.0)));
        cells_ = glm::ivec2(int(std::min(side, 1024.0)));
        origin_ = lo;
        cellSize_ = glm::max((hi - lo) / glm::dvec2(cells_), glm::dvec2(1e-300));
        grid_.assign(size_t(cells_.x) * size_t(cells_.y), {});
        k = start;
        do {
            if (nodes_[k].reflex) {
                const glm::ivec2 c = cellOf(nodes_[k].p);
                grid_[size_t(c.y) * size_t(cells_.x) + size_t(c.x)].push_back(k);
            }
            k = nodes_[k].next;
        } while (k != start);
    }

    glm::ivec2 cellOf(glm::dvec2 p) const {
        return glm::clamp(glm::ivec2(glm::floor((p - origin_) / cellSize_)), glm::ivec2(0), cells_ - 1);
    }

    /// A vertex only turns from reflex to convex as ears are cut; the grid keeps it and the
    /// ear test skips it.
    void updateReflex(uint32_t n) {
        if (nodes_[n].reflex && isConvex(n)) nodes_[n].reflex = false;
    }

    /// `onEdgesAllowed`: a reflex vertex on the ear's boundary does not block it.
    bool isEar(uint32_t n, bool onEdgesAllowed) const {
        const uint32_t ia = nodes_[n].prev, ic = nodes_[n].next;
        const glm::dvec2 a = nodes_[ia].p, b = nodes_[n].p, c = nodes_[ic].p;
        if (cross(a, b, c) <= 0.0) return false;
        const glm::ivec2 lo = cellOf(glm::min(a, glm::min(b, c))), hi = cellOf(glm::max(a, glm::max(b, c)));
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x)
                for (uint32_t k : grid_[size_t(y) * size_t(cells_.x) + size_t(x)]) {
                    const Node& r = nodes_[k];
                    if (r.removed || !r.reflex || k == ia || k == ic || k == n) continue;
                    if (r.p == a || r.p == b || r.p == c) continue;   // a bridge's copy
                    if (onEdgesAllowed ? inTriangleStrictly(a, b, c, r.p) : inTriangle(a, b, c, r.p)) return false;
                }
        return true;
    }

    void emit(uint32_t a, uint32_t b, uint32_t c, std::vector<uint32_t>& out) const {
        out.insert(out.end(), {nodes_[a].index, nodes_[b].index, nodes_[c].index});
    }

    std::span<const glm::dvec2> points_;
    std::vector<Node> nodes_;
    glm::ivec2 cells_{1};
    glm::dvec2 origin_{0.0}, cellSize_{1.0};
    std::vector<std::vector<uint32_t>> grid_;
};

}  // namespace

double ringArea2(std::span<const glm::dvec2> ring) {
    double sum = 0.0;
    for (size_t i = 0, n = ring.size(); i < n; ++i) {
        const glm::dvec2 a = ring[i], b = ring[(i + 1) % n];
        sum += (a.x - ring[0].x) * (b.y - ring[0].y) - (b.x - ring[0].x) * (a.y - ring[0].y);
    }
    return sum;
}

Result<std::vector<uint32_t>> triangulate(std::span<const glm::dvec2> points, std::span<const uint32_t> ringStarts,
                                          size_t maxPoints, TriangulateStats* stats) {
    if (points.size() > maxPoints)
        return makeError("a polygon of " + std::to_string(points.size()) + " points is over the limit of " +
                         std::to_string(maxPoints));
    for (size_t r = 0; r < ringStarts.size(); ++r)
        if (ringStarts[r] >= points.size() || (r > 0 && ringStarts[r] <= ringStarts[r - 1]))
            return makeError("ring " + std::to_string(r) + " starts at point " + std::to_string(ringStarts[r]) +
                             ", out of order or past the " + std::to_string(points.size()) + " points");
    for (size_t i = 0; i < points.size(); ++i)
        if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y))
            return makeError("point " + std::to_string(i) + " of the polygon is not a finite number");
    TriangulateStats local;
    std::vector<uint32_t> out;
    if (ringStarts.empty()) return out;
    EarCutter cutter(points);
    const auto ringEnd = [&](size_t r) { return r + 1 < ringStarts.size() ? ringStarts[r + 1] : uint32_t(points.size()); };
    const uint32_t outer = cutter.addRing(ringStarts[0], ringEnd(0), true);
    if (outer == kNone) return out;
    std::vector<uint32_t> holes;
    for (size_t r = 1; r < ringStarts.size(); ++r)
        if (uint32_t h = cutter.addRing(ringStarts[r], ringEnd(r), false); h != kNone) holes.push_back(h);
    out.reserve(3 * points.size());
    cutter.cut(cutter.bridgeHoles(outer, std::move(holes)), out, local);
    if (stats) *stats = local;
    return out;
}

}  // namespace orbis::vector
