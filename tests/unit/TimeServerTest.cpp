#include "engine/scene/TimeServer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

using namespace orbis;
using orbis::scene::Subscription;
using orbis::scene::TimeEvent;
using orbis::scene::TimeServer;

namespace {

constexpr TimeNs kSecond = kNsPerSecond;

// A server over [0 s, 10 s], at `now`, with every event recorded.
struct Fixture {
    TimeServer time;
    std::vector<TimeEvent> events;
    Subscription sub;

    explicit Fixture(TimeNs now = 0) {
        EXPECT_TRUE(time.setRange(0, 10 * kSecond).ok());
        time.seek(now);
        sub = time.observe([this](const TimeEvent& e) { events.push_back(e); });
        time.advance(0.0);  // consume the initial jump so tests start from a quiet state
        events.clear();
    }
};

}  // namespace

TEST(TimeServer, StartsPausedAtZeroWithRateOneAndNoLoop) {
    TimeServer time;
    EXPECT_EQ(time.start(), 0);
    EXPECT_EQ(time.end(), 0);
    EXPECT_EQ(time.now(), 0);
    EXPECT_FALSE(time.playing());
    EXPECT_EQ(time.rate(), 1.0);
    EXPECT_FALSE(time.loop());
}

TEST(TimeServer, SetRangeRejectsStartAfterEndAndChangesNothing) {
    TimeServer time;
    ASSERT_TRUE(time.setRange(0, 10 * kSecond).ok());
    auto r = time.setRange(5 * kSecond, 1 * kSecond);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.message().find("is after its end"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("1970-01-01T00:00:05.000Z"), std::string::npos) << r.message();
    EXPECT_EQ(time.start(), 0);
    EXPECT_EQ(time.end(), 10 * kSecond);
}

TEST(TimeServer, SetRangeClampsNowIntoTheRange) {
    TimeServer time;
    ASSERT_TRUE(time.setRange(5 * kSecond, 8 * kSecond).ok());
    EXPECT_EQ(time.now(), 5 * kSecond);
    time.seek(7 * kSecond);
    ASSERT_TRUE(time.setRange(0, 6 * kSecond).ok());
    EXPECT_EQ(time.now(), 6 * kSecond);
}

TEST(TimeServer, SeekClampsIntoTheRange) {
    Fixture f;
    f.time.seek(-3 * kSecond);
    EXPECT_EQ(f.time.now(), 0);
    f.time.seek(30 * kSecond);
    EXPECT_EQ(f.time.now(), 10 * kSecond);
    f.time.seek(4 * kSecond);
    EXPECT_EQ(f.time.now(), 4 * kSecond);
}

TEST(TimeServer, StepSeeksRelativeToNowAndClamps) {
    Fixture f(5 * kSecond);
    f.time.step(2 * kSecond);
    EXPECT_EQ(f.time.now(), 7 * kSecond);
    f.time.step(-1 * kSecond);
    EXPECT_EQ(f.time.now(), 6 * kSecond);
    f.time.step(std::numeric_limits<TimeNs>::max());  // saturates instead of overflowing
    EXPECT_EQ(f.time.now(), 10 * kSecond);
    f.time.advance(0.0);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_TRUE(f.events[0].jumped);
}

TEST(TimeServer, AdvanceWhilePausedHoldsTimeButStillNotifies) {
    Fixture f(2 * kSecond);
    f.time.advance(0.5);
    EXPECT_EQ(f.time.now(), 2 * kSecond);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_EQ(f.events[0].now, 2 * kSecond);
    EXPECT_FALSE(f.events[0].playing);
    EXPECT_FALSE(f.events[0].jumped);
}

TEST(TimeServer, AdvanceMovesByRateTimesWallSeconds) {
    Fixture f(1 * kSecond);
    f.time.setRate(2.0);
    f.time.play();
    f.time.advance(0.5);
    EXPECT_EQ(f.time.now(), 2 * kSecond);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_EQ(f.events[0].now, 2 * kSecond);
    EXPECT_EQ(f.events[0].previous, 1 * kSecond);
    EXPECT_TRUE(f.events[0].playing);
    EXPECT_FALSE(f.events[0].jumped);
    EXPECT_EQ(f.events[0].rate, 2.0);
}

TEST(TimeServer, ManySmallAdvancesDoNotAccumulateRoundingError) {
    // 1/60 s is 16666666.67 ns: rounding each frame alone would drift by 0.33 ns per frame,
    // 200 ns over 600 frames. Carrying the remainder keeps the total within 1 ns (the final
    // rounding of the carried fraction).
    TimeServer time;
    ASSERT_TRUE(time.setRange(0, 100 * kSecond).ok());
    time.play();
    for (int i = 0; i < 600; ++i) time.advance(1.0 / 60.0);
    EXPECT_NEAR(static_cast<double>(time.now()), 10.0 * kSecond, 1.0);
}

TEST(TimeServer, NegativeRatePlaysBackwards) {
    Fixture f(5 * kSecond);
    f.time.setRate(-1.5);
    f.time.play();
    f.time.advance(2.0);
    EXPECT_EQ(f.time.now(), 2 * kSecond);
    EXPECT_TRUE(f.time.playing());
}

TEST(TimeServer, ZeroRateHoldsTimeWhilePlaying) {
    Fixture f(5 * kSecond);
    f.time.setRate(0.0);
    f.time.play();
    f.time.advance(3.0);
    EXPECT_EQ(f.time.now(), 5 * kSecond);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_TRUE(f.events[0].playing);
}

TEST(TimeServer, NonFiniteRateIsIgnored) {
    TimeServer time;
    time.setRate(3.0);
    time.setRate(std::nan(""));
    time.setRate(std::numeric_limits<double>::infinity());
    EXPECT_EQ(time.rate(), 3.0);
}

TEST(TimeServer, NonPositiveOrNanWallTimeDoesNotMoveTime) {
    Fixture f(5 * kSecond);
    f.time.play();
    f.time.advance(-1.0);
    f.time.advance(std::nan(""));
    EXPECT_EQ(f.time.now(), 5 * kSecond);
    EXPECT_EQ(f.events.size(), 2u);
}

TEST(TimeServer, EndWithoutLoopClampsAndPauses) {
    Fixture f(9 * kSecond);
    f.time.play();
    f.time.advance(5.0);
    EXPECT_EQ(f.time.now(), 10 * kSecond);
    EXPECT_FALSE(f.time.playing());
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_FALSE(f.events[0].playing);
    EXPECT_FALSE(f.events[0].jumped);  // it played continuously up to the end
}

TEST(TimeServer, StartWithNegativeRateWithoutLoopClampsAndPauses) {
    Fixture f(1 * kSecond);
    f.time.setRate(-1.0);
    f.time.play();
    f.time.advance(5.0);
    EXPECT_EQ(f.time.now(), 0);
    EXPECT_FALSE(f.time.playing());
}

TEST(TimeServer, LoopWrapsToStartAndFlagsJump) {
    Fixture f(9 * kSecond);
    f.time.setLoop(true);
    f.time.play();
    f.time.advance(2.0);
    // The 1 s overshoot past the end carries over, so the loop keeps a constant rate.
    EXPECT_EQ(f.time.now(), 1 * kSecond);
    EXPECT_TRUE(f.time.playing());
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_TRUE(f.events[0].jumped);
    EXPECT_EQ(f.events[0].previous, 9 * kSecond);
    f.time.advance(1.0);
    EXPECT_FALSE(f.events[1].jumped);
}

TEST(TimeServer, LoopReachesTheEndExactlyBeforeWrapping) {
    Fixture f(9 * kSecond);
    f.time.setLoop(true);
    f.time.play();
    f.time.advance(1.0);
    EXPECT_EQ(f.time.now(), 10 * kSecond);
    EXPECT_TRUE(f.time.playing());
    EXPECT_FALSE(f.events.back().jumped);
}

TEST(TimeServer, LoopWrapsToEndWhenPlayingBackwards) {
    Fixture f(1 * kSecond);
    f.time.setLoop(true);
    f.time.setRate(-1.0);
    f.time.play();
    f.time.advance(3.0);
    EXPECT_EQ(f.time.now(), 8 * kSecond);
    EXPECT_TRUE(f.events.back().jumped);
}

TEST(TimeServer, LoopOverSeveralPeriodsInOneFrameWrapsModuloTheRange) {
    Fixture f(0);
    f.time.setLoop(true);
    f.time.setRate(25.0);
    f.time.play();
    f.time.advance(1.0);  // 25 s in a 10 s loop
    EXPECT_EQ(f.time.now(), 5 * kSecond);
}

TEST(TimeServer, HugeRateSaturatesInsteadOfOverflowing) {
    TimeServer time;
    ASSERT_TRUE(time.setRange(std::numeric_limits<TimeNs>::min(), std::numeric_limits<TimeNs>::max()).ok());
    time.setRate(1e12);
    time.play();
    time.advance(1e9);
    EXPECT_EQ(time.now(), std::numeric_limits<TimeNs>::max());
    EXPECT_FALSE(time.playing());
}

TEST(TimeServer, EachAdvanceNotifiesEveryObserverExactlyOnce) {
    TimeServer time;
    int a = 0, b = 0;
    auto subA = time.observe([&](const TimeEvent&) { ++a; });
    auto subB = time.observe([&](const TimeEvent&) { ++b; });
    for (int i = 0; i < 3; ++i) time.advance(0.1);
    EXPECT_EQ(a, 3);
    EXPECT_EQ(b, 3);
}

TEST(TimeServer, SeveralSeeksBetweenAdvancesGiveOneJumpedEvent) {
    Fixture f(0);
    f.time.seek(3 * kSecond);
    f.time.seek(4 * kSecond);
    f.time.step(1 * kSecond);
    EXPECT_TRUE(f.events.empty());  // setters never notify
    f.time.advance(0.0);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_TRUE(f.events[0].jumped);
    EXPECT_EQ(f.events[0].previous, 0);
    EXPECT_EQ(f.events[0].now, 5 * kSecond);
    f.time.advance(0.0);
    ASSERT_EQ(f.events.size(), 2u);
    EXPECT_FALSE(f.events[1].jumped);
}

TEST(TimeServer, SetRangeFlagsJump) {
    Fixture f(0);
    ASSERT_TRUE(f.time.setRange(0, 20 * kSecond).ok());
    f.time.advance(0.0);
    ASSERT_EQ(f.events.size(), 1u);
    EXPECT_TRUE(f.events[0].jumped);
}

TEST(TimeServer, FirstEventReportsAJumpWithPreviousEqualToNow) {
    TimeServer time;
    ASSERT_TRUE(time.setRange(2 * kSecond, 4 * kSecond).ok());
    std::vector<TimeEvent> events;
    auto sub = time.observe([&](const TimeEvent& e) { events.push_back(e); });
    time.advance(0.0);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_TRUE(events[0].jumped);
    EXPECT_EQ(events[0].previous, 2 * kSecond);
    EXPECT_EQ(events[0].now, 2 * kSecond);
}

TEST(TimeServer, PreviousIsNowOfTheLastEvent) {
    Fixture f(1 * kSecond);
    f.time.play();
    f.time.advance(1.0);
    f.time.advance(2.0);
    ASSERT_EQ(f.events.size(), 2u);
    EXPECT_EQ(f.events[1].previous, f.events[0].now);
    EXPECT_EQ(f.events[1].now, 4 * kSecond);
}

TEST(TimeServer, DestroyingTheSubscriptionUnsubscribes) {
    TimeServer time;
    int calls = 0;
    {
        Subscription sub = time.observe([&](const TimeEvent&) { ++calls; });
        EXPECT_TRUE(sub.active());
        time.advance(0.0);
    }
    time.advance(0.0);
    EXPECT_EQ(calls, 1);
}

TEST(TimeServer, SubscriptionIsMoveOnlyAndMovingKeepsOneRegistration) {
    static_assert(!std::is_copy_constructible_v<Subscription>);
    static_assert(!std::is_copy_assignable_v<Subscription>);
    static_assert(std::is_nothrow_move_constructible_v<Subscription>);
    TimeServer time;
    int calls = 0;
    Subscription a = time.observe([&](const TimeEvent&) { ++calls; });
    Subscription b = std::move(a);
    EXPECT_FALSE(a.active());
    EXPECT_TRUE(b.active());
    time.advance(0.0);
    EXPECT_EQ(calls, 1);
    Subscription c;
    c = std::move(b);
    time.advance(0.0);
    EXPECT_EQ(calls, 2);
    c.reset();
    time.advance(0.0);
    EXPECT_EQ(calls, 2);
}

TEST(TimeServer, MoveAssigningOverASubscriptionUnsubscribesTheOldOne) {
    TimeServer time;
    int first = 0, second = 0;
    Subscription sub = time.observe([&](const TimeEvent&) { ++first; });
    sub = time.observe([&](const TimeEvent&) { ++second; });
    time.advance(0.0);
    EXPECT_EQ(first, 0);
    EXPECT_EQ(second, 1);
}

TEST(TimeServer, SubscriptionOutlivingTheServerIsSafe) {
    Subscription sub;
    {
        TimeServer time;
        sub = time.observe([](const TimeEvent&) {});
        EXPECT_TRUE(sub.active());
    }
    EXPECT_FALSE(sub.active());
    sub.reset();  // must not touch the destroyed server
    EXPECT_FALSE(sub.active());
}

TEST(TimeServer, ObserverMayUnsubscribeItselfDuringNotification) {
    TimeServer time;
    int selfCalls = 0, otherCalls = 0;
    Subscription self;
    self = time.observe([&](const TimeEvent&) {
        ++selfCalls;
        self.reset();  // destroys nothing while running: the function stays alive until the end
    });
    auto other = time.observe([&](const TimeEvent&) { ++otherCalls; });
    time.advance(0.0);
    time.advance(0.0);
    EXPECT_EQ(selfCalls, 1);
    EXPECT_EQ(otherCalls, 2);
}

TEST(TimeServer, ObserverRemovedByAnotherDuringNotificationIsNotCalledAgain) {
    TimeServer time;
    int laterCalls = 0;
    Subscription later;
    auto first = time.observe([&](const TimeEvent&) { later.reset(); });
    later = time.observe([&](const TimeEvent&) { ++laterCalls; });
    time.advance(0.0);
    EXPECT_EQ(laterCalls, 0);
}

TEST(TimeServer, ObserverAddedDuringNotificationIsCalledFromTheNextAdvance) {
    TimeServer time;
    int addedCalls = 0;
    std::vector<Subscription> added;
    auto adder = time.observe([&](const TimeEvent&) {
        // Many, so that the list must grow while the notification walks it.
        for (int i = 0; i < 50; ++i) added.push_back(time.observe([&](const TimeEvent&) { ++addedCalls; }));
    });
    time.advance(0.0);
    EXPECT_EQ(addedCalls, 0);
    adder.reset();
    time.advance(0.0);
    EXPECT_EQ(addedCalls, 50);
}

TEST(TimeServer, EmptyObserverGivesInactiveSubscription) {
    TimeServer time;
    Subscription sub = time.observe(nullptr);
    EXPECT_FALSE(sub.active());
    time.advance(0.0);  // must not call an empty function
    SUCCEED();
}
