// Building a Trajectory (Trajectory.h): checking samples, and appending them one by one, which
// is also how create() builds it, so a trajectory read at once and one grown fix by fix from a
// live feed are the same. Each append touches the last three knots: their tangents (the end
// knot's turns into an interior one), their derived attitudes, and the last two segments'
// rotations.
#include "formats/motion/Trajectory.h"

#include "base/Log.h"
#include "globe/Ellipsoid.h"
#include "formats/motion/Attitude.h"

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

Result<Trajectory> Trajectory::create(std::vector<TrajectorySample> samples, const TrajectoryOptions& options,
                                      const std::string& name) {
    if (samples.empty()) return makeError(name + ": no samples (a trajectory needs at least one time-stamped position)");
    Trajectory tr;
    tr.name_ = name;
    tr.options_ = options;
    tr.interpolation_ = options.interpolation;
    tr.before_ = options.before;
    tr.after_ = options.after;
    tr.samples_.reserve(samples.size());
    tr.times_.reserve(samples.size());
    tr.knots_.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        TrajectorySample s = samples[i];
        bool drop = false;
        if (auto r = tr.check(s, i, drop); !r) return r.error();
        if (drop) continue;
        tr.appendChecked(s);
        tr.lastIndex_ = i;
    }
    if (tr.droppedDuplicates_ > 0)
        tr.warnings_.push_back(name + ": " + std::to_string(tr.droppedDuplicates_) +
                               " samples dropped: their time repeats the sample before");
    // A still start waiting for a move that never came: its samples show the angles its poses use.
    for (std::size_t i = 0; i < tr.lazyEnd_; ++i) tr.setAttitude(i, tr.lazyHeadingDeg_, tr.lazyPitchDeg_);
    tr.computeBounds();
    return tr;
}

Result<void> Trajectory::append(TrajectorySample sample) {
    bool drop = false;
    const std::size_t index = lastIndex_ + 1;
    if (auto r = check(sample, index, drop); !r) return r;
    if (drop) return {};
    appendChecked(sample);
    lastIndex_ = index;
    extendBounds(knots_.size() - 1);
    return {};
}

void Trajectory::keepLast(std::size_t count) {
    count = std::max<std::size_t>(count, 1);
    if (count >= samples_.size()) return;
    std::vector<TrajectorySample> kept(samples_.end() - std::ptrdiff_t(count), samples_.end());
    for (std::size_t i = 0; i < kept.size(); ++i) {   // the angles as given, not as derived
        const uint8_t d = derived_[samples_.size() - count + i];
        if (d & 1) kept[i].headingDeg.reset();
        if (d & 2) kept[i].pitchDeg.reset();
        if (d & 4) kept[i].rollDeg.reset();
    }
    auto rebuilt = create(std::move(kept), options_, name_);   // checked once already: cannot fail
    if (!rebuilt) return;
    std::vector<std::string> warnings = std::move(warnings_);
    const std::size_t dropped = droppedDuplicates_;
    *this = std::move(*rebuilt);
    warnings_ = std::move(warnings);
    droppedDuplicates_ = dropped;
}

Result<void> Trajectory::check(TrajectorySample& s, std::size_t index, bool& drop) {
    drop = false;
    if (!std::isfinite(s.lonDeg) || !std::isfinite(s.latDeg) || !std::isfinite(s.alt))
        return makeError(where(name_, s, index) + ": the position (lon " + number(s.lonDeg) + ", lat " + number(s.latDeg) +
                         ", alt " + number(s.alt) + ") is not a number");
    if (s.latDeg < -90.0 || s.latDeg > 90.0)
        return makeError(where(name_, s, index) + ": latitude " + number(s.latDeg) + " is outside -90..90");
    if (s.lonDeg < -360.0 || s.lonDeg > 360.0)
        return makeError(where(name_, s, index) + ": longitude " + number(s.lonDeg) + " is outside -360..360");
    for (std::optional<double>* a : {&s.headingDeg, &s.pitchDeg, &s.rollDeg})
        if (*a && !std::isfinite(**a)) a->reset();
    if (!samples_.empty()) {
        const TrajectorySample& prev = samples_.back();
        if (s.t < prev.t)
            return makeError(where(name_, s, index) + ": time " + timeText(s.t) + " is before " + lineOf(prev, lastIndex_) + "'s (" +
                             timeText(prev.t) + "): the samples must be in time order");
        if (s.t == prev.t) {
            if (options_.duplicateTimes == DuplicateTimes::KeepFirst) {
                ++droppedDuplicates_;
                drop = true;
                return {};
            }
            return makeError(where(name_, s, index) + ": time " + timeText(s.t) + " is the same as " + lineOf(prev, lastIndex_) +
                             "'s: each sample needs its own time (or drop repeats: duplicate times \"keep-first\")");
        }
    }
    if (options_.clampToGround) {
        s.altRef = AltitudeRef::Ground;
        s.alt = 0.0;
    }
    return {};
}

void Trajectory::appendChecked(const TrajectorySample& s) {
    const std::size_t j = knots_.size();
    samples_.push_back(s);
    derived_.push_back(uint8_t((s.headingDeg ? 0 : 1) | (s.pitchDeg ? 0 : 2) | (s.rollDeg ? 0 : 4)));
    if (derived_.back()) ++derivedAttitudes_;
    double height = s.alt;
    if (s.altRef == AltitudeRef::MeanSeaLevel) {
        if (options_.geoid) {
            const double geoid = options_.geoid(s.lonDeg, s.latDeg);
            if (std::isfinite(geoid)) height += geoid;   // a grid without this place: the ellipsoid
        } else if (!warnedGeoid_) {
            warnedGeoid_ = true;
            warnings_.push_back(name_ + ": altitudes above mean sea level are taken as heights above the ellipsoid "
                                        "(no geoid model): they may be off by up to about 100 m");
            log::warn(warnings_.back());
        }
    }
    times_.push_back(s.t);
    Knot k;
    k.p = globe::Ellipsoid::wgs84().toEcef(s.lonDeg, s.latDeg, height);
    k.groundWeight = s.altRef == AltitudeRef::Ground ? 1.0 : 0.0;
    knots_.push_back(k);
    lastMoving_.push_back(-1);
    if (j > 0) {
        Knot& a = knots_[j - 1];
        a.seconds = secondsBetween(times_[j], times_[j - 1]);
        a.chordVelocity = (knots_[j].p - a.p) / a.seconds;
    }
    // Knot j - 1 turns from the end into an interior knot, j is the new end; with three knots
    // the start's tangent sees its second chord too.
    for (std::size_t i = j >= 2 ? j - 2 : 0; i <= j; ++i) {
        knots_[i].m = tangentAt(i);
        setMotion(i);
        lastMoving_[i] = knots_[i].moving ? std::ptrdiff_t(i) : (i > 0 ? lastMoving_[i - 1] : -1);
    }
    if (j < 4) {
        recomputeAttitudes();
    } else if (firstMoving_ < 0 && knots_[j - 1].moving) {
        // The first interior knot that moves: the still start before it takes its direction (once).
        recomputeAttitudes();
    } else if (firstMoving_ >= 0) {
        for (std::size_t i = j - 1; i <= j; ++i) {
            const Knot& from = knots_[i].moving ? knots_[i] : knots_[std::size_t(lastMoving_[i - 1])];
            setAttitude(i, from.motionHeadingDeg, from.motionPitchDeg);
        }
        linkRotation(j - 2);
        linkRotation(j - 1);
    } else {
        // Nothing moves but maybe the end: the still start waits (knotQ() computes it).
        lazyEnd_ = j;
        lazyHeadingDeg_ = knots_[j].moving ? knots_[j].motionHeadingDeg : 0.0;
        lazyPitchDeg_ = knots_[j].moving ? knots_[j].motionPitchDeg : 0.0;
        setAttitude(j, lazyHeadingDeg_, lazyPitchDeg_);
    }
    updateEndVelocities();
}

void Trajectory::recomputeAttitudes() {
    const std::size_t n = knots_.size();
    firstMoving_ = -1;
    for (std::size_t i = 0; i + 1 < n; ++i)
        if (knots_[i].moving) {
            firstMoving_ = std::ptrdiff_t(i);
            break;
        }
    if (firstMoving_ >= 0) {
        lazyEnd_ = 0;
        const Knot& first = knots_[std::size_t(firstMoving_)];
        for (std::size_t i = 0; i < n; ++i) {
            const Knot& from = knots_[i].moving || lastMoving_[i] < 0 ? (knots_[i].moving ? knots_[i] : first)
                                                                        : knots_[std::size_t(lastMoving_[i])];
            setAttitude(i, from.motionHeadingDeg, from.motionPitchDeg);
        }
        for (std::size_t i = 0; i + 1 < n; ++i) linkRotation(i);
    } else {
        lazyEnd_ = n - 1;
        lazyHeadingDeg_ = knots_[n - 1].moving ? knots_[n - 1].motionHeadingDeg : 0.0;
        lazyPitchDeg_ = knots_[n - 1].moving ? knots_[n - 1].motionPitchDeg : 0.0;
        for (std::size_t i = 0; i < n; ++i) setAttitude(i, lazyHeadingDeg_, lazyPitchDeg_);
    }
}

glm::dvec3 Trajectory::tangentAt(std::size_t i) const {
    const std::size_t n = knots_.size();
    if (n < 2) return glm::dvec3(0.0);
    // d(k) = chord velocity of segment k, h(k) its duration.
    auto d = [&](std::size_t k) { return knots_[k].chordVelocity; };
    auto h = [&](std::size_t k) { return knots_[k].seconds; };
    auto limit = [](glm::dvec3 m, double maxSpeed) {
        const double speed = glm::length(m);
        return speed > maxSpeed ? m * (maxSpeed / speed) : m;
    };
    if (n == 2) return d(0);
    if (i == 0) {   // the parabola through the first three samples
        const glm::dvec3 m0 = ((2.0 * h(0) + h(1)) * d(0) - h(0) * d(1)) / (h(0) + h(1));
        return limit(m0, 2.0 * glm::length(d(0)));
    }
    if (i == n - 1) {   // through the last three
        const std::size_t l = n - 2;
        const glm::dvec3 mn = ((2.0 * h(l) + h(l - 1)) * d(l) - h(l) * d(l - 1)) / (h(l) + h(l - 1));
        return limit(mn, 2.0 * glm::length(d(l)));
    }
    // The derivative of the parabola through three samples at their real times.
    const glm::dvec3 m = (h(i) * d(i - 1) + h(i - 1) * d(i)) / (h(i - 1) + h(i));
    return limit(m, 2.0 * std::min(glm::length(d(i - 1)), glm::length(d(i))));
}

void Trajectory::setMotion(std::size_t i) {
    Knot& k = knots_[i];
    k.moving = glm::length(k.m) >= kMinSpeed;
    if (!k.moving) return;
    const HeadingPitchRoll a = headingPitchFromDirection(k.m, samples_[i].lonDeg, samples_[i].latDeg);
    k.motionHeadingDeg = a.headingDeg;
    k.motionPitchDeg = a.pitchDeg;
}

glm::dquat Trajectory::attitudeQ(std::size_t i, double headingDeg, double pitchDeg) const {
    const TrajectorySample& s = samples_[i];
    const uint8_t d = derived_[i];
    return bodyToEcef(s.lonDeg, s.latDeg, (d & 1) ? headingDeg : *s.headingDeg, (d & 2) ? pitchDeg : *s.pitchDeg,
                      (d & 4) ? 0.0 : *s.rollDeg);
}

void Trajectory::setAttitude(std::size_t i, double headingDeg, double pitchDeg) {
    knots_[i].q = attitudeQ(i, headingDeg, pitchDeg);
    TrajectorySample& s = samples_[i];
    const uint8_t d = derived_[i];
    if (d & 1) s.headingDeg = headingDeg;
    if (d & 2) s.pitchDeg = pitchDeg;
    if (d & 4) s.rollDeg = 0.0;
}

void Trajectory::linkRotation(std::size_t i) {
    Knot& k = knots_[i];
    const glm::dquat& b = knots_[i + 1].q;
    k.sign = glm::dot(k.q, b) < 0.0 ? -1.0 : 1.0;
    const glm::dquat diff = k.sign * b - k.q, sum = k.sign * b + k.q;
    k.angle = 2.0 * std::atan2(std::sqrt(glm::dot(diff, diff)), std::sqrt(glm::dot(sum, sum)));
    k.invSinAngle = k.angle < 1e-9 ? 0.0 : 1.0 / std::sin(k.angle);
}

void Trajectory::updateEndVelocities() {
    const std::size_t n = knots_.size();
    if (n < 2) return;
    const bool linear = interpolation_ == Interpolation::Linear;
    startVelocity_ = linear ? knots_.front().chordVelocity : knots_.front().m;
    endVelocity_ = linear ? knots_[n - 2].chordVelocity : knots_.back().m;
}

}  // namespace orbis::motion
