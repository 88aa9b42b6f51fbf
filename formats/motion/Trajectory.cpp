#include "formats/motion/Trajectory.h"

#include "base/Log.h"
#include "globe/Ellipsoid.h"
#include "formats/motion/Attitude.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace orbis::motion {

const char* toString(AltitudeRef ref) {
    switch (ref) {
        case AltitudeRef::Ellipsoid: return "ellipsoid";
        case AltitudeRef::MeanSeaLevel: return "mean sea level";
        case AltitudeRef::Ground: return "ground";
    }
    return "?";
}

const char* toString(Interpolation i) { return i == Interpolation::Linear ? "linear" : "catmull-rom"; }

const char* toString(Extrapolation e) {
    switch (e) {
        case Extrapolation::Hold: return "hold";
        case Extrapolation::Linear: return "linear";
        case Extrapolation::Hide: return "hide";
    }
    return "?";
}

double secondsBetween(TimeNs a, TimeNs b) {
    TimeNs d = 0;
    if (!__builtin_sub_overflow(a, b, &d)) {
        constexpr TimeNs kExact = TimeNs(1) << 53;   // 104 days: a double holds every ns below
        if (d > -kExact && d < kExact) return double(d) * 1e-9;
        // Whole seconds and the rest apart: exact to the nanosecond for any span a double can hold.
        return double(d / kNsPerSecond) + double(d % kNsPerSecond) * 1e-9;
    }
    return (double(a) - double(b)) * 1e-9;   // over 292 years apart: nanoseconds do not matter
}

glm::dvec3 Pose::forward() const { return forwardAxis(orientation); }
glm::dvec3 Pose::right() const { return rightAxis(orientation); }
glm::dvec3 Pose::up() const { return upAxis(orientation); }

void Trajectory::interpolate(std::size_t i, double s, glm::dvec3& p, glm::dvec3& v, glm::dquat& q, double& w) const {
    const Knot& a = knots_[i];
    const Knot& b = knots_[i + 1];
    const glm::dvec3 chord = b.p - a.p;
    if (interpolation_ == Interpolation::Linear) {
        p = a.p + s * chord;
        v = a.chordVelocity;
    } else {
        // Cubic Hermite on [0, 1] with h00 + h01 = 1 folded in (a.p + h01 * chord keeps the
        // small differences exact next to Earth-sized coordinates).
        const double hs = a.seconds, s2 = s * s, s3 = s2 * s;
        const double h01 = 3.0 * s2 - 2.0 * s3, h10 = s3 - 2.0 * s2 + s, h11 = s3 - s2;
        p = a.p + h01 * chord + (hs * h10) * a.m + (hs * h11) * b.m;
        const double d01 = 6.0 * (s - s2), d10 = 3.0 * s2 - 4.0 * s + 1.0, d11 = 3.0 * s2 - 2.0 * s;
        v = (d01 / hs) * chord + d10 * a.m + d11 * b.m;
    }
    if (i < lazyEnd_) {   // a still start whose attitude waits for the first move (TrajectoryBuild.cpp)
        q = slerpShortest(knotQ(i), knotQ(i + 1), s);
    } else {
        const glm::dquat qb = a.sign * b.q;   // b's sign on a's side: slerp the short way
        if (a.invSinAngle == 0.0) q = glm::normalize(a.q + s * (qb - a.q));   // under 1e-9 rad apart
        else q = (std::sin((1.0 - s) * a.angle) * a.invSinAngle) * a.q + (std::sin(s * a.angle) * a.invSinAngle) * qb;
    }
    w = a.groundWeight + s * (b.groundWeight - a.groundWeight);
}

void Trajectory::finish(Pose& out, const glm::dvec3& p, double groundWeight, const GroundFn* ground) const {
    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    globe::Geodetic g = e.toGeodetic(p);
    out.ecef = p;
    if (groundWeight > 0.0) {
        const std::optional<double> terrain = ground && *ground ? (*ground)(g.lonDeg, g.latDeg) : std::nullopt;
        if (terrain && std::isfinite(*terrain)) {
            // Along the geodetic normal: the same lon/lat, the height raised exactly by this.
            const double lat = glm::radians(g.latDeg), lon = glm::radians(g.lonDeg);
            const glm::dvec3 up(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
            out.onGround = groundWeight >= 1.0 && std::abs(g.height) <= kOnGroundAglMetres;   // g.height: above the ground here
            out.ecef += up * (groundWeight * *terrain);
            g.height += groundWeight * *terrain;
        } else {
            out.groundUnknown = true;
        }
    }
    out.lonDeg = g.lonDeg;
    out.latDeg = g.latDeg;
    out.height = g.height;
    const HeadingPitchRoll a = headingPitchRoll(out.orientation, g.lonDeg, g.latDeg);
    out.headingDeg = a.headingDeg;
    out.pitchDeg = a.pitchDeg;
    out.rollDeg = a.rollDeg;
}

std::size_t Trajectory::segmentOf(TimeNs t, double& s) const {
    std::size_t i = std::size_t(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
    i = std::min(i == 0 ? 0 : i - 1, times_.size() - 2);   // t_i <= t; the last time ends the last segment
    s = std::clamp(secondsBetween(t, times_[i]) / knots_[i].seconds, 0.0, 1.0);
    return i;
}

std::optional<Pose> Trajectory::pose(TimeNs t, const GroundFn* ground) const {
    Pose out;
    out.t = t;
    glm::dvec3 p(0.0);
    double w = 0.0;
    const std::size_t n = times_.size();
    if (t < times_.front() || t > times_.back()) {
        const bool before = t < times_.front();
        const Extrapolation mode = before ? before_ : after_;
        if (mode == Extrapolation::Hide) return std::nullopt;
        const Knot& k = before ? knots_.front() : knots_.back();
        p = k.p;
        out.orientation = knotQ(before ? 0 : n - 1);
        w = k.groundWeight;
        if (mode == Extrapolation::Linear) {
            out.velocity = before ? startVelocity_ : endVelocity_;
            p += out.velocity * secondsBetween(t, before ? times_.front() : times_.back());
        }
        out.extrapolated = true;
    } else if (n == 1) {
        p = knots_[0].p;
        out.orientation = knotQ(0);
        w = knots_[0].groundWeight;
    } else {
        double s = 0.0;
        const std::size_t i = segmentOf(t, s);
        interpolate(i, s, p, out.velocity, out.orientation, w);
    }
    finish(out, p, w, ground);
    return out;
}

}  // namespace orbis::motion
