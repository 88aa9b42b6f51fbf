#include "layers/motion/Trajectory.h"

#include "engine/core/Log.h"
#include "globe/Ellipsoid.h"
#include "layers/motion/Attitude.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace orbis::motion {
namespace {

/// Below this speed (m/s) a sample "does not move": its direction of motion is noise.
constexpr double kMinSpeed = 0.01;

std::string where(const std::string& name, const TrajectorySample& s, std::size_t index) {
    return name + (s.line > 0 ? ": line " + std::to_string(s.line) : ": sample " + std::to_string(index + 1));
}

std::string lineOf(const TrajectorySample& s, std::size_t index) {
    return s.line > 0 ? "line " + std::to_string(s.line) : "sample " + std::to_string(index + 1);
}

/// ISO 8601 with milliseconds, or nanoseconds when the time has more.
std::string timeText(TimeNs t) { return formatIso8601(t, t % 1'000'000 == 0 ? 3 : 9); }

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

}  // namespace

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

Result<Trajectory> Trajectory::create(std::vector<TrajectorySample> samples, const TrajectoryOptions& options,
                                      const std::string& name) {
    if (samples.empty()) return makeError(name + ": no samples (a trajectory needs at least one time-stamped position)");
    Trajectory tr;
    tr.name_ = name;
    tr.interpolation_ = options.interpolation;
    tr.before_ = options.before;
    tr.after_ = options.after;

    // Validate, drop repeated times when asked, apply clampToGround.
    std::vector<TrajectorySample>& kept = tr.samples_;
    kept.reserve(samples.size());
    std::size_t keptIndex = 0;   // index in `samples` of kept.back()
    for (std::size_t i = 0; i < samples.size(); ++i) {
        TrajectorySample s = samples[i];
        if (!std::isfinite(s.lonDeg) || !std::isfinite(s.latDeg) || !std::isfinite(s.alt))
            return makeError(where(name, s, i) + ": the position (lon " + number(s.lonDeg) + ", lat " + number(s.latDeg) +
                             ", alt " + number(s.alt) + ") is not a number");
        if (s.latDeg < -90.0 || s.latDeg > 90.0)
            return makeError(where(name, s, i) + ": latitude " + number(s.latDeg) + " is outside -90..90");
        if (s.lonDeg < -360.0 || s.lonDeg > 360.0)
            return makeError(where(name, s, i) + ": longitude " + number(s.lonDeg) + " is outside -360..360");
        for (std::optional<double>* a : {&s.headingDeg, &s.pitchDeg, &s.rollDeg})
            if (*a && !std::isfinite(**a)) a->reset();
        if (!kept.empty()) {
            const TrajectorySample& prev = kept.back();
            if (s.t < prev.t)
                return makeError(where(name, s, i) + ": time " + timeText(s.t) + " is before " + lineOf(prev, keptIndex) + "'s (" +
                                 timeText(prev.t) + "): the samples must be in time order");
            if (s.t == prev.t) {
                if (options.duplicateTimes == DuplicateTimes::KeepFirst) {
                    ++tr.droppedDuplicates_;
                    continue;
                }
                return makeError(where(name, s, i) + ": time " + timeText(s.t) + " is the same as " + lineOf(prev, keptIndex) +
                                 "'s: each sample needs its own time (or drop repeats: duplicate times \"keep-first\")");
            }
        }
        if (options.clampToGround) {
            s.altRef = AltitudeRef::Ground;
            s.alt = 0.0;
        }
        kept.push_back(s);
        keptIndex = i;
    }
    if (tr.droppedDuplicates_ > 0)
        tr.warnings_.push_back(name + ": " + std::to_string(tr.droppedDuplicates_) +
                               " samples dropped: their time repeats the sample before");

    const bool needsGeoid = std::any_of(kept.begin(), kept.end(), [](const TrajectorySample& s) {
        return s.altRef == AltitudeRef::MeanSeaLevel;
    });
    if (needsGeoid && !options.geoid) {
        tr.warnings_.push_back(name + ": altitudes above mean sea level are taken as heights above the ellipsoid "
                                      "(no geoid model): they may be off by up to about 100 m");
        log::warn(tr.warnings_.back());
    }

    const globe::Ellipsoid& e = globe::Ellipsoid::wgs84();
    const std::size_t n = kept.size();
    tr.times_.resize(n);
    tr.knots_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const TrajectorySample& s = kept[i];
        double height = s.alt;
        if (s.altRef == AltitudeRef::MeanSeaLevel && options.geoid) {
            const double geoid = options.geoid(s.lonDeg, s.latDeg);
            if (std::isfinite(geoid)) height += geoid;   // a grid without this place: the ellipsoid
        }
        tr.times_[i] = s.t;
        tr.knots_[i].p = e.toEcef(s.lonDeg, s.latDeg, height);
        tr.knots_[i].groundWeight = s.altRef == AltitudeRef::Ground ? 1.0 : 0.0;
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
        Knot& k = tr.knots_[i];
        k.seconds = secondsBetween(tr.times_[i + 1], tr.times_[i]);
        k.chordVelocity = (tr.knots_[i + 1].p - k.p) / k.seconds;
    }
    tr.computeTangents();

    tr.computeAttitudes();

    if (n >= 2) {
        const bool linear = tr.interpolation_ == Interpolation::Linear;
        tr.startVelocity_ = linear ? tr.knots_.front().chordVelocity : tr.knots_.front().m;
        tr.endVelocity_ = linear ? tr.knots_[n - 2].chordVelocity : tr.knots_.back().m;
    }
    tr.computeBounds();
    return tr;
}

void Trajectory::computeAttitudes() {
    // The angles given, the missing ones from the motion (see the header).
    const std::size_t n = knots_.size();
    std::vector<std::optional<HeadingPitchRoll>> motion(n);
    for (std::size_t i = 0; i < n; ++i)
        if (glm::length(knots_[i].m) >= kMinSpeed)
            motion[i] = headingPitchFromDirection(knots_[i].m, samples_[i].lonDeg, samples_[i].latDeg);
    std::optional<HeadingPitchRoll> last;
    for (std::size_t i = 0; i < n; ++i) {   // forward: the last moving sample
        if (motion[i]) last = motion[i];
        else motion[i] = last;
    }
    last.reset();
    for (std::size_t i = n; i-- > 0;) {     // backward: the first moving one, for a still start
        if (motion[i]) last = motion[i];
        else motion[i] = last;
    }
    for (std::size_t i = 0; i < n; ++i) {
        TrajectorySample& s = samples_[i];
        const HeadingPitchRoll derived = motion[i].value_or(HeadingPitchRoll{});
        if (!s.headingDeg || !s.pitchDeg || !s.rollDeg) ++derivedAttitudes_;
        if (!s.headingDeg) s.headingDeg = derived.headingDeg;
        if (!s.pitchDeg) s.pitchDeg = derived.pitchDeg;
        if (!s.rollDeg) s.rollDeg = 0.0;
        glm::dquat q = bodyToEcef(s.lonDeg, s.latDeg, *s.headingDeg, *s.pitchDeg, *s.rollDeg);
        if (i > 0 && glm::dot(q, knots_[i - 1].q) < 0.0) q = -q;   // one hemisphere: slerp the short way
        knots_[i].q = q;
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
        Knot& k = knots_[i];
        const glm::dquat diff = knots_[i + 1].q - k.q, sum = knots_[i + 1].q + k.q;
        k.angle = 2.0 * std::atan2(std::sqrt(glm::dot(diff, diff)), std::sqrt(glm::dot(sum, sum)));
        k.invSinAngle = k.angle < 1e-9 ? 0.0 : 1.0 / std::sin(k.angle);
    }
}

void Trajectory::computeTangents() {
    const std::size_t n = knots_.size();
    if (n < 2) return;
    // d[k] = chord velocity of segment k, h[k] its duration.
    auto d = [&](std::size_t k) { return knots_[k].chordVelocity; };
    auto h = [&](std::size_t k) { return knots_[k].seconds; };
    auto limit = [](glm::dvec3 m, double maxSpeed) {
        const double speed = glm::length(m);
        return speed > maxSpeed ? m * (maxSpeed / speed) : m;
    };
    if (n == 2) {
        knots_[0].m = knots_[1].m = d(0);
        return;
    }
    // The derivative of the parabola through three samples at their real times.
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const glm::dvec3 m = (h(i) * d(i - 1) + h(i - 1) * d(i)) / (h(i - 1) + h(i));
        knots_[i].m = limit(m, 2.0 * std::min(glm::length(d(i - 1)), glm::length(d(i))));
    }
    const glm::dvec3 m0 = ((2.0 * h(0) + h(1)) * d(0) - h(0) * d(1)) / (h(0) + h(1));
    knots_[0].m = limit(m0, 2.0 * glm::length(d(0)));
    const std::size_t l = n - 2;   // the last segment
    const glm::dvec3 mn = ((2.0 * h(l) + h(l - 1)) * d(l) - h(l) * d(l - 1)) / (h(l) + h(l - 1));
    knots_[n - 1].m = limit(mn, 2.0 * glm::length(d(l)));
}

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
    if (a.invSinAngle == 0.0) q = glm::normalize(a.q + s * (b.q - a.q));   // under 1e-9 rad apart
    else q = (std::sin((1.0 - s) * a.angle) * a.invSinAngle) * a.q + (std::sin(s * a.angle) * a.invSinAngle) * b.q;
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
        out.orientation = k.q;
        w = k.groundWeight;
        if (mode == Extrapolation::Linear) {
            out.velocity = before ? startVelocity_ : endVelocity_;
            p += out.velocity * secondsBetween(t, before ? times_.front() : times_.back());
        }
        out.extrapolated = true;
    } else if (n == 1) {
        p = knots_[0].p;
        out.orientation = knots_[0].q;
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
