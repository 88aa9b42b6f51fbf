// The viewer's drawing tools (ui/input/Sketch.h) and the projection of the ground into the window
// that draws them (MapTools projectToWindow): measures against closed forms, boxes across the
// antimeridian, GeoJSON that GDAL's readers take (counter-clockwise rings, closed), points behind
// the horizon hidden, projection the inverse of picking.
#include "ui/input/MapTools.h"
#include "ui/input/Sketch.h"

#include "globe/Viewpoint.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace orbis::ui {
namespace {

globe::Geodetic at(double lon, double lat) { return {lon, lat, 0.0}; }

TEST(Sketch, ToolsKeepTheirPointsAndMeasure) {
    Sketch s;
    s.add(at(1, 1));
    EXPECT_TRUE(s.points().empty()) << "no tool, no points";
    s.setTool(SketchTool::Path);
    const uint64_t r0 = s.revision();
    s.add(at(0, 0));
    EXPECT_FALSE(s.complete());
    s.add(at(1, 0));
    s.add(at(1, 1));
    EXPECT_GT(s.revision(), r0);
    ASSERT_TRUE(s.complete());
    // One degree of the equator is 111 319.49 m; one of the meridian at the equator 110 574.4 m.
    EXPECT_NEAR(s.lengthM(), 111319.49 + 110574.4, 5.0);
    EXPECT_EQ(s.along().size(), 3u);
    EXPECT_FALSE(s.area());
    s.removeLast();
    EXPECT_NEAR(s.lengthM(), 111319.49, 0.5);

    s.setTool(SketchTool::Box);
    EXPECT_TRUE(s.points().empty()) << "another tool starts again";
    s.add(at(179.5, -0.5));
    s.add(at(-179.5, 0.5));   // across the antimeridian
    ASSERT_TRUE(s.complete());
    const auto b = *s.bounds();
    EXPECT_DOUBLE_EQ(b.west, 179.5);
    EXPECT_DOUBLE_EQ(b.east, 180.5) << "continued past 180, not the 359 degrees the other way";
    const auto area = *s.area();
    EXPECT_NEAR(area.areaM2, 111319.49 * 110574.4, 0.002 * 111319.49 * 110574.4) << "a degree square at the equator";
    EXPECT_EQ(s.outline().size(), 5u);
    s.add(at(10, 10));
    EXPECT_EQ(s.points().size(), 1u) << "a third corner starts a new box";

    s.setTool(SketchTool::Point);
    s.add(at(5, 5));
    s.add(at(6, 6));
    ASSERT_EQ(s.points().size(), 1u);
    EXPECT_EQ(s.points()[0].lonDeg, 6.0);
    EXPECT_EQ(s.lengthM(), 0.0);
    s.add({std::nan(""), 1.0, 0.0});
    EXPECT_EQ(s.points()[0].lonDeg, 6.0) << "not a place: ignored";
}

TEST(Sketch, GeoJsonIsAFeatureCollectionWithClosedCounterClockwiseRings) {
    Sketch s;
    s.setTool(SketchTool::Polygon);
    s.add(at(9.0, 46.0));
    s.add(at(9.0, 46.1));   // clockwise: north, then east
    EXPECT_EQ(s.geoJson(), "") << "incomplete";
    s.add(at(9.1, 46.0));
    const auto j = nlohmann::json::parse(s.geoJson());
    EXPECT_EQ(j["type"], "FeatureCollection");
    const auto& ring = j["features"][0]["geometry"]["coordinates"][0];
    ASSERT_EQ(ring.size(), 4u);
    EXPECT_EQ(ring.front(), ring.back()) << "closed";
    double twice = 0.0;
    for (size_t i = 0; i + 1 < ring.size(); ++i)
        twice += ring[i][0].get<double>() * ring[i + 1][1].get<double>() - ring[i + 1][0].get<double>() * ring[i][1].get<double>();
    EXPECT_GT(twice, 0.0) << "counter-clockwise";

    s.setTool(SketchTool::Sight);
    s.add(at(9.0, 46.0));
    s.add(at(9.05, 46.02));
    const auto line = nlohmann::json::parse(s.geoJson());
    EXPECT_EQ(line["features"][0]["geometry"]["type"], "LineString");
    EXPECT_EQ(line["features"][0]["geometry"]["coordinates"][1][0], 9.05);
}

TEST(Sketch, LengthsAndAreasReadAsAUserWrites) {
    EXPECT_EQ(formatLength(0.25), "0.25 m");
    EXPECT_EQ(formatLength(850.4), "850 m");
    EXPECT_EQ(formatLength(1234.0), "1.23 km");
    EXPECT_EQ(formatLength(12400.0), "12.4 km");
    EXPECT_EQ(formatArea(420.0), "420 m\u00b2");
    EXPECT_EQ(formatArea(32000.0), "3.20 ha");
    EXPECT_EQ(formatArea(1.25e7), "12.50 km\u00b2");
}

TEST(ProjectToWindow, IsTheInverseOfPickingAndHidesWhatLiesBehindTheHorizon) {
    const globe::Pose pose = globe::poseFromViewpoint({10.0, 45.0, 0.0, 30.0, -40.0, 5.0e4});
    const glm::dvec2 viewport(1280.0, 720.0);
    const double fov = glm::radians(45.0);
    for (const glm::dvec2 px : {glm::dvec2(640, 360), glm::dvec2(100, 600), glm::dvec2(1200, 200)}) {
        const glm::dvec2 ndc(2.0 * px.x / viewport.x - 1.0, 2.0 * px.y / viewport.y - 1.0);
        const auto ground = pick(pose, fov, viewport.x / viewport.y, ndc, {});
        ASSERT_TRUE(ground);
        const auto back = projectToWindow(pose, fov, viewport, ground->ecef);
        ASSERT_TRUE(back);
        EXPECT_NEAR(back->x, px.x, 1e-6);
        EXPECT_NEAR(back->y, px.y, 1e-6);
    }
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    EXPECT_FALSE(projectToWindow(pose, fov, viewport, wgs84.toEcef(-170.0, -45.0))) << "the far side of the Earth";
    // From 20 000 km above (0, 0), looking down: the centre is seen, a point 85 degrees away is
    // on the visible cap's edge side but past the horizon (the horizon is at ~81 degrees).
    const globe::Pose high = globe::poseFromViewpoint({0.0, 0.0, 0.0, 0.0, -90.0, 2.0e7});
    EXPECT_TRUE(projectToWindow(high, fov, viewport, wgs84.toEcef(0.0, 0.0), 1e6));
    EXPECT_TRUE(projectToWindow(high, fov, viewport, wgs84.toEcef(70.0, 0.0), 1e6));
    EXPECT_FALSE(projectToWindow(high, fov, viewport, wgs84.toEcef(85.0, 0.0), 1e6));
    EXPECT_FALSE(projectToWindow(pose, fov, viewport, pose.position - (pose.orientation * glm::dvec3(0, 0, -1)) * 100.0))
        << "behind the eye";
    EXPECT_FALSE(projectToWindow(pose, fov, {0.0, 720.0}, wgs84.toEcef(10.0, 45.0)));
}

}  // namespace
}  // namespace orbis::ui
