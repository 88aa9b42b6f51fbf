// Stiff cases: the antimeridian, a flight over the pole, one sample, two samples at one place,
// times at the int64 extremes, and the sample checks (order, repeats, NaN, ranges).
#include "formats/motion/Attitude.h"
#include "MotionTestUtil.h"

#include <gtest/gtest.h>

#include <limits>

namespace orbis::motion {
namespace {

using namespace test;

TrajectorySample at(TimeNs t, double lon, double lat, double alt = 0.0) {
    TrajectorySample s;
    s.t = t;
    s.lonDeg = lon;
    s.latDeg = lat;
    s.alt = alt;
    return s;
}

TEST(TrajectoryStiff, AntimeridianIsCrossedTheShortWay) {
    std::vector<TrajectorySample> samples;
    // 179.75, 179.85, 179.95, -179.95, -179.85: 0.1 degrees apart, every 10 s.
    for (int i = 0; i < 5; ++i) samples.push_back(at(atSeconds(10.0 * i), globe::wrapLongitude(179.75 + 0.1 * i), 10.0, 5000.0));
    auto tr = Trajectory::create(samples);
    ASSERT_TRUE(tr.ok()) << tr.message();
    for (double s = 0.0; s <= 40.0; s += 1.0) {
        const auto p = tr->pose(atSeconds(s));
        // Going the long way round would put the midpoints near longitude 0.
        EXPECT_GT(std::abs(p->lonDeg), 179.7) << s;
        // Heading from the motion along the parallel: exact inside, O(a^2) = 2e-4 degrees off at
        // the ends' one-sided tangents.
        EXPECT_NEAR(headingDiff(p->headingDeg, 90.0), 0.0, 1e-3) << s;
        EXPECT_NEAR(p->height, 5000.0, 0.01) << s;   // Catmull-Rom: the 2.4 m sagitta of 11 km chords is gone
    }
    const double mid = tr->pose(atSeconds(25.0))->lonDeg;   // halfway from 179.95 to -179.95
    EXPECT_NEAR(std::abs(mid), 180.0, 1e-6);
    const TrajectoryBounds& b = tr->bounds();
    EXPECT_TRUE(b.crossesAntimeridian());
    EXPECT_NEAR(b.westDeg, 179.75, 1e-9);
    EXPECT_NEAR(b.eastDeg, -179.85, 1e-9);
}

TEST(TrajectoryStiff, OverThePoleTheVehicleDoesNotSpin) {
    // Straight over the north pole: the local heading flips from 0 to 180 at the pole, the
    // vehicle itself does not turn.
    const Circle c = meridianOverPole();
    const double pole = 0.5 * 3.14159265358979323846 * c.radius / c.speed;
    std::vector<TrajectorySample> samples = c.samples(pole - 95.0, pole + 95.0, 10.0);   // no sample on the pole itself
    auto tr = Trajectory::create(samples);
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_NEAR(*tr->samples().front().headingDeg, 0.0, 1e-6);
    EXPECT_NEAR(*tr->samples().back().headingDeg, 180.0, 1e-6);
    // Inside the first and last segments (whose end tangents are one-sided parabolas, off the
    // circle's by O(a^2) = 1e-5 degrees), forward is the circle's direction to rounding.
    glm::dquat previous = tr->pose(atSeconds(pole - 85.0))->orientation;
    for (double s = pole - 85.0; s <= pole + 85.0; s += 0.5) {
        const auto p = tr->pose(atSeconds(s));
        EXPECT_LT(angleDeg(p->forward(), glm::normalize(c.velocityAt(s))), 1e-6) << s - pole;
        // The path turns by 0.5 s * 250 m/s / 6400 km = 0.00112 degrees per step; so may the body.
        EXPECT_LT(angleBetweenDeg(previous, p->orientation), 0.0012) << s - pole;
        // Wings level: the right wing stays horizontal (perpendicular to the circle's plane).
        EXPECT_LT(std::abs(glm::dot(p->right(), glm::dvec3(1.0, 0.0, 0.0))), 1e-9);
        previous = p->orientation;
    }
    const TrajectoryBounds& b = tr->bounds();
    EXPECT_GT(b.northDeg, 89.99);   // the pole between two samples counts
    EXPECT_EQ(b.westDeg, -180.0);
    EXPECT_EQ(b.eastDeg, 180.0);
}

TEST(TrajectoryStiff, SampleExactlyOnThePole) {
    std::vector<TrajectorySample> samples{at(atSeconds(0.0), 0.0, 89.99), at(atSeconds(10.0), 0.0, 90.0), at(atSeconds(20.0), 180.0, 89.99)};
    auto tr = Trajectory::create(samples);
    ASSERT_TRUE(tr.ok()) << tr.message();
    for (double s = 0.0; s <= 20.0; s += 0.5) {
        const auto p = tr->pose(atSeconds(s));
        EXPECT_TRUE(std::isfinite(p->headingDeg) && std::isfinite(p->pitchDeg) && std::isfinite(p->rollDeg));
        EXPECT_NEAR(glm::length(p->orientation), 1.0, 1e-12);
        EXPECT_GT(p->latDeg, 89.98);
    }
}

TEST(TrajectoryStiff, OneSampleIsAConstantPose) {
    TrajectorySample s = at(atSeconds(0.0), 7.0, 46.0, 500.0);
    s.headingDeg = 45.0;
    for (Extrapolation e : {Extrapolation::Hold, Extrapolation::Linear}) {
        TrajectoryOptions o;
        o.before = o.after = e;
        auto tr = Trajectory::create({s}, o);
        ASSERT_TRUE(tr.ok()) << tr.message();
        for (TimeNs t : {std::numeric_limits<TimeNs>::min(), atSeconds(-1.0), atSeconds(0.0), atSeconds(1e6), std::numeric_limits<TimeNs>::max()}) {
            const auto p = tr->pose(t);
            ASSERT_TRUE(p);
            EXPECT_NEAR(p->lonDeg, 7.0, 1e-12);
            EXPECT_NEAR(p->height, 500.0, 1e-6);
            EXPECT_NEAR(p->headingDeg, 45.0, 1e-9);
            EXPECT_EQ(glm::length(p->velocity), 0.0);
        }
        EXPECT_EQ(tr->timeRange().begin, tr->timeRange().end);
        EXPECT_EQ(tr->pathEcef(atSeconds(-5.0), atSeconds(5.0), 10).size(), 1u);
    }
    TrajectoryOptions hide;
    hide.before = hide.after = Extrapolation::Hide;
    auto tr = Trajectory::create({s}, hide);
    EXPECT_TRUE(tr->pose(atSeconds(0.0)).has_value());
    EXPECT_FALSE(tr->pose(atSeconds(0.0) + 1).has_value());
}

TEST(TrajectoryStiff, TwoSamplesAtOnePlace) {
    auto tr = Trajectory::create({at(atSeconds(0.0), 7.0, 46.0, 10.0), at(atSeconds(10.0), 7.0, 46.0, 10.0)});
    ASSERT_TRUE(tr.ok()) << tr.message();
    const glm::dvec3 p0 = globe::Ellipsoid::wgs84().toEcef(7.0, 46.0, 10.0);
    for (double s = -5.0; s <= 15.0; s += 0.5) {
        const auto p = tr->pose(atSeconds(s));
        EXPECT_LT(glm::length(p->ecef - p0), 1e-8);
        EXPECT_NEAR(headingDiff(p->headingDeg, 0.0), 0.0, 1e-9);   // no motion at all: heading 0, pitch 0
        EXPECT_NEAR(p->pitchDeg, 0.0, 1e-9);
    }
}

TEST(TrajectoryStiff, TimesAtTheInt64Extremes) {
    const TimeNs lo = std::numeric_limits<TimeNs>::min(), hi = std::numeric_limits<TimeNs>::max();
    EXPECT_NEAR(secondsBetween(hi, lo), 18446744073.709551615, 1e-5);
    EXPECT_NEAR(secondsBetween(lo, hi), -18446744073.709551615, 1e-5);
    EXPECT_EQ(secondsBetween(atSeconds(1.5), atSeconds(0.0)), 1.5);
    for (Interpolation mode : {Interpolation::Linear, Interpolation::CatmullRom}) {
        TrajectoryOptions o;
        o.interpolation = mode;
        o.before = o.after = Extrapolation::Linear;
        auto tr = Trajectory::create({at(lo + 1, 7.0, 46.0), at(0, 7.001, 46.0), at(hi - 1, 7.002, 46.0)}, o);
        ASSERT_TRUE(tr.ok()) << tr.message();
        for (TimeNs t : {lo, lo + 1, TimeNs(-1), TimeNs(0), TimeNs(1), hi - 1, hi}) {
            const auto p = tr->pose(t);
            ASSERT_TRUE(p);
            EXPECT_TRUE(std::isfinite(p->ecef.x) && std::isfinite(p->ecef.y) && std::isfinite(p->ecef.z)) << t;
            EXPECT_TRUE(std::isfinite(p->headingDeg)) << t;
        }
        EXPECT_NEAR(tr->pose(0)->lonDeg, 7.001, 1e-12);
        EXPECT_NEAR(tr->pose(hi - 1)->lonDeg, 7.002, 1e-12);
    }
}

TEST(TrajectoryStiff, ManySamplesFindTheirSegment) {
    // 100 000 samples 1 ms apart along the equator: the binary search lands on the right one.
    const Circle c = equator();
    const std::vector<TrajectorySample> samples = c.samples(0.0, 99.999, 0.001);
    ASSERT_EQ(samples.size(), 100000u);
    auto tr = Trajectory::create(samples);
    ASSERT_TRUE(tr.ok()) << tr.message();
    for (double s : {0.0, 0.0005, 12.3456, 50.0, 99.9985, 99.999}) EXPECT_LT(glm::length(tr->pose(atSeconds(s))->ecef - c.at(s)), 1e-6) << s;
}

// ------------------------------------------------------------------------- sample checks

TEST(TrajectoryChecks, NoSamplesIsAnError) {
    auto tr = Trajectory::create({}, {}, "empty.csv");
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "empty.csv: no samples")) << tr.message();
}

TEST(TrajectoryChecks, TimeGoingBackNamesBothLines) {
    std::vector<TrajectorySample> s{at(atSeconds(0.0), 7, 46), at(atSeconds(10.0), 7, 46.1), at(atSeconds(5.0), 7, 46.2)};
    for (std::size_t i = 0; i < s.size(); ++i) s[i].line = 11 + i;
    auto tr = Trajectory::create(s, {}, "f.csv");
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "f.csv: line 13: time 2023-11-14T22:13:25.000Z is before line 12's")) << tr.message();
    s[2].line = 0;   // without lines: sample numbers
    auto numbered = Trajectory::create(s, {}, "f.csv");
    EXPECT_TRUE(contains(numbered.message(), "sample 3")) << numbered.message();
}

TEST(TrajectoryChecks, RepeatedTimeIsAnErrorOrDroppedWhenAsked) {
    std::vector<TrajectorySample> s{at(atSeconds(0.0), 7, 46), at(atSeconds(10.0), 7, 46.1), at(atSeconds(10.0), 7, 46.2),
                                    at(atSeconds(20.0), 7, 46.3)};
    for (std::size_t i = 0; i < s.size(); ++i) s[i].line = 2 + i;
    auto tr = Trajectory::create(s, {}, "f.csv");
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "f.csv: line 4: time 2023-11-14T22:13:30.000Z is the same as line 3's")) << tr.message();
    TrajectoryOptions o;
    o.duplicateTimes = DuplicateTimes::KeepFirst;
    auto kept = Trajectory::create(s, o, "f.csv");
    ASSERT_TRUE(kept.ok()) << kept.message();
    EXPECT_EQ(kept->sampleCount(), 3u);
    EXPECT_EQ(kept->droppedDuplicates(), 1u);
    EXPECT_NEAR(kept->pose(atSeconds(10.0))->latDeg, 46.1, 1e-9);   // the first one kept
    EXPECT_EQ(kept->warnings().size(), 1u);
}

TEST(TrajectoryChecks, NonFinitePositionNamesTheLine) {
    std::vector<TrajectorySample> s{at(atSeconds(0.0), 7, 46), at(atSeconds(1.0), 7, std::nan(""))};
    s[1].line = 9;
    auto tr = Trajectory::create(s, {}, "f.csv");
    ASSERT_FALSE(tr.ok());
    EXPECT_TRUE(contains(tr.message(), "f.csv: line 9: the position")) << tr.message();
}

TEST(TrajectoryChecks, OutOfRangeLatitudeAndLongitude) {
    auto lat = Trajectory::create({at(0, 7, 90.5)}, {}, "f");
    EXPECT_TRUE(contains(lat.message(), "latitude 90.5 is outside -90..90")) << lat.message();
    auto lon = Trajectory::create({at(0, 400, 0)}, {}, "f");
    EXPECT_TRUE(contains(lon.message(), "longitude 400 is outside")) << lon.message();
    auto wrapped = Trajectory::create({at(0, 350, 0)});   // 350 = -10
    ASSERT_TRUE(wrapped.ok());
    EXPECT_NEAR(wrapped->pose(0)->lonDeg, -10.0, 1e-12);
}

TEST(TrajectoryChecks, NonFiniteAngleIsAbsent) {
    std::vector<TrajectorySample> s = equator().samples(0.0, 20.0, 10.0);
    for (TrajectorySample& x : s) {
        x.headingDeg = std::numeric_limits<double>::quiet_NaN();
        x.rollDeg = std::numeric_limits<double>::infinity();
    }
    auto tr = Trajectory::create(s);
    ASSERT_TRUE(tr.ok()) << tr.message();
    EXPECT_NEAR(tr->pose(atSeconds(5.0))->headingDeg, 90.0, 1e-6);   // derived from the motion
    EXPECT_EQ(*tr->samples()[0].rollDeg, 0.0);
}

}  // namespace
}  // namespace orbis::motion
