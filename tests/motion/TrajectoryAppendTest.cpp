// A trajectory grown one sample at a time (Trajectory::append, the live feed's path) gives the
// poses of the one created from all the samples at once, including still starts, stops, given
// and derived angles; keepLast() is create() over the samples kept; bad appends are errors.
#include "formats/motion/Attitude.h"
#include "formats/motion/Trajectory.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

using namespace orbis;
using namespace orbis::motion;

namespace {

TrajectorySample sample(double seconds, double lon, double lat, double alt, std::optional<double> heading = std::nullopt,
                        std::optional<double> pitch = std::nullopt, std::optional<double> roll = std::nullopt) {
    TrajectorySample s;
    s.t = fromSeconds(seconds);
    s.lonDeg = lon;
    s.latDeg = lat;
    s.alt = alt;
    s.headingDeg = heading;
    s.pitchDeg = pitch;
    s.rollDeg = roll;
    return s;
}

/// A drive with everything that makes attitudes non-local: it stands still at the start (three
/// repeated fixes), moves with derived and given angles, stops twice, turns, and climbs.
std::vector<TrajectorySample> drive() {
    std::vector<TrajectorySample> v;
    double t = 0.0, lon = 9.0, lat = 46.0, alt = 500.0;
    for (int i = 0; i < 3; ++i) v.push_back(sample(t++, lon, lat, alt));   // parked
    for (int i = 0; i < 40; ++i) {
        const double turn = glm::radians(3.0 * i);
        lon += 0.0002 * std::cos(turn);
        lat += 0.0002 * std::sin(turn);
        alt += 0.5 * std::sin(0.3 * i);
        std::optional<double> heading, roll;
        if (i % 7 == 3) heading = 42.0 + i;   // now and then the feed gives a heading
        if (i % 11 == 5) roll = -3.0;
        v.push_back(sample(t, lon, lat, alt, heading, std::nullopt, roll));
        t += (i % 5 == 4) ? 2.5 : 1.0;        // uneven spacing
        if (i == 12 || i == 30) {            // a stop: the same place twice more
            v.push_back(sample(t, lon, lat, alt));
            t += 1.0;
            v.push_back(sample(t, lon, lat, alt));
            t += 1.0;
        }
    }
    return v;
}

Trajectory grown(const std::vector<TrajectorySample>& v, const TrajectoryOptions& o) {
    auto t = Trajectory::create({v.front()}, o, "grown");
    EXPECT_TRUE(t) << t.message();
    for (size_t i = 1; i < v.size(); ++i) {
        auto r = t->append(v[i]);
        EXPECT_TRUE(r) << r.message();
    }
    return std::move(*t);
}

/// Poses at every sample, between them and beyond both ends agree: positions and velocities to
/// the bit (the same arithmetic), attitudes to 1e-9 degrees (a lazy still start is computed at
/// query time, the same formula in another order).
void expectSamePoses(const Trajectory& a, const Trajectory& b) {
    ASSERT_EQ(a.sampleCount(), b.sampleCount());
    ASSERT_EQ(a.timeRange().begin, b.timeRange().begin);
    ASSERT_EQ(a.timeRange().end, b.timeRange().end);
    const double span = secondsBetween(a.timeRange().end, a.timeRange().begin);
    for (int k = -20; k <= 1020; ++k) {
        const TimeNs t = a.timeRange().begin + fromSeconds(span * k / 1000.0);
        const auto pa = a.pose(t), pb = b.pose(t);
        ASSERT_EQ(pa.has_value(), pb.has_value());
        if (!pa) continue;
        EXPECT_EQ(pa->ecef, pb->ecef) << k;
        EXPECT_EQ(pa->velocity, pb->velocity) << k;
        EXPECT_LT(angleBetweenDeg(pa->orientation, pb->orientation), 1e-9) << k;
        EXPECT_NEAR(pa->headingDeg, pb->headingDeg, 1e-9) << k;
        EXPECT_NEAR(pa->pitchDeg, pb->pitchDeg, 1e-9) << k;
    }
}

}  // namespace

TEST(TrajectoryAppend, GrownSampleBySampleEqualsCreatedAtOnce) {
    const auto v = drive();
    for (Interpolation interpolation : {Interpolation::Linear, Interpolation::CatmullRom}) {
        TrajectoryOptions o;
        o.interpolation = interpolation;
        o.before = o.after = Extrapolation::Linear;
        auto batch = Trajectory::create(v, o, "batch");
        ASSERT_TRUE(batch) << batch.message();
        expectSamePoses(*batch, grown(v, o));
        // And at every length on the way (each prefix is a trajectory of its own).
        for (size_t n : {1u, 2u, 3u, 4u, 5u, 6u, 17u, 30u}) {
            std::vector<TrajectorySample> prefix(v.begin(), v.begin() + long(n));
            expectSamePoses(*Trajectory::create(prefix, o, "batch"), grown(prefix, o));
        }
    }
}

TEST(TrajectoryAppend, JumpsBetweenRepeatedFixesMatchToo) {
    // A feed that repeats each position once (A A B B C C ...): every interior knot stands still
    // (its tangent is limited by the still chord beside it) and only the end moves, so the
    // start's derived attitude follows the end at every append: computed lazily, still equal.
    std::vector<TrajectorySample> v;
    for (int i = 0; i < 60; ++i) v.push_back(sample(i, 9.0 + 0.0003 * (i / 2), 46.0 + 0.0001 * (i / 2), 400.0));
    TrajectoryOptions o;
    o.interpolation = Interpolation::Linear;
    for (size_t n : {7u, 8u, 60u}) {
        std::vector<TrajectorySample> prefix(v.begin(), v.begin() + long(n));
        expectSamePoses(*Trajectory::create(prefix, o, "batch"), grown(prefix, o));
    }
}

TEST(TrajectoryAppend, KeepLastIsCreateOverTheSamplesKept) {
    const auto v = drive();
    TrajectoryOptions o;
    o.interpolation = Interpolation::Linear;
    Trajectory t = grown(v, o);
    t.keepLast(20);
    std::vector<TrajectorySample> last(v.end() - 20, v.end());
    auto batch = Trajectory::create(last, o, "batch");
    ASSERT_TRUE(batch);
    expectSamePoses(*batch, t);
    EXPECT_EQ(t.bounds().radius, batch->bounds().radius) << "the rebuild's bounds are exact";
    // Appending goes on after it.
    ASSERT_TRUE(t.append(sample(1000.0, 9.1, 46.1, 500.0)));
    EXPECT_EQ(t.sampleCount(), 21u);
}

TEST(TrajectoryAppend, BoundsHoldEverySample) {
    const auto v = drive();
    const Trajectory t = grown(v, {});
    const auto batch = Trajectory::create(v, {}, "batch");
    for (const auto& s : t.samples()) {
        EXPECT_GE(s.latDeg, t.bounds().southDeg);
        EXPECT_LE(s.latDeg, t.bounds().northDeg);
        EXPECT_GE(s.lonDeg, t.bounds().westDeg);
        EXPECT_LE(s.lonDeg, t.bounds().eastDeg);
    }
    EXPECT_EQ(t.bounds().southDeg, batch->bounds().southDeg);
    EXPECT_EQ(t.bounds().northDeg, batch->bounds().northDeg);
    EXPECT_EQ(t.bounds().centerEcef, batch->bounds().centerEcef);
    // Conservative: at least the exact sphere, not much more (the drive spans ~1.5 km).
    EXPECT_GE(t.bounds().radius, batch->bounds().radius);
    EXPECT_LT(t.bounds().radius, batch->bounds().radius * 1.5);
}

TEST(TrajectoryAppend, BadAppendsAreErrorsAndLeaveTheTrajectoryAlone) {
    auto t = Trajectory::create({sample(0, 9.0, 46.0, 0.0), sample(1, 9.001, 46.0, 0.0)}, {}, "live");
    ASSERT_TRUE(t);
    auto late = t->append(sample(0.5, 9.002, 46.0, 0.0));
    ASSERT_FALSE(late);
    EXPECT_NE(late.message().find("live: sample 3: time"), std::string::npos) << late.message();
    EXPECT_NE(late.message().find("must be in time order"), std::string::npos) << late.message();
    EXPECT_FALSE(t->append(sample(1, 9.002, 46.0, 0.0)));   // the same time
    auto nan = t->append(sample(2, std::nan(""), 46.0, 0.0));
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.message().find("not a number"), std::string::npos);
    EXPECT_FALSE(t->append(sample(2, 9.0, 91.0, 0.0)));
    EXPECT_EQ(t->sampleCount(), 2u);
    TrajectoryOptions keep;
    keep.duplicateTimes = DuplicateTimes::KeepFirst;
    auto k = Trajectory::create({sample(0, 9.0, 46.0, 0.0)}, keep, "live");
    ASSERT_TRUE(k->append(sample(0, 9.5, 46.0, 0.0)));   // dropped, counted
    EXPECT_EQ(k->sampleCount(), 1u);
    EXPECT_EQ(k->droppedDuplicates(), 1u);
}

TEST(TrajectoryAppend, TwentyThousandFixesOfALiveFeed) {
    // A 10 Hz feed's fixes, appended one by one (the figure printed is informational: the
    // benchmark is not timed here).
    TrajectoryOptions o;
    o.interpolation = Interpolation::Linear;
    auto t = Trajectory::create({sample(0, 9.0, 46.0, 300.0)}, o, "feed");
    ASSERT_TRUE(t);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 1; i <= 20000; ++i) ASSERT_TRUE(t->append(sample(0.1 * i, 9.0 + 1e-5 * i, 46.0 + 5e-6 * i, 300.0, 60.0)));
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ append ] %.2f us per fix over 20 000 fixes\n", us / 2e4);
    EXPECT_EQ(t->sampleCount(), 20001u);
    const auto last = t->pose(t->timeRange().end);
    ASSERT_TRUE(last);
    EXPECT_NEAR(last->lonDeg, 9.2, 1e-9);
    EXPECT_NEAR(last->headingDeg, 60.0, 1e-9);
}
