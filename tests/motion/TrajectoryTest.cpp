// Trajectory interpolation against analytic paths: a great circle at constant speed (linear:
// the chord's sagitta; Catmull-Rom: far below it), a constant-rate roll, constant
// acceleration at uneven times; extrapolation at both ends; ground and mean-sea-level
// altitudes; the path line and bounds.
#include "formats/motion/Attitude.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

#include <random>

namespace orbis::motion {
namespace {

using namespace test;

Trajectory make(std::vector<TrajectorySample> samples, TrajectoryOptions o = {}) {
    auto t = Trajectory::create(std::move(samples), o, "test");
    EXPECT_TRUE(t.ok()) << t.message();
    return std::move(*t);
}

TrajectoryOptions with(Interpolation i) {
    TrajectoryOptions o;
    o.interpolation = i;
    return o;
}

// ------------------------------------------------------------------------- a great circle

/// Largest position error at the segments' midpoints (and the sagitta they should have).
struct CircleErrors {
    double maxError = 0.0, minError = 1e300, sagitta = 0.0;
};

CircleErrors circleErrors(const Circle& c, Interpolation mode, double from, double to) {
    const double step = 10.0;   // samples every 10 s
    const Trajectory tr = make(c.samples(from, to, step), with(mode));
    CircleErrors e;
    e.sagitta = c.radius * (1.0 - std::cos(0.5 * c.angleAt(step)));
    // Inner segments only: the ends use one-sided tangents (checked separately).
    for (double s = from + step + 0.5 * step; s < to - step; s += step) {
        const auto p = tr.pose(atSeconds(s));
        const double err = glm::length(p->ecef - c.at(s));
        e.maxError = std::max(e.maxError, err);
        e.minError = std::min(e.minError, err);
    }
    return e;
}

TEST(TrajectoryCircle, LinearMidpointsMissByTheSagittaAlongTheEquator) {
    const CircleErrors e = circleErrors(equator(), Interpolation::Linear, 0.0, 600.0);
    // 2.5 km chords on a radius of 6378 km: sagitta R (1 - cos(a/2)) = 0.1225 m. The chord's
    // midpoint lies exactly that far inside; ECEF round trips through lon/lat/height cost ~1e-9 m.
    EXPECT_NEAR(e.sagitta, 0.1225, 0.0005);
    EXPECT_NEAR(e.maxError, e.sagitta, 1e-6);
    EXPECT_NEAR(e.minError, e.sagitta, 1e-6);
}

TEST(TrajectoryCircle, LinearMidpointsMissByTheSagittaOverThePole) {
    // 300 s either side of the pole: samples at lat up to 90 exactly (t = pole) and back down.
    const Circle c = meridianOverPole();
    const double pole = 0.5 * 3.14159265358979323846 * c.radius / c.speed;
    const CircleErrors e = circleErrors(c, Interpolation::Linear, pole - 300.0, pole + 300.0);
    EXPECT_NEAR(e.maxError, e.sagitta, 1e-6);
    EXPECT_NEAR(e.minError, e.sagitta, 1e-6);
}

TEST(TrajectoryCircle, CatmullRomIsFarCloserThanTheChord) {
    for (const Circle& c : {equator(), meridianOverPole()}) {
        const double pole = 0.5 * 3.14159265358979323846 * c.radius / c.speed;
        const CircleErrors e = circleErrors(c, Interpolation::CatmullRom, pole - 300.0, pole + 300.0);
        // A cubic with parabola tangents on a circle: error of order R a^4 (a = 3.9e-4 rad):
        // ~1e-7 m. 1e-5 m is 1/10 000 of the sagitta.
        EXPECT_LT(e.maxError, 1e-5) << "sagitta " << e.sagitta;
    }
}

TEST(TrajectoryCircle, CatmullRomVelocityIsTheCirclesAtEveryTime) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 600.0, 10.0));
    for (double s = 10.0; s <= 590.0; s += 3.7) {
        const auto p = tr.pose(atSeconds(s));
        // The spline's derivative: O(v a^2) = 250 m/s * 1.5e-7 off at worst.
        EXPECT_LT(glm::length(p->velocity - c.velocityAt(s)), 1e-3) << s;
    }
}

TEST(TrajectoryCircle, LinearVelocityIsTheChords) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 100.0, 10.0), with(Interpolation::Linear));
    const auto p = tr.pose(atSeconds(23.0));
    const glm::dvec3 chord = (c.at(30.0) - c.at(20.0)) / 10.0;
    EXPECT_LT(glm::length(p->velocity - chord), 1e-9);
}

TEST(TrajectoryCircle, CatmullRomIsC1AtTheSamples) {
    const Trajectory tr = make(equator().samples(0.0, 100.0, 10.0));
    for (double knot : {10.0, 20.0, 50.0, 90.0}) {
        const auto before = tr.pose(atSeconds(knot) - 1), at = tr.pose(atSeconds(knot)), after = tr.pose(atSeconds(knot) + 1);
        EXPECT_LT(glm::length(before->ecef - at->ecef), 1e-6);   // 1 ns at 250 m/s: 2.5e-7 m
        EXPECT_LT(glm::length(after->ecef - at->ecef), 1e-6);
        EXPECT_LT(glm::length(before->velocity - after->velocity), 1e-6);
    }
}

TEST(TrajectoryCircle, ExactAtTheSamples) {
    const Circle c = equator();
    const std::vector<TrajectorySample> samples = c.samples(0.0, 100.0, 10.0);
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        const Trajectory tr = make(samples, with(mode));
        for (const TrajectorySample& s : samples) EXPECT_LT(glm::length(tr.pose(s.t)->ecef - c.at(toSeconds(s.t - kT0))), 1e-8);
    }
}

TEST(TrajectoryCircle, DerivedAttitudeLooksAlongTheMotion) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 600.0, 10.0));
    EXPECT_EQ(tr.derivedAttitudes(), tr.sampleCount());
    for (double s = 5.0; s < 600.0; s += 10.0) {
        const auto p = tr.pose(atSeconds(s));
        EXPECT_NEAR(p->headingDeg, 90.0, 1e-6);
        EXPECT_NEAR(p->pitchDeg, 0.0, 1e-6);
        EXPECT_NEAR(p->rollDeg, 0.0, 1e-6);
        EXPECT_LT(angleDeg(p->forward(), glm::normalize(c.velocityAt(s))), 1e-6);
    }
}

// ------------------------------------------------------------------------- attitude

TEST(TrajectoryAttitude, ConstantRateRollIsExactAtEveryFraction) {
    // Roll = 36 deg/s * t, sampled every second, at a fixed place: every pair of samples is a
    // 36-degree turn about the same body axis, which slerp splits exactly.
    std::vector<TrajectorySample> samples;
    for (int i = 0; i <= 20; ++i) {
        TrajectorySample s;
        s.t = atSeconds(i);
        s.lonDeg = 10.0;
        s.latDeg = 50.0;
        s.alt = 1000.0;
        s.headingDeg = 30.0;
        s.pitchDeg = 0.0;
        s.rollDeg = std::remainder(36.0 * i, 360.0);
        samples.push_back(s);
    }
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        const Trajectory tr = make(samples, with(mode));
        for (double s = 0.0; s <= 20.0; s += 0.125) {
            const auto p = tr.pose(atSeconds(s));
            // Quaternion products and atan2: ~1e-14 rad; 1e-9 degrees leaves room, and a
            // wrong interpolation (nlerp, the long way) is off by degrees.
            EXPECT_NEAR(headingDiff(p->rollDeg, 36.0 * s), 0.0, 1e-9) << s;
            EXPECT_NEAR(p->headingDeg, 30.0, 1e-9);
            EXPECT_NEAR(p->pitchDeg, 0.0, 1e-9);
        }
    }
}

TEST(TrajectoryAttitude, ConstantHeadingStaysConstantAlongALongEastWestPath) {
    // 1 000 km east along the parallel 45 N (12.7 degrees of longitude), heading 90 given at
    // every sample: the local frame turns by the meridian convergence between samples, and the
    // interpolated heading must follow it.
    std::vector<TrajectorySample> samples;
    const double step = 10.0, speed = 250.0;
    const double radius = glm::length(glm::dvec2(globe::Ellipsoid::wgs84().toEcef(0.0, 45.0, 3000.0)));   // of the parallel
    for (int i = 0; i <= 400; ++i) {
        TrajectorySample s;
        s.t = atSeconds(i * step);
        s.lonDeg = glm::degrees(speed * i * step / radius);
        s.latDeg = 45.0;
        s.alt = 3000.0;
        s.headingDeg = 90.0;
        s.pitchDeg = 0.0;
        s.rollDeg = 0.0;
        samples.push_back(s);
    }
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        const Trajectory tr = make(samples, with(mode));
        double worstHeading = 0.0, worstPitch = 0.0;
        for (double s = 0.0; s <= 4000.0; s += 2.5) {
            const auto p = tr.pose(atSeconds(s));
            worstHeading = std::max(worstHeading, std::abs(headingDiff(p->headingDeg, 90.0)));
            worstPitch = std::max(worstPitch, std::abs(p->pitchDeg));
        }
        // O(a^3) of the segment's angle between the chord's and the rotation's longitude, and
        // the Catmull-Rom point's offset along the path: ~1e-9 deg. 1e-6 keeps a wide margin;
        // interpolating in the frame of the segment's first sample (one that does not turn
        // along it) is off by up to the meridian convergence, 0.022 deg.
        EXPECT_LT(worstHeading, 1e-6) << toString(mode);
        EXPECT_LT(worstPitch, 1e-6) << toString(mode);
    }
}

TEST(TrajectoryAttitude, Heading350To10PassesThroughNorth) {
    std::vector<TrajectorySample> samples(2);
    for (int i = 0; i < 2; ++i) {
        samples[i].t = atSeconds(i);
        samples[i].lonDeg = 7.0;
        samples[i].latDeg = 46.0;
        samples[i].headingDeg = i == 0 ? 350.0 : 10.0;
        samples[i].pitchDeg = 0.0;
        samples[i].rollDeg = 0.0;
    }
    const Trajectory tr = make(samples);
    for (double f : {0.25, 0.5, 0.75}) EXPECT_NEAR(headingDiff(tr.pose(atSeconds(f))->headingDeg, 350.0 + 20.0 * f), 0.0, 1e-9);
    EXPECT_NEAR(headingDiff(tr.pose(atSeconds(0.5))->headingDeg, 0.0), 0.0, 1e-9);
}

TEST(TrajectoryAttitude, GivenAnglesAreKeptMissingOnesDerived) {
    // Heading given (a crab angle: nose 20 degrees off the course), pitch and roll derived.
    std::vector<TrajectorySample> samples = equator().samples(0.0, 100.0, 10.0);
    for (TrajectorySample& s : samples) s.headingDeg = 110.0;
    const Trajectory tr = make(samples);
    const auto p = tr.pose(atSeconds(55.0));
    EXPECT_NEAR(p->headingDeg, 110.0, 1e-6);
    EXPECT_NEAR(p->pitchDeg, 0.0, 1e-6);
    EXPECT_NEAR(p->rollDeg, 0.0, 1e-6);
    ASSERT_TRUE(tr.samples()[3].pitchDeg.has_value());   // the derived angles are filled in the samples kept
    EXPECT_NEAR(*tr.samples()[3].pitchDeg, 0.0, 1e-6);
    EXPECT_EQ(*tr.samples()[3].headingDeg, 110.0);
    EXPECT_EQ(tr.derivedAttitudes(), samples.size());
}

TEST(TrajectoryAttitude, StillStartTakesTheFirstMotionsDirection) {
    // Parked for 20 s, then off to the north: the parked samples face north (the first motion).
    std::vector<TrajectorySample> samples;
    for (int i = 0; i < 6; ++i) {
        TrajectorySample s;
        s.t = atSeconds(10.0 * i);
        s.lonDeg = 7.0;
        s.latDeg = 46.0 + (i < 3 ? 0.0 : 0.001 * (i - 2));
        samples.push_back(s);
    }
    const Trajectory tr = make(samples);
    for (double s : {0.0, 5.0, 15.0}) EXPECT_NEAR(headingDiff(tr.pose(atSeconds(s))->headingDeg, 0.0), 0.0, 1e-6) << s;
}

// ------------------------------------------------------------------------- spline shape

TEST(TrajectorySpline, ReproducesConstantAccelerationAtUnevenTimes) {
    // p(t) = p0 + v t + a t^2 / 2 in ECEF: the parabola tangents are exact for it, and a cubic
    // Hermite with exact tangents reproduces a quadratic, whatever the spacing.
    const glm::dvec3 p0 = globe::Ellipsoid::wgs84().toEcef(7.0, 46.0, 500.0);
    const glm::dvec3 v(30.0, -20.0, 10.0), a(0.5, 0.25, -0.1);
    auto at = [&](double t) { return p0 + v * t + 0.5 * a * t * t; };
    std::vector<TrajectorySample> samples;
    const double times[] = {0.0, 0.7, 1.0, 3.5, 3.6, 8.0, 8.25, 9.0, 15.0};
    for (double t : times) samples.push_back(sampleAt(atSeconds(t), at(t)));
    const Trajectory tr = make(samples);
    for (double t = 0.0; t <= 15.0; t += 0.05) {
        const auto p = tr.pose(atSeconds(t));
        // ECEF -> geodetic -> ECEF round trips of the samples: ~1e-9 m.
        EXPECT_LT(glm::length(p->ecef - at(t)), 1e-6) << t;
        EXPECT_LT(glm::length(p->velocity - (v + a * t)), 1e-6) << t;
    }
}

TEST(TrajectorySpline, HugeGapDoesNotOvershoot) {
    // 10 samples at 250 m/s a second apart, then 1 km more in 11.6 days. Unlimited tangents
    // (250 m/s over 1e6 s) would swing the curve ~37 000 km out; limited ones keep it within
    // the gap's own length of its chord.
    std::vector<TrajectorySample> samples = equator().samples(0.0, 9.0, 1.0);
    const glm::dvec3 last = equator().at(9.0), further = equator().at(13.0);
    samples.push_back(sampleAt(atSeconds(1e6), further));
    const Trajectory tr = make(samples);
    const glm::dvec3 d = further - last;
    double worst = 0.0;
    for (double s = 9.0; s <= 1e6; s += 997.0) {
        const glm::dvec3 p = tr.pose(atSeconds(s))->ecef - last;
        const double along = std::clamp(glm::dot(p, d) / glm::dot(d, d), 0.0, 1.0);
        worst = std::max(worst, glm::length(p - along * d));
    }
    EXPECT_LT(worst, glm::length(d));
}

TEST(TrajectorySpline, StopBetweenTwoSamplesAtOnePlace) {
    // Moving, parked from 20 s to 40 s, moving again: while parked the vehicle does not creep.
    std::vector<TrajectorySample> samples;
    const Circle c = equator(10.0);
    for (double s : {0.0, 10.0, 20.0}) samples.push_back(sampleAt(atSeconds(s), c.at(s)));
    samples.push_back(sampleAt(atSeconds(40.0), c.at(20.0)));
    for (double s : {50.0, 60.0}) samples.push_back(sampleAt(atSeconds(s), c.at(s - 20.0)));
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        const Trajectory tr = make(samples, with(mode));
        for (double s = 20.0; s <= 40.0; s += 1.0) {
            const auto p = tr.pose(atSeconds(s));
            EXPECT_LT(glm::length(p->ecef - c.at(20.0)), 1e-8) << s;
            // At 40 s exactly the segment that starts there (moving again) gives the velocity.
            if (s < 40.0) {
                EXPECT_LT(glm::length(p->velocity), 1e-9) << s;
            }
        }
    }
}

// ------------------------------------------------------------------------- extrapolation

TEST(TrajectoryExtrapolation, HoldKeepsTheEndPoses) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 100.0, 10.0));
    const auto before = tr.pose(atSeconds(-50.0)), after = tr.pose(atSeconds(1e5));
    ASSERT_TRUE(before && after);
    EXPECT_TRUE(before->extrapolated);
    EXPECT_TRUE(after->extrapolated);
    EXPECT_FALSE(tr.pose(atSeconds(50.0))->extrapolated);
    EXPECT_LT(glm::length(before->ecef - c.at(0.0)), 1e-8);
    EXPECT_LT(glm::length(after->ecef - c.at(100.0)), 1e-8);
    EXPECT_EQ(glm::length(before->velocity), 0.0);
    EXPECT_EQ(glm::length(after->velocity), 0.0);
    EXPECT_NEAR(after->headingDeg, 90.0, 1e-6);
}

TEST(TrajectoryExtrapolation, LinearGoesOnWithTheEndVelocity) {
    const Circle c = equator();
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        TrajectoryOptions o = with(mode);
        o.before = o.after = Extrapolation::Linear;
        const Trajectory tr = make(c.samples(0.0, 100.0, 10.0), o);
        const auto start = tr.pose(atSeconds(0.0)), end = tr.pose(atSeconds(100.0));
        const auto before = tr.pose(atSeconds(-10.0)), after = tr.pose(atSeconds(120.0));
        EXPECT_LT(glm::length(before->ecef - (start->ecef - 10.0 * before->velocity)), 1e-8);
        EXPECT_LT(glm::length(after->ecef - (end->ecef + 20.0 * after->velocity)), 1e-8);
        EXPECT_NEAR(glm::length(after->velocity), 250.0, 0.01);   // the chord's or the tangent's speed
        EXPECT_LT(angleBetweenDeg(after->orientation, end->orientation), 1e-12);   // attitude held
        EXPECT_TRUE(after->extrapolated);
    }
}

TEST(TrajectoryExtrapolation, HideGivesNoPoseOutside) {
    TrajectoryOptions o;
    o.before = Extrapolation::Hide;
    o.after = Extrapolation::Linear;
    const Trajectory tr = make(equator().samples(0.0, 100.0, 10.0), o);
    EXPECT_FALSE(tr.pose(atSeconds(0.0) - 1).has_value());
    EXPECT_TRUE(tr.pose(atSeconds(0.0)).has_value());
    EXPECT_TRUE(tr.pose(atSeconds(100.0)).has_value());
    EXPECT_TRUE(tr.pose(atSeconds(100.0) + 1).has_value());
    o.after = Extrapolation::Hide;
    const Trajectory hidden = make(equator().samples(0.0, 100.0, 10.0), o);
    EXPECT_FALSE(hidden.pose(atSeconds(100.0) + 1).has_value());
}

// ------------------------------------------------------------------------- altitudes

std::vector<TrajectorySample> groundSamples(double agl) {
    std::vector<TrajectorySample> samples;
    for (int i = 0; i < 5; ++i) {
        TrajectorySample s;
        s.t = atSeconds(10.0 * i);
        s.lonDeg = 7.0 + 0.001 * i;
        s.latDeg = 46.0;
        s.alt = agl;
        s.altRef = AltitudeRef::Ground;
        samples.push_back(s);
    }
    return samples;
}

TEST(TrajectoryAltitude, GroundAddsTheTerrainUnderThePose) {
    const Trajectory tr = make(groundSamples(100.0));
    const GroundFn terrain = [](double lon, double) { return std::optional<double>(500.0 + 1000.0 * (lon - 7.0)); };
    const auto p = tr.pose(atSeconds(15.0), &terrain);
    EXPECT_FALSE(p->groundUnknown);
    EXPECT_NEAR(p->height, 600.0 + 1000.0 * (p->lonDeg - 7.0), 1e-6);
    const globe::Geodetic g = globe::Ellipsoid::wgs84().toGeodetic(p->ecef);
    EXPECT_NEAR(g.height, p->height, 1e-6);
    EXPECT_NEAR(g.lonDeg, p->lonDeg, 1e-12);
}

TEST(TrajectoryAltitude, UnknownTerrainCountsAsZeroAndSaysSo) {
    const Trajectory tr = make(groundSamples(100.0));
    const GroundFn nothing = [](double, double) { return std::optional<double>(); };
    for (const GroundFn* g : {&nothing, static_cast<const GroundFn*>(nullptr)}) {
        const auto p = tr.pose(atSeconds(15.0), g);
        EXPECT_TRUE(p->groundUnknown);
        EXPECT_NEAR(p->height, 100.0, 0.01);   // the chord's sagitta over 77 m: far below 1 cm
    }
}

TEST(TrajectoryAltitude, ClampToGroundPutsEverySampleOnTheTerrain) {
    std::vector<TrajectorySample> samples = groundSamples(0.0);
    for (TrajectorySample& s : samples) {
        s.alt = 3000.0;
        s.altRef = AltitudeRef::Ellipsoid;
    }
    TrajectoryOptions o;
    o.clampToGround = true;
    const Trajectory tr = make(samples, o);
    const GroundFn terrain = [](double, double) { return std::optional<double>(432.0); };
    for (double s = 0.0; s <= 40.0; s += 2.5) EXPECT_NEAR(tr.pose(atSeconds(s), &terrain)->height, 432.0, 0.01);
    EXPECT_EQ(tr.samples()[2].altRef, AltitudeRef::Ground);
}

TEST(TrajectoryAltitude, LeavingTheGroundBlendsSmoothly) {
    std::vector<TrajectorySample> samples = groundSamples(0.0);
    samples[4].altRef = AltitudeRef::Ellipsoid;   // the last sample 0 m above the ellipsoid
    samples[4].alt = 1000.0;
    TrajectoryOptions o = with(Interpolation::Linear);
    const Trajectory tr = make(samples, o);
    const GroundFn terrain = [](double, double) { return std::optional<double>(500.0); };
    // Halfway from 0 m above a 500 m terrain to 1000 m above the ellipsoid: 500 + 250 = 750 m.
    EXPECT_NEAR(tr.pose(atSeconds(35.0), &terrain)->height, 750.0, 0.01);
    EXPECT_NEAR(tr.pose(atSeconds(30.0), &terrain)->height, 500.0, 1e-6);
    EXPECT_NEAR(tr.pose(atSeconds(40.0), &terrain)->height, 1000.0, 1e-6);
}

TEST(TrajectoryAltitude, MeanSeaLevelAddsTheGeoid) {
    std::vector<TrajectorySample> samples = groundSamples(100.0);
    for (TrajectorySample& s : samples) s.altRef = AltitudeRef::MeanSeaLevel;
    TrajectoryOptions o;
    o.geoid = [](double, double) { return 47.5; };
    const Trajectory tr = make(samples, o);
    EXPECT_NEAR(tr.pose(atSeconds(20.0))->height, 147.5, 1e-6);
    EXPECT_TRUE(tr.warnings().empty());
    EXPECT_NEAR(tr.bounds().minHeight, 147.5, 1e-6);
}

TEST(TrajectoryAltitude, MeanSeaLevelWithoutAGeoidIsTakenAsEllipsoidAndWarned) {
    std::vector<TrajectorySample> samples = groundSamples(100.0);
    for (TrajectorySample& s : samples) s.altRef = AltitudeRef::MeanSeaLevel;
    const Trajectory tr = make(samples);
    EXPECT_NEAR(tr.pose(atSeconds(20.0))->height, 100.0, 1e-6);
    ASSERT_EQ(tr.warnings().size(), 1u);
    EXPECT_TRUE(contains(tr.warnings()[0], "mean sea level")) << tr.warnings()[0];
}

// ------------------------------------------------------------------------- path and bounds

TEST(TrajectoryPath, LinearPathIsTheSamplesBetweenTheEnds) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 100.0, 10.0), with(Interpolation::Linear));
    const auto path = tr.pathEcef(atSeconds(15.0), atSeconds(45.0), 1000);
    ASSERT_EQ(path.size(), 5u);   // 15, 20, 30, 40, 45
    EXPECT_LT(glm::length(path[1] - c.at(20.0)), 1e-8);
    EXPECT_LT(glm::length(path[3] - c.at(40.0)), 1e-8);
    EXPECT_LT(glm::length(path[0] - tr.pose(atSeconds(15.0))->ecef), 1e-9);
    EXPECT_LT(glm::length(path[4] - tr.pose(atSeconds(45.0))->ecef), 1e-9);
    EXPECT_EQ(tr.pathEcef(atSeconds(-100.0), atSeconds(1000.0), 1000).size(), 11u);   // clamped to the samples
    EXPECT_TRUE(tr.pathEcef(atSeconds(200.0), atSeconds(300.0), 1000).empty());
    EXPECT_TRUE(tr.pathEcef(atSeconds(50.0), atSeconds(40.0), 1000).empty());
}

TEST(TrajectoryPath, CurvesGetPointsBetweenSamplesWithinTheBudget) {
    const Circle c = equator();
    const Trajectory tr = make(c.samples(0.0, 100.0, 10.0));
    const auto path = tr.pathEcef(atSeconds(0.0), atSeconds(100.0), 1000);
    EXPECT_GT(path.size(), 11u);   // the 0.12 m sagitta is over the 5 cm tolerance
    EXPECT_LE(path.size(), 11u + 10u * 16u);
    for (const glm::dvec3& p : path) EXPECT_NEAR(glm::length(p), c.radius, 1e-5);   // on the circle
    const auto few = tr.pathEcef(atSeconds(0.0), atSeconds(100.0), 4);
    ASSERT_EQ(few.size(), 4u);
    EXPECT_LT(glm::length(few.front() - c.at(0.0)), 1e-8);
    EXPECT_LT(glm::length(few.back() - c.at(100.0)), 1e-8);
    // A single sample: one point.
    const Trajectory single = make(equator().samples(0.0, 0.0, 10.0));
    EXPECT_EQ(single.pathEcef(atSeconds(-1.0), atSeconds(1.0), 100).size(), 1u);
    // A straight path in ECEF needs no points between its samples.
    std::vector<TrajectorySample> line;
    for (int i = 0; i < 5; ++i) line.push_back(sampleAt(atSeconds(10.0 * i), c.at(0.0) + glm::dvec3(0.0, 100.0 * i, 0.0)));
    EXPECT_EQ(make(line).pathEcef(atSeconds(0.0), atSeconds(40.0), 100).size(), 5u);
}

TEST(TrajectoryPath, GroundPathFollowsTheTerrain) {
    const Trajectory tr = make(groundSamples(0.0), with(Interpolation::Linear));
    const GroundFn terrain = [](double, double) { return std::optional<double>(250.0); };
    for (const glm::dvec3& p : tr.pathEcef(atSeconds(0.0), atSeconds(40.0), 100, &terrain))
        EXPECT_NEAR(globe::Ellipsoid::wgs84().toGeodetic(p).height, 250.0, 0.01);
}

TEST(TrajectoryBoundsTest, HoldTheSamples) {
    const Trajectory tr = make(groundSamples(100.0));
    const TrajectoryBounds& b = tr.bounds();
    EXPECT_NEAR(b.westDeg, 7.0, 1e-9);
    EXPECT_NEAR(b.eastDeg, 7.004, 1e-9);
    EXPECT_NEAR(b.southDeg, 46.0, 1e-9);
    EXPECT_NEAR(b.northDeg, 46.0, 1e-9);
    EXPECT_NEAR(b.minHeight, 100.0, 1e-6);
    EXPECT_FALSE(b.crossesAntimeridian());
    for (const TrajectorySample& s : tr.samples())
        EXPECT_LE(glm::length(globe::Ellipsoid::wgs84().toEcef(s.lonDeg, s.latDeg, s.alt) - b.centerEcef), b.radius + 1e-6);
    EXPECT_NEAR(b.radius, 0.5 * 0.004 * 3.14159265358979323846 / 180.0 * 6378137.0 * std::cos(glm::radians(46.0)), 5.0);
}

TEST(TrajectoryTime, RangeAndCount) {
    const Trajectory tr = make(equator().samples(0.0, 100.0, 10.0));
    EXPECT_EQ(tr.sampleCount(), 11u);
    EXPECT_EQ(tr.timeRange().begin, atSeconds(0.0));
    EXPECT_EQ(tr.timeRange().end, atSeconds(100.0));
    EXPECT_EQ(tr.name(), "test");
}

}  // namespace
}  // namespace orbis::motion
