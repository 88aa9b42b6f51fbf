#include "layers/vector/LabelPlacement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

using orbis::vector::LabelCandidate;
using orbis::vector::LabelPlacementOptions;
using orbis::vector::LabelPlacer;

namespace {

LabelCandidate box(uint64_t id, double priority, double x, double y, double w = 40.0, double h = 12.0) {
    return {.id = id, .priority = priority, .min = {x, y}, .max = {x + w, y + h}};
}

bool overlap(const LabelCandidate& a, const LabelCandidate& b) {
    return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y;
}

std::set<uint64_t> ids(const std::vector<LabelCandidate>& c, const std::vector<uint32_t>& placed) {
    std::set<uint64_t> out;
    for (uint32_t i : placed) out.insert(c[i].id);
    return out;
}

std::vector<LabelCandidate> randomLabels(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-50.0, 1970.0), y(-20.0, 1100.0), w(20.0, 160.0), h(10.0, 24.0), p(0.0, 100.0);
    std::vector<LabelCandidate> out;
    for (size_t i = 0; i < n; ++i) out.push_back(box(i, p(rng), x(rng), y(rng), w(rng), h(rng)));
    return out;
}

const LabelPlacementOptions kHd{.screen = {1920.0, 1080.0}, .marginPx = 4.0};

}  // namespace

TEST(LabelPlacement, NoTwoPlacedLabelsOverlapAndAllAreOnScreen) {
    LabelPlacer placer;
    for (uint32_t seed = 1; seed <= 3; ++seed) {
        const auto labels = randomLabels(10000, seed);
        const auto placed = placer.place(labels, kHd);
        ASSERT_GT(placed.size(), 100u);   // the screen holds a few hundred of these
        for (size_t a = 0; a < placed.size(); ++a) {
            const LabelCandidate& la = labels[placed[a]];
            EXPECT_TRUE(la.min.x >= 0 && la.min.y >= 0 && la.max.x <= 1920 && la.max.y <= 1080) << la.id;
            for (size_t b = a + 1; b < placed.size(); ++b)
                ASSERT_FALSE(overlap(la, labels[placed[b]])) << la.id << " and " << labels[placed[b]].id;
        }
        EXPECT_EQ(placer.stats().placed, placed.size());
        EXPECT_EQ(placer.stats().placed + placer.stats().rejectedOverlap + placer.stats().rejectedOffscreen, 10000u);
    }
}

TEST(LabelPlacement, EveryRejectedLabelIsBlockedByAPlacedOneOrTheScreenEdge) {
    // Greedy and maximal: a label left out overlaps a placed label (grown by the margin, as a new
    // label must be) or does not fit inside the screen's margin.
    LabelPlacer placer;
    const auto labels = randomLabels(3000, 7);
    const auto placed = placer.place(labels, kHd);
    std::vector<char> isPlaced(labels.size());
    for (uint32_t i : placed) isPlaced[i] = 1;
    for (size_t i = 0; i < labels.size(); ++i) {
        if (isPlaced[i]) continue;
        LabelCandidate grown = labels[i];
        grown.min -= kHd.marginPx;
        grown.max += kHd.marginPx;
        const bool offscreen = grown.min.x < 0 || grown.min.y < 0 || grown.max.x > 1920 || grown.max.y > 1080;
        const bool blocked = std::any_of(placed.begin(), placed.end(), [&](uint32_t p) { return overlap(grown, labels[p]); });
        EXPECT_TRUE(offscreen || blocked) << "label " << labels[i].id << " was left out with room to spare";
    }
}

TEST(LabelPlacement, TheMoreImportantOfTwoOverlappingLabelsWins) {
    LabelPlacer placer;
    const std::vector<LabelCandidate> labels = {box(1, 5.0, 100, 100), box(2, 9.0, 120, 104)};
    EXPECT_EQ(ids(labels, placer.place(labels, kHd)), std::set<uint64_t>{2});
}

TEST(LabelPlacement, TheChoiceDoesNotDependOnTheCandidatesOrder) {
    auto labels = randomLabels(2000, 11);
    LabelPlacer a, b;
    const auto first = ids(labels, a.place(labels, kHd));
    std::reverse(labels.begin(), labels.end());
    EXPECT_EQ(ids(labels, b.place(labels, kHd)), first);
}

TEST(LabelPlacement, ANewLabelDisplacesAShownOneOnlyBeyondThePriorityHysteresis) {
    LabelPlacementOptions options = kHd;
    options.priorityHysteresis = 1.0;
    LabelPlacer placer;
    std::vector<LabelCandidate> labels = {box(1, 5.0, 100, 100)};
    ASSERT_EQ(ids(labels, placer.place(labels, options)), std::set<uint64_t>{1});
    labels.push_back(box(2, 5.9, 120, 104));   // more important, but within the hysteresis
    EXPECT_EQ(ids(labels, placer.place(labels, options)), std::set<uint64_t>{1});
    labels[1].priority = 6.1;                    // beyond it
    EXPECT_EQ(ids(labels, placer.place(labels, options)), std::set<uint64_t>{2});
}

TEST(LabelPlacement, ASlowPanChangesALabelOnlyAtTheEdgeAndItsMargin) {
    // A label moves right 0.25 px a frame across the screen's right edge and back: it goes when
    // its box leaves the screen, and comes back only when the box is the margin inside again.
    LabelPlacer placer;
    const double w = 40.0;
    std::vector<LabelCandidate> labels = {box(1, 1.0, 1920.0 - w - 10.0, 500.0, w)};
    placer.place(labels, kHd);
    int changes = 0;
    bool shown = true;
    double goneAt = 0.0, backAt = 0.0;
    const auto step = [&](double dx) {
        labels[0].min.x += dx;
        labels[0].max.x += dx;
        const bool now = !placer.place(labels, kHd).empty();
        if (now != shown) {
            ++changes;
            (now ? backAt : goneAt) = labels[0].max.x;
        }
        shown = now;
    };
    for (int i = 0; i < 80; ++i) step(0.25);    // out to max.x = 1930
    for (int i = 0; i < 80; ++i) step(-0.25);   // back to 1910
    EXPECT_EQ(changes, 2);
    EXPECT_DOUBLE_EQ(goneAt, 1920.25);                    // the first position past the edge
    EXPECT_DOUBLE_EQ(backAt, 1920.0 - kHd.marginPx);      // the first position the margin inside
    // Near the edge, jitter smaller than the margin never toggles it: shown at 1918-1919...
    changes = 0;
    for (int i = 0; i < 36; ++i) step(0.25);   // max.x 1910 -> 1919
    for (int i = 0; i < 20; ++i) step(i % 2 ? 1.0 : -1.0);
    EXPECT_EQ(changes, 0);
    EXPECT_TRUE(shown);
    // ... and hidden at 1917-1921, once it has gone.
    step(2.0);   // 1921
    EXPECT_FALSE(shown);
    for (int i = 0; i < 20; ++i) step(i % 2 ? 4.0 : -4.0);
    EXPECT_EQ(changes, 1);
}

TEST(LabelPlacement, TwoLabelsPassingEachOtherToggleOnlyAtContactAndAtTheMarginGap) {
    // A (important, still) and B (moving left into A, then back): B goes when the boxes overlap
    // and returns when the gap is the margin again.
    LabelPlacer placer;
    std::vector<LabelCandidate> labels = {box(1, 10.0, 500, 500), box(2, 1.0, 560, 500)};   // A ends at 540
    ASSERT_EQ(placer.place(labels, kHd).size(), 2u);
    std::vector<double> toggles;
    bool bShown = true;
    for (int i = 0; i < 120; ++i) {
        const double dx = i < 60 ? -0.5 : 0.5;
        labels[1].min.x += dx;
        labels[1].max.x += dx;
        const bool now = ids(labels, placer.place(labels, kHd)).count(2) > 0;
        if (now != bShown) toggles.push_back(labels[1].min.x);
        bShown = now;
    }
    ASSERT_EQ(toggles.size(), 2u);
    EXPECT_DOUBLE_EQ(toggles[0], 539.5);                  // the first overlap
    EXPECT_DOUBLE_EQ(toggles[1], 540.0 + kHd.marginPx);   // a margin's gap again
}

TEST(LabelPlacement, BadCandidatesAreLeftOutWithoutHarm) {
    LabelPlacer placer;
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    std::vector<LabelCandidate> labels = {
        box(1, 1.0, 100, 100),
        {.id = 2, .priority = 1.0, .min = {nan, 10}, .max = {50, 20}},
        {.id = 3, .priority = 1.0, .min = {10, 10}, .max = {inf, 20}},
        {.id = 4, .priority = 1.0, .min = {60, 10}, .max = {50, 20}},   // inverted
        {.id = 5, .priority = nan, .min = {300, 300}, .max = {340, 312}},
        box(1, 2.0, 800, 800),   // a repeated id: placed once
    };
    const auto placed = placer.place(labels, kHd);
    EXPECT_EQ(ids(labels, placed), (std::set<uint64_t>{1, 5}));
    EXPECT_EQ(placed.size(), 2u);
    // No screen: nothing placed, and last frame forgotten.
    EXPECT_TRUE(placer.place(labels, LabelPlacementOptions{}).empty());
}

TEST(LabelPlacement, EqualPrioritiesAreBrokenByIdWhateverTheOrder) {
    // Every label has the same priority and each overlaps the next: the lower id wins each pair.
    std::vector<LabelCandidate> labels;
    for (uint64_t id = 0; id < 200; ++id) labels.push_back(box(1000 - id, 7.0, 10.0 + 30.0 * double(id), 100.0));
    LabelPlacer a, b;
    const auto first = ids(labels, a.place(labels, kHd));
    std::mt19937 rng(5);
    std::shuffle(labels.begin(), labels.end(), rng);
    EXPECT_EQ(ids(labels, b.place(labels, kHd)), first);
    // Boxes 40 wide every 30 px, ids falling to the right: the rightmost box that fits with its
    // margin (x = 1870, id 938) goes first, then every other box leftwards: 32 labels.
    EXPECT_EQ(first.size(), 32u);
    for (uint64_t id : first) EXPECT_EQ((id - 938) % 2, 0u) << id;
    EXPECT_EQ(*first.begin(), 938u);
}

TEST(LabelPlacement, AVisibilityTestIsAskedOnlyOfLabelsWithRoomAndAHiddenOneTakesNone) {
    // Three labels in a row, each overlapping the next; the best one is hidden (the terrain):
    // it takes no room, so the second, which it would have blocked, is placed, and the third,
    // blocked by the second, is never asked.
    const std::vector<LabelCandidate> labels = {box(1, 3.0, 100, 100), box(2, 2.0, 120, 100), box(3, 1.0, 150, 100)};
    std::vector<uint32_t> asked;
    LabelPlacer placer;
    const auto placed = placer.place(labels, kHd, [&](uint32_t i) {
        asked.push_back(i);
        return labels[i].id != 1;
    });
    EXPECT_EQ(ids(labels, placed), (std::set<uint64_t>{2}));
    EXPECT_EQ(asked, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(placer.stats().rejectedHidden, 1u);
    EXPECT_EQ(placer.stats().rejectedOverlap, 1u);
}
