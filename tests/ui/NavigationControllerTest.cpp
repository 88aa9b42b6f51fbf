// Navigation bindings: what the mouse grabs stays under it, zoom and flights go where the
// cursor points, keyboard flight scales with height and never goes under the ground, and bad
// events change nothing.
#include "ui/input/NavigationController.h"

#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::ui {
namespace {

using globe::Pose;
using globe::Viewpoint;

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const ViewportSize kViewport{1280.0, 720.0};

NavigationController makeController(const Viewpoint& vp) {
    NavigationController c;
    c.handle(kViewport);
    c.setFovYRad(glm::radians(45.0));
    c.setViewpoint(vp);
    return c;
}

MouseButtonEvent press(MouseButton b, glm::dvec2 px, double time = 0.0, bool ctrl = false) {
    MouseButtonEvent e;
    e.button = b;
    e.pressed = true;
    e.position = px;
    e.modifiers.ctrl = ctrl;
    e.timeSeconds = time;
    return e;
}

MouseButtonEvent release(MouseButton b, glm::dvec2 px) {
    MouseButtonEvent e = press(b, px);
    e.pressed = false;
    return e;
}

KeyEvent key(Key k, bool pressed, bool ctrl = false) {
    KeyEvent e;
    e.key = k;
    e.pressed = pressed;
    e.modifiers.ctrl = ctrl;
    return e;
}

// Drags `button` from `from` to `to` in `steps` moves, as a window would report them. Each
// drag starts a second after the last, so that two drags from one place are no double click.
void dragMouse(NavigationController& c, MouseButton button, glm::dvec2 from, glm::dvec2 to, int steps = 10,
               bool ctrl = false) {
    static double clock = 0.0;
    clock += 1.0;
    c.handle(press(button, from, clock, ctrl));
    for (int i = 1; i <= steps; ++i) c.handle(MouseMoveEvent{from + (to - from) * (double(i) / steps)});
    c.handle(release(button, to));
}

double eyeHeight(const NavigationController& c) { return wgs84().toGeodetic(c.pose().position).height; }

bool finite(const Pose& p) {
    return std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
           std::isfinite(p.orientation.w) && std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) &&
           std::isfinite(p.orientation.z);
}

double angleDiff(double a, double b) { return std::abs(globe::wrapLongitude(a - b)); }

// Runs advance() at 60 Hz until nothing animates; returns the seconds it took.
double runUntilIdle(NavigationController& c, double maxSeconds = 10.0) {
    double t = 0.0;
    while (c.animating() && t < maxSeconds) {
        c.advance(1.0 / 60.0);
        t += 1.0 / 60.0;
    }
    return t;
}

// A 4000 m Gaussian mountain (sigma 0.02 degrees, ~2 km) at lon/lat 0/0 on a 100 m plain.
std::optional<double> mountain(double lonDeg, double latDeg) {
    const double r2 = (lonDeg * lonDeg + latDeg * latDeg) / (0.02 * 0.02);
    return 100.0 + 4000.0 * std::exp(-0.5 * r2);
}

TEST(NavigationController, LeftDragKeepsTheGrabbedPointUnderTheCursor) {
    // 1e-6 of the range: the manipulator's rotation is exact; the picks are exact on flat ground.
    struct Case {
        Viewpoint vp;
        glm::dvec2 from, to;
    };
    const Case cases[] = {
        {{10.0, 40.0, 0.0, 30.0, -50.0, 2.0e5}, {700.0, 400.0}, {300.0, 600.0}},
        {{179.9, 0.0, 0.0, 90.0, -45.0, 1.0e5}, {400.0, 420.0}, {1000.0, 380.0}},   // across lon 180
        {{0.0, 89.5, 0.0, 0.0, -60.0, 2.0e5}, {640.0, 500.0}, {640.0, 250.0}},     // over the pole
    };
    for (const auto& c : cases) {
        NavigationController nav = makeController(c.vp);
        const auto grabbed = nav.groundAt(c.from);
        ASSERT_TRUE(grabbed.has_value());
        dragMouse(nav, MouseButton::Left, c.from, c.to);
        const auto under = nav.groundAt(c.to);
        ASSERT_TRUE(under.has_value());
        EXPECT_LT(glm::length(under->ecef - grabbed->ecef), 1e-6 * c.vp.range);
        EXPECT_NEAR(angleDiff(under->geodetic.lonDeg, grabbed->geodetic.lonDeg), 0.0, 1e-7);
        EXPECT_NEAR(under->geodetic.latDeg, grabbed->geodetic.latDeg, 1e-7);
    }
    // On a 3000 m plateau the grabbed point is on the plateau (1 cm: the manipulator meets a
    // raised ellipsoid within ~5 mm of the plateau).
    NavigationController nav = makeController({-105.0, 39.0, 3000.0, 20.0, -35.0, 2.0e4});
    nav.setHeightQuery([](double, double) { return std::optional<double>(3000.0); });
    const auto grabbed = nav.groundAt({600.0, 500.0});
    dragMouse(nav, MouseButton::Left, {600.0, 500.0}, {500.0, 300.0});
    EXPECT_LT(glm::length(nav.groundAt({500.0, 300.0})->ecef - grabbed->ecef), 1e-2);
}

TEST(NavigationController, WheelZoomsTowardTheCursorByTheNotchFactor) {
    NavigationController nav = makeController({20.0, 30.0, 0.0, 10.0, -45.0, 1.0e5});
    const glm::dvec2 cursor(900.0, 250.0);
    nav.handle(MouseMoveEvent{cursor});
    const auto p = nav.groundAt(cursor);
    ASSERT_TRUE(p.has_value());
    const double before = p->distance;
    nav.handle(ScrollEvent{0.0, 1.0});
    auto after = nav.groundAt(cursor);
    ASSERT_TRUE(after.has_value());
    // 1e-6 relative: the eye moves along the cursor ray, exactly.
    EXPECT_NEAR(after->distance, before * NavigationController::kWheelZoomFactor, 1e-6 * before);
    EXPECT_LT(glm::length(after->ecef - p->ecef), 1e-6 * before);
    nav.handle(ScrollEvent{0.0, -2.0});   // two notches out
    after = nav.groundAt(cursor);
    EXPECT_NEAR(after->distance, before / NavigationController::kWheelZoomFactor, 1e-6 * before);
    EXPECT_LT(glm::length(after->ecef - p->ecef), 1e-6 * before);
}

TEST(NavigationController, RightDragZoomsTowardWhereItStarted) {
    NavigationController nav = makeController({-3.0, 51.0, 0.0, 0.0, -60.0, 5.0e4});
    const glm::dvec2 start(300.0, 500.0);
    const auto p = nav.groundAt(start);
    ASSERT_TRUE(p.has_value());
    // Up by one doubling's worth of pixels: half the distance, the point still under `start`.
    dragMouse(nav, MouseButton::Right, start, start - glm::dvec2(40.0, NavigationController::kDragZoomPxPerDoubling));
    const auto after = nav.groundAt(start);
    ASSERT_TRUE(after.has_value());
    EXPECT_NEAR(after->distance, 0.5 * p->distance, 1e-6 * p->distance);
    EXPECT_LT(glm::length(after->ecef - p->ecef), 1e-6 * p->distance);
}

TEST(NavigationController, TiltAndTurnDragsAreClamped) {
    for (const bool ctrlLeft : {false, true}) {
        NavigationController nav = makeController({5.0, 50.0, 0.0, 0.0, -45.0, 1.0e4});
        const MouseButton button = ctrlLeft ? MouseButton::Left : MouseButton::Middle;
        // A tenth of the height up: 9 degrees toward the horizon.
        dragMouse(nav, button, {640.0, 400.0}, {640.0, 328.0}, 5, ctrlLeft);
        EXPECT_NEAR(nav.viewpoint().pitchDeg, -36.0, 1e-6);
        dragMouse(nav, button, {640.0, 700.0}, {640.0, 0.0}, 20, ctrlLeft);
        EXPECT_NEAR(nav.viewpoint().pitchDeg, globe::EarthManipulator::kMaxPitchDeg, 1e-6);
        dragMouse(nav, button, {640.0, 0.0}, {640.0, 700.0}, 20, ctrlLeft);
        dragMouse(nav, button, {640.0, 0.0}, {640.0, 700.0}, 20, ctrlLeft);
        EXPECT_NEAR(nav.viewpoint().pitchDeg, globe::EarthManipulator::kMinPitchDeg, 1e-6);
        // A quarter of the width right: the view turns 45 degrees east, about the same point.
        const Viewpoint before = nav.viewpoint();
        dragMouse(nav, button, {100.0, 300.0}, {420.0, 300.0}, 8, ctrlLeft);
        EXPECT_NEAR(angleDiff(nav.viewpoint().headingDeg, before.headingDeg + 45.0), 0.0, 1e-6);
        EXPECT_NEAR(nav.viewpoint().latDeg, before.latDeg, 1e-7);
    }
}

TEST(NavigationController, DoubleClickFliesToThePointAtHalfItsDistance) {
    NavigationController nav = makeController({2.35, 48.85, 0.0, 20.0, -50.0, 3.0e4});
    const glm::dvec2 px(900.0, 500.0);
    const auto target = nav.groundAt(px);
    ASSERT_TRUE(target.has_value());
    const Viewpoint start = nav.viewpoint();
    nav.handle(press(MouseButton::Left, px + glm::dvec2(2.0, -2.0), 10.0));
    nav.handle(release(MouseButton::Left, px));
    EXPECT_FALSE(nav.animating());
    nav.handle(press(MouseButton::Left, px, 10.2));   // the second press says where to go
    EXPECT_TRUE(nav.flying());
    nav.handle(MouseMoveEvent{px + glm::dvec2(3.0, 0.0)});   // a jitter does not grab the globe
    nav.handle(release(MouseButton::Left, px));
    const double seconds = runUntilIdle(nav);
    EXPECT_NEAR(seconds, NavigationController::kFlightSeconds, 1.0 / 60.0 + 1e-9);
    // The flight keeps heading and pitch; it ends with the point at the centre (1e-7 degrees,
    // ~1 cm) at half its distance (1 mm).
    const Viewpoint end = nav.viewpoint();
    EXPECT_NEAR(angleDiff(end.lonDeg, target->geodetic.lonDeg), 0.0, 1e-7);
    EXPECT_NEAR(end.latDeg, target->geodetic.latDeg, 1e-7);
    EXPECT_NEAR(end.range, 0.5 * target->distance, 1e-3);
    EXPECT_NEAR(angleDiff(end.headingDeg, start.headingDeg), 0.0, 1e-6);
    EXPECT_NEAR(end.pitchDeg, start.pitchDeg, 1e-6);
}

TEST(NavigationController, SlowOrDistantClicksAreNoDoubleClick) {
    NavigationController nav = makeController({2.35, 48.85, 0.0, 0.0, -50.0, 3.0e4});
    const glm::dvec2 px(700.0, 400.0);
    const double tooSlow = NavigationController::kDoubleClickSeconds + 0.05;
    for (const auto& [dt, offset] : {std::pair{tooSlow, 0.0}, std::pair{0.1, NavigationController::kDoubleClickPx + 1.0}}) {
        nav.handle(press(MouseButton::Left, px, 100.0));
        nav.handle(release(MouseButton::Left, px));
        nav.handle(press(MouseButton::Left, px + glm::dvec2(offset, 0.0), 100.0 + dt));
        nav.handle(release(MouseButton::Left, px));
        EXPECT_FALSE(nav.flying());
        nav.releaseAll();
    }
    // A third quick click after a double click starts no second flight.
    nav.handle(press(MouseButton::Left, px, 200.0));
    nav.handle(press(MouseButton::Left, px, 200.1));
    ASSERT_TRUE(nav.flying());
    nav.handle(press(MouseButton::Left, px, 200.2));   // grabs: the flight stops
    EXPECT_FALSE(nav.flying());
}

TEST(NavigationController, DoubleClickIntoSpaceIsAPlainPress) {
    // From 40 000 km the corner is in space: no flight, and the second press still grabs.
    NavigationController nav = makeController({0.0, 0.0, 0.0, 0.0, -90.0, 4.0e7});
    const glm::dvec2 corner(5.0, 5.0);
    ASSERT_FALSE(nav.groundAt(corner).has_value());
    nav.handle(press(MouseButton::Left, corner, 50.0));
    nav.handle(release(MouseButton::Left, corner));
    nav.handle(press(MouseButton::Left, corner, 50.1));
    EXPECT_FALSE(nav.flying());
    const std::uint64_t revision = nav.revision();
    nav.handle(MouseMoveEvent{corner + glm::dvec2(100.0, 0.0)});
    EXPECT_GT(nav.revision(), revision);
}

TEST(NavigationController, HomeKeyReturnsToTheHomeViewpointExactly) {
    NavigationController nav = makeController({100.0, -10.0, 0.0, 45.0, -45.0, 1.0e4});
    const Viewpoint home{10.0, 30.0, 0.0, 0.0, -90.0, 2.2e7};
    nav.setHomeViewpoint(home);
    dragMouse(nav, MouseButton::Left, {600.0, 300.0}, {200.0, 100.0});
    nav.handle(key(Key::Home, true));
    nav.handle(key(Key::Home, false));
    EXPECT_TRUE(nav.animating());
    runUntilIdle(nav);
    const Pose expected = globe::poseFromViewpoint(home);
    EXPECT_EQ(nav.pose().position, expected.position);
    EXPECT_EQ(nav.pose().orientation, expected.orientation);
    // Ctrl+Home is the application's shortcut, not ours.
    nav.setViewpoint({100.0, -10.0, 0.0, 45.0, -45.0, 1.0e4});
    nav.handle(key(Key::Home, true, true));
    EXPECT_FALSE(nav.animating());
}

TEST(NavigationController, GrabbingTheGlobeCancelsAFlight) {
    NavigationController nav = makeController({0.0, 0.0, 0.0, 0.0, -90.0, 1.0e7});
    nav.flyTo({100.0, 40.0, 0.0, 0.0, -60.0, 1.0e5});
    nav.advance(0.3);
    ASSERT_TRUE(nav.flying());
    nav.handle(press(MouseButton::Right, {640.0, 360.0}));
    EXPECT_FALSE(nav.flying());
    EXPECT_FALSE(nav.animating());
}

TEST(NavigationController, KeyboardSpeedIsProportionalToHeight) {
    // Forward for 0.1 s straight down (heading 0: north) from 1 m and from 40 000 km: the eye
    // moves 0.1 heights along its sphere (1e-6 relative), keeps its height, and goes north.
    for (const double h : {1.0, 4.0e7}) {
        NavigationController nav = makeController({30.0, 10.0, 0.0, 0.0, -90.0, h});
        const Pose before = nav.pose();
        const globe::Geodetic g0 = wgs84().toGeodetic(before.position);
        nav.handle(key(Key::W, true));
        EXPECT_TRUE(nav.animating());
        const std::uint64_t revision = nav.revision();
        nav.advance(0.1);
        EXPECT_GT(nav.revision(), revision);
        const globe::Geodetic g1 = wgs84().toGeodetic(nav.pose().position);
        const double r0 = glm::length(before.position);
        const double angle = std::acos(std::clamp(glm::dot(before.position, nav.pose().position) /
                                                      (r0 * glm::length(nav.pose().position)), -1.0, 1.0));
        // The arc is measured by its chord for 1 m (acos loses precision at 1e-8 rad).
        const double moved = h < 10.0 ? glm::length(nav.pose().position - before.position) : angle * r0;
        EXPECT_NEAR(moved, 0.1 * g0.height, 1e-3 * 0.1 * g0.height) << h;
        EXPECT_NEAR(g1.height, g0.height, 1e-6 * g0.height + 1e-6) << h;
        EXPECT_GT(g1.latDeg, g0.latDeg);
        EXPECT_NEAR(g1.lonDeg, g0.lonDeg, 1e-9);
        nav.handle(key(Key::W, false));
        EXPECT_FALSE(nav.animating());
        const std::uint64_t still = nav.revision();
        nav.advance(0.1);
        EXPECT_EQ(nav.revision(), still);   // nothing held: the camera rests
    }
}

TEST(NavigationController, KeysStrafeTurnAndZoom) {
    const Viewpoint vp{30.0, 10.0, 0.0, 0.0, -90.0, 1000.0};
    {
        NavigationController nav = makeController(vp);   // D: strafe right, that is east
        const double lon0 = wgs84().toGeodetic(nav.pose().position).lonDeg;
        nav.handle(key(Key::D, true));
        nav.advance(0.05);
        EXPECT_GT(wgs84().toGeodetic(nav.pose().position).lonDeg, lon0);
    }
    {
        NavigationController nav = makeController(vp);   // E: turn right in place, 60 deg/s
        const glm::dvec3 eye = nav.pose().position;
        nav.handle(key(Key::E, true));
        nav.advance(0.05);
        nav.advance(0.05);
        EXPECT_NEAR(angleDiff(nav.viewpoint().headingDeg, 6.0), 0.0, 1e-6);
        EXPECT_LT(glm::length(nav.pose().position - eye), 1e-6);
    }
    {
        NavigationController nav = makeController(vp);   // R / PageUp: in, one halving per second
        nav.handle(key(Key::PageUp, true));
        nav.advance(0.1);
        EXPECT_NEAR(nav.viewpoint().range, 1000.0 * std::exp2(-0.1), 1e-6);
        nav.handle(key(Key::PageUp, false));
        nav.handle(key(Key::F, true));
        nav.advance(0.1);
        EXPECT_NEAR(nav.viewpoint().range, 1000.0, 1e-6);
    }
    {
        NavigationController nav = makeController(vp);   // Ctrl+S is a shortcut, not "back"
        nav.handle(key(Key::S, true, true));
        EXPECT_FALSE(nav.animating());
    }
}

TEST(NavigationController, KeyboardFlightNeverGoesUnderAMountain) {
    // From 3000 m over the plain 30 km east of the mountain, forward (west) into its flank: at
    // ~145 m a step the eye lands inside the slope and is lifted; it stays the clearance above
    // the ground at every step (1 um), then creeps up the slope at 1 m/s.
    NavigationController nav;
    nav.handle(kViewport);
    nav.setHeightQuery(mountain);
    nav.setPose(globe::poseFromEye({0.3, 0.001, 3000.0}, -90.0, -10.0));
    nav.handle(key(Key::W, true));
    double maxHeight = 0.0;
    for (int i = 0; i < 600; ++i) {
        nav.advance(0.05);
        const globe::Geodetic g = wgs84().toGeodetic(nav.pose().position);
        ASSERT_GE(g.height, *mountain(g.lonDeg, g.latDeg) + 1.0 - 1e-6) << i;
        maxHeight = std::max(maxHeight, g.height);
    }
    EXPECT_GT(maxHeight, 3000.0 + 1e-3);   // lifted by the slope
    EXPECT_LT(wgs84().toGeodetic(nav.pose().position).lonDeg, 0.03);
    // Zooming in with the keys stops at the clearance too.
    nav.setViewpoint({0.0, 0.0, 4100.0, 0.0, -90.0, 500.0});
    nav.handle(key(Key::W, false));
    nav.handle(key(Key::R, true));
    for (int i = 0; i < 200; ++i) nav.advance(0.1);
    EXPECT_GE(eyeHeight(nav), 4100.0 + 1.0 - 1e-6);
    EXPECT_LT(eyeHeight(nav), 4100.0 + 2.0);
}

TEST(NavigationController, LiftsTheCameraWhenTheGroundUnderItRises) {
    // Finer terrain loads under a resting camera 10 m above the ellipsoid: the next advance
    // lifts it above the new ground.
    NavigationController nav = makeController({7.0, 46.0, 0.0, 0.0, -30.0, 10.0});
    nav.setHeightQuery([](double, double) { return std::optional<double>(500.0); });
    const std::uint64_t revision = nav.revision();
    nav.advance(0.0);
    EXPECT_GE(eyeHeight(nav), 501.0 - 1e-6);
    EXPECT_GT(nav.revision(), revision);
}

TEST(NavigationController, BadEventsAreIgnored) {
    NavigationController nav = makeController({0.0, 0.0, 0.0, 0.0, -60.0, 1.0e5});
    const Pose start = nav.pose();
    const std::uint64_t revision = nav.revision();
    // Not-finite positions, scrolls and times.
    nav.handle(press(MouseButton::Left, {kNaN, 100.0}));
    nav.handle(MouseMoveEvent{{kNaN, kNaN}});
    nav.handle(release(MouseButton::Left, {kNaN, 100.0}));
    nav.handle(ScrollEvent{0.0, kNaN});
    nav.handle(ScrollEvent{kNaN, 0.0});
    nav.handle(press(MouseButton::Left, {500.0, 300.0}, kNaN));
    nav.handle(press(MouseButton::Left, {500.0, 300.0}, kNaN));   // no double click from NaN times
    nav.handle(release(MouseButton::Left, {500.0, 300.0}));
    nav.advance(kNaN);
    nav.advance(-1.0);
    nav.advance(std::numeric_limits<double>::infinity());
    nav.setFovYRad(kNaN);
    nav.setFovYRad(0.0);
    nav.setMinClearance(kNaN);
    EXPECT_FALSE(nav.flying());
    // A zero-size viewport (a minimised window): mouse events do nothing until a size comes.
    nav.handle(ViewportSize{0.0, 0.0});
    dragMouse(nav, MouseButton::Left, {10.0, 10.0}, {300.0, 200.0});
    nav.handle(MouseMoveEvent{{300.0, 200.0}});
    nav.handle(ScrollEvent{0.0, 3.0});
    EXPECT_FALSE(nav.groundAt({300.0, 200.0}).has_value());
    nav.handle(ViewportSize{kNaN, 720.0});
    nav.handle(ScrollEvent{0.0, 3.0});
    EXPECT_EQ(nav.pose().position, start.position);
    EXPECT_EQ(nav.pose().orientation, start.orientation);
    EXPECT_EQ(nav.revision(), revision);
    // A bad pose or viewpoint leaves the camera where it was.
    Pose bad = start;
    bad.position.y = kNaN;
    nav.setPose(bad);
    nav.setViewpoint({kNaN, 0.0, 0.0, 0.0, -60.0, 1.0e5});
    EXPECT_TRUE(finite(nav.pose()));
    EXPECT_EQ(nav.pose().position, start.position);
    // And with a valid size again it works.
    nav.handle(kViewport);
    nav.handle(MouseMoveEvent{{640.0, 360.0}});
    nav.handle(ScrollEvent{0.0, 1.0});
    EXPECT_GT(nav.revision(), revision);
    EXPECT_TRUE(finite(nav.pose()));
}

}  // namespace
}  // namespace orbis::ui
