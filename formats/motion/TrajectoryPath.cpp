// The trajectory's path line and bounds (Trajectory.h): what is drawn and framed, apart from
// the pose at one time.
#include "formats/motion/Trajectory.h"

#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::motion {
namespace {

/// A path piece bending less than this away from its chord (metres) is drawn as the chord.
constexpr double kFlatTolerance = 0.05;
/// Most points put on a curve between two samples.
constexpr std::size_t kMaxPointsPerSegment = 16;

/// Longitude change from a to b the short way, in (-180, 180].
double lonDelta(double a, double b) {
    double d = std::fmod(b - a, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d <= -180.0) d += 360.0;
    return d;
}

/// A segment from `a` to `p` (ECEF; longitudes given) that turns the longitude by over 90
/// degrees passes by a pole: widens `bb`'s latitudes to where the segment comes closest to the
/// Earth's axis (over a pole, the pole itself, which no sample need be at) and returns true.
bool widenPastPole(TrajectoryBounds& bb, const glm::dvec3& a, double aLonDeg, const glm::dvec3& p, double pLonDeg) {
    if (std::abs(lonDelta(aLonDeg, pLonDeg)) <= 90.0) return false;
    const glm::dvec2 axy(a.x, a.y), dxy(p.x - a.x, p.y - a.y);
    const double dd = glm::dot(dxy, dxy);
    const double u = dd > 0.0 ? -glm::dot(axy, dxy) / dd : 0.0;
    if (u > 0.0 && u < 1.0) {
        const double lat = globe::Ellipsoid::wgs84().toGeodetic(a + u * (p - a)).latDeg;
        bb.southDeg = std::min(bb.southDeg, lat);
        bb.northDeg = std::max(bb.northDeg, lat);
    }
    return true;
}

}  // namespace

glm::dvec3 Trajectory::pointOn(std::size_t i, double s, const GroundFn* ground) const {
    glm::dvec3 p, v;
    glm::dquat q;
    double w = 0.0;
    if (knots_.size() == 1) {
        p = knots_[0].p;
        w = knots_[0].groundWeight;
    } else {
        interpolate(i, s, p, v, q, w);
    }
    if (w > 0.0 && ground && *ground) {
        const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(p);
        if (const std::optional<double> terrain = (*ground)(g.lonDeg, g.latDeg); terrain && std::isfinite(*terrain))
            p += globe::Ellipsoid::wgs84().surfaceNormal(g.lonDeg, g.latDeg) * (w * *terrain);
    }
    return p;
}

std::vector<glm::dvec3> Trajectory::pathEcef(TimeNs from, TimeNs to, std::size_t maxPoints, const GroundFn* ground) const {
    std::vector<glm::dvec3> out;
    const TimeNs a = std::max(from, times_.front()), b = std::min(to, times_.back());
    if (from > to || a > b) return out;
    maxPoints = std::max<std::size_t>(maxPoints, 2);
    if (times_.size() == 1 || a == b) {
        double s = 0.0;
        const std::size_t i = times_.size() == 1 ? 0 : segmentOf(a, s);
        out.push_back(pointOn(i, s, ground));
        return out;
    }
    // Samples strictly inside (a, b): [first, last).
    const std::size_t first = std::size_t(std::upper_bound(times_.begin(), times_.end(), a) - times_.begin());
    const std::size_t last = std::size_t(std::lower_bound(times_.begin(), times_.end(), b) - times_.begin());
    const std::size_t inside = last > first ? last - first : 0;
    double sa = 0.0, sb = 0.0;
    const std::size_t ia = segmentOf(a, sa), ib = segmentOf(b, sb);

    if (inside + 2 > maxPoints) {   // too many samples: every k-th, evenly
        const std::size_t keep = maxPoints - 2;
        out.reserve(maxPoints);
        out.push_back(pointOn(ia, sa, ground));
        for (std::size_t j = 0; j < keep; ++j) {
            const std::size_t k = first + std::size_t(double(j) * double(inside) / double(keep));
            out.push_back(k + 1 < times_.size() ? pointOn(k, 0.0, ground) : pointOn(k - 1, 1.0, ground));
        }
        out.push_back(pointOn(ib, sb, ground));
        return out;
    }

    // Pieces between consecutive points: (segment, s from, s to).
    struct Piece {
        std::size_t segment;
        double s0, s1;
        bool curved;
    };
    std::vector<Piece> pieces;
    pieces.reserve(inside + 1);
    auto bends = [&](std::size_t i) {
        if (interpolation_ != Interpolation::CatmullRom) return false;
        // The Hermite curve minus its chord is h10 (h m0 - d) + h11 (h m1 - d), |h10|, |h11| <= 4/27.
        const Knot& k0 = knots_[i];
        const glm::dvec3 d = knots_[i + 1].p - k0.p;
        const double bound = 4.0 / 27.0 *
                             (glm::length(k0.seconds * k0.m - d) + glm::length(k0.seconds * knots_[i + 1].m - d));
        return bound > kFlatTolerance;
    };
    if (inside == 0) {
        pieces.push_back({ia, sa, ia == ib ? sb : 1.0, bends(ia)});
    } else {
        pieces.push_back({ia, sa, 1.0, bends(ia)});
        for (std::size_t k = first; k + 1 < last; ++k) pieces.push_back({k, 0.0, 1.0, bends(k)});
        pieces.push_back({last - 1, 0.0, last - 1 == ib ? sb : 1.0, bends(last - 1)});
    }
    const std::size_t curved = std::size_t(std::count_if(pieces.begin(), pieces.end(), [](const Piece& p) { return p.curved; }));
    const std::size_t spare = maxPoints - (inside + 2);
    const std::size_t per = curved == 0 ? 0 : std::min(kMaxPointsPerSegment, spare / curved);

    out.reserve(inside + 2 + per * curved);
    for (const Piece& piece : pieces) {
        out.push_back(pointOn(piece.segment, piece.s0, ground));
        if (!piece.curved) continue;
        for (std::size_t k = 1; k <= per; ++k)
            out.push_back(pointOn(piece.segment, piece.s0 + (piece.s1 - piece.s0) * double(k) / double(per + 1), ground));
    }
    out.push_back(pointOn(ib, sb, ground));
    return out;
}

void Trajectory::computeBounds() {
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    TrajectoryBounds& bb = bounds_;
    bb.southDeg = bb.minHeight = std::numeric_limits<double>::infinity();
    bb.northDeg = bb.maxHeight = -std::numeric_limits<double>::infinity();
    std::vector<double> lons;
    lons.reserve(knots_.size());
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    bool aroundPole = false;
    double prevLon = 0.0;
    for (std::size_t i = 0; i < knots_.size(); ++i) {
        const glm::dvec3& p = knots_[i].p;
        const globe::Geodetic g = e.toGeodetic(p);
        lons.push_back(globe::wrapLongitude(g.lonDeg));
        bb.southDeg = std::min(bb.southDeg, g.latDeg);
        bb.northDeg = std::max(bb.northDeg, g.latDeg);
        bb.minHeight = std::min(bb.minHeight, g.height);
        bb.maxHeight = std::max(bb.maxHeight, g.height);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
        if (i > 0 && widenPastPole(bb, knots_[i - 1].p, prevLon, p, g.lonDeg)) aroundPole = true;
        prevLon = g.lonDeg;
    }
    // Longitudes: the complement of the widest gap between them around the circle.
    std::sort(lons.begin(), lons.end());
    double widest = lons.front() + 360.0 - lons.back();
    bb.westDeg = lons.front();
    bb.eastDeg = lons.back();
    for (std::size_t i = 0; i + 1 < lons.size(); ++i) {
        if (lons[i + 1] - lons[i] > widest) {
            widest = lons[i + 1] - lons[i];
            bb.westDeg = lons[i + 1];
            bb.eastDeg = lons[i];
        }
    }
    if (aroundPole) {
        bb.westDeg = -180.0;
        bb.eastDeg = 180.0;
    }
    bb.centerEcef = 0.5 * (lo + hi);
    bb.radius = 0.0;
    for (const Knot& k : knots_) bb.radius = std::max(bb.radius, glm::length(k.p - bb.centerEcef));
    boxLo_ = lo;
    boxHi_ = hi;
    aroundPole_ = aroundPole;
}

void Trajectory::extendBounds(std::size_t i) {
    // What computeBounds() does for every knot, for the one appended: the same box, latitudes
    // and heights; longitudes widened on the side that needs less; the sphere kept around every
    // knot so far (its centre moves with the box: conservative).
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    TrajectoryBounds& bb = bounds_;
    const glm::dvec3& p = knots_[i].p;
    const globe::Geodetic g = e.toGeodetic(p);
    const double lon = globe::wrapLongitude(g.lonDeg);
    bb.southDeg = std::min(bb.southDeg, g.latDeg);
    bb.northDeg = std::max(bb.northDeg, g.latDeg);
    bb.minHeight = std::min(bb.minHeight, g.height);
    bb.maxHeight = std::max(bb.maxHeight, g.height);
    if (i > 0) {
        const glm::dvec3& a = knots_[i - 1].p;
        if (widenPastPole(bb, a, e.toGeodetic(a).lonDeg, p, g.lonDeg)) aroundPole_ = true;
    }
    if (aroundPole_) {
        bb.westDeg = -180.0;
        bb.eastDeg = 180.0;
    } else if (!(bb.westDeg == -180.0 && bb.eastDeg == 180.0)) {
        auto around = [](double d) { return d - 360.0 * std::floor(d / 360.0); };   // [0, 360)
        const double width = around(bb.eastDeg - bb.westDeg);
        if (around(lon - bb.westDeg) > width) {   // outside: grow towards it the shorter way
            const double east = around(lon - bb.eastDeg), west = around(bb.westDeg - lon);
            if (width + std::min(east, west) >= 360.0) bb.westDeg = -180.0, bb.eastDeg = 180.0;
            else if (east <= west) bb.eastDeg = lon;
            else bb.westDeg = lon;
        }
    }
    const glm::dvec3 oldCenter = bb.centerEcef;
    boxLo_ = glm::min(boxLo_, p);
    boxHi_ = glm::max(boxHi_, p);
    bb.centerEcef = 0.5 * (boxLo_ + boxHi_);
    bb.radius = std::max(bb.radius + glm::length(bb.centerEcef - oldCenter), glm::length(p - bb.centerEcef));
}

}  // namespace orbis::motion
