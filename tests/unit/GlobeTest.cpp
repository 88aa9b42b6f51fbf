// Geodesy: ellipsoid conversions, ENU frames, viewpoints, culling, and the globe mesh.
#include "globe/Culling.h"
#include "globe/Ellipsoid.h"
#include "globe/Viewpoint.h"
#include "layers/earth/EarthMesh.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

namespace orbis::globe {
namespace {

const Ellipsoid& wgs84() { return Ellipsoid::wgs84(); }

TEST(Ellipsoid, KnownPointsInEcef) {
    // Tolerance 1 mm: GeographicLib is exact to nanometres; these are textbook values.
    const glm::dvec3 p = wgs84().toEcef(0.0, 0.0, 0.0);
    EXPECT_NEAR(p.x, 6378137.0, 1e-3);
    EXPECT_NEAR(p.y, 0.0, 1e-3);
    const glm::dvec3 pole = wgs84().toEcef(0.0, 90.0, 0.0);
    EXPECT_NEAR(pole.z, 6356752.314245, 1e-3);
    EXPECT_NEAR(glm::length(glm::dvec2(pole)), 0.0, 1e-3);
}

TEST(Ellipsoid, RoundTripAtStiffPlaces) {
    // Poles, antimeridian, below the ellipsoid (Dead Sea), 40 000 km out. Tolerance 1e-9 deg
    // (0.1 mm) and 1e-4 m.
    const Geodetic cases[] = {{0, 90, 0}, {0, -90, 100}, {180, 0, 0}, {-180, 45, 10}, {35.5, 31.5, -430},
                              {10, 20, 4.0e7}, {179.9999999, -89.9999999, 1}};
    for (const auto& g : cases) {
        const Geodetic back = wgs84().toGeodetic(wgs84().toEcef(g));
        EXPECT_NEAR(back.latDeg, g.latDeg, 1e-9);
        if (std::abs(g.latDeg) < 90.0) {
            EXPECT_NEAR(wrapLongitude(back.lonDeg - g.lonDeg + 1e-12), 0.0, 1e-9);
        }
        EXPECT_NEAR(back.height, g.height, 1e-4);
    }
}

TEST(Ellipsoid, EnuFrameIsOrthonormalEvenAtThePole) {
    for (double lat : {-90.0, -45.0, 0.0, 89.999, 90.0}) {
        const glm::dmat3 m = wgs84().enuFrame(30.0, lat);
        EXPECT_NEAR(glm::dot(m[0], m[1]), 0.0, 1e-14);
        EXPECT_NEAR(glm::dot(m[0], m[2]), 0.0, 1e-14);
        EXPECT_NEAR(glm::length(m[2]), 1.0, 1e-14);
        EXPECT_NEAR(glm::dot(glm::cross(m[0], m[1]), m[2]), 1.0, 1e-14);   // right-handed
    }
}

TEST(Ellipsoid, RayIntersectionFromSpaceAndGrazing) {
    const glm::dvec3 eye(2.0e7, 0, 0);
    auto t = wgs84().intersectRay(eye, glm::dvec3(-1, 0, 0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 2.0e7 - 6378137.0, 1e-6);
    EXPECT_FALSE(wgs84().intersectRay(eye, glm::dvec3(1, 0, 0)));
    EXPECT_FALSE(wgs84().intersectRay(eye, glm::normalize(glm::dvec3(-1, 0.5, 0))));
}

TEST(Viewpoint, EyeIsRangeAwayAndLooksAtTarget) {
    const Viewpoint vp{10.0, 45.0, 100.0, 30.0, -40.0, 5000.0};
    const Pose pose = poseFromViewpoint(vp);
    const glm::dvec3 target = wgs84().toEcef(10.0, 45.0, 100.0);
    EXPECT_NEAR(glm::length(pose.position - target), 5000.0, 1e-6);
    const glm::dvec3 forward = pose.orientation * glm::dvec3(0, 0, -1);
    EXPECT_NEAR(glm::dot(forward, glm::normalize(target - pose.position)), 1.0, 1e-12);
    // Pitch -40: the eye is range*sin(40) above the target (flat-earth approximation at 5 km: 2 m).
    EXPECT_NEAR(wgs84().toGeodetic(pose.position).height - 100.0, 5000.0 * std::sin(glm::radians(40.0)), 3.0);
}

TEST(Viewpoint, HeadingTurnsClockwiseFromNorth) {
    const Pose north = poseFromEye({0.0, 0.0, 10.0}, 0.0, 0.0);
    const Pose east = poseFromEye({0.0, 0.0, 10.0}, 90.0, 0.0);
    const glm::dmat3 enu = wgs84().enuFrame(0.0, 0.0);
    EXPECT_NEAR(glm::dot(north.orientation * glm::dvec3(0, 0, -1), enu[1]), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(east.orientation * glm::dvec3(0, 0, -1), enu[0]), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(east.orientation * glm::dvec3(0, 1, 0), enu[2]), 1.0, 1e-12);   // level: up is up
}

TEST(Viewpoint, StraightDownAtThePoleIsWellDefined) {
    const Pose p = poseFromViewpoint({0.0, 90.0, 0.0, 0.0, -90.0, 1.0e6});
    const glm::dvec3 f = p.orientation * glm::dvec3(0, 0, -1);
    EXPECT_NEAR(f.z, -1.0, 1e-12);
    EXPECT_TRUE(std::isfinite(p.position.x));
    EXPECT_NEAR(p.position.z, 6356752.314245 + 1.0e6, 1e-3);
}

TEST(Culling, FrustumKeepsWhatIsAheadAndDropsWhatIsBehind) {
    const auto f = ViewFrustum::perspective(glm::radians(45.0), 1.0, 1.0);
    EXPECT_TRUE(f.intersectsSphere({0, 0, -100}, 1));
    EXPECT_FALSE(f.intersectsSphere({0, 0, 100}, 1));
    EXPECT_FALSE(f.intersectsSphere({1000, 0, -100}, 1));
    EXPECT_TRUE(f.intersectsSphere({1000, 0, -100}, 1000));
    EXPECT_TRUE(f.intersectsSphere({0, 0, -1e12}, 1));   // infinite far plane
}

TEST(Culling, HorizonHidesTheFarSideOnly) {
    const glm::dvec3 eye(2.0e7, 0, 0);
    EXPECT_FALSE(sphereBelowHorizon(eye, wgs84().toEcef(0, 0, 0), 1000));     // facing point
    EXPECT_TRUE(sphereBelowHorizon(eye, wgs84().toEcef(180, 0, 0), 1000));    // antipode
    EXPECT_FALSE(sphereBelowHorizon(eye, wgs84().toEcef(60, 0, 0), 1000));    // within the horizon (acos(a/r) = 71 deg)
    EXPECT_TRUE(sphereBelowHorizon(eye, wgs84().toEcef(80, 0, 0), 1000));
    // An eye below the surface culls nothing.
    EXPECT_FALSE(sphereBelowHorizon(wgs84().toEcef(0, 0, -100), wgs84().toEcef(180, 0, 0), 1));
}

TEST(GlobeMesh, NeighbouringPatchesShareBitIdenticalEdges) {
    // No cracks: every vertex position (in ECEF, rebuilt in double) on a shared edge is
    // identical from both patches, up to float rounding of the relative positions.
    const auto mesh = layers::EarthMesh::build(30.0, 4);
    ASSERT_EQ(mesh.patches.size(), 12u * 6u);
    std::map<std::pair<float, float>, glm::dvec3> seen;
    double worst = 0.0;
    for (size_t p = 0; p < mesh.patches.size(); ++p) {
        for (uint32_t v = 0; v < mesh.verticesPerPatch(); ++v) {
            const auto& vert = mesh.vertices[p * mesh.verticesPerPatch() + v];
            float lon = vert.lonLatDeg.x == 180.0f ? -180.0f : vert.lonLatDeg.x;
            if (std::abs(vert.lonLatDeg.y) == 90.0f) lon = 0.0f;   // all longitudes meet at a pole
            const glm::dvec3 ecef = mesh.patches[p].origin + glm::dvec3(vert.position);
            auto [it, inserted] = seen.emplace(std::make_pair(lon, vert.lonLatDeg.y), ecef);
            if (!inserted) worst = std::max(worst, glm::length(it->second - ecef));
        }
    }
    // Float relative positions over a 30-degree patch (~1700 km): spacing ~0.125 m.
    EXPECT_LT(worst, 0.3);
}

TEST(GlobeMesh, TrianglesWindCounterClockwiseFromOutside) {
    const auto mesh = layers::EarthMesh::build(10.0, 2);
    const size_t patch = mesh.patches.size() / 2 + 3;
    const auto* v = &mesh.vertices[patch * mesh.verticesPerPatch()];
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const glm::dvec3 a(v[mesh.indices[i]].position), b(v[mesh.indices[i + 1]].position), c(v[mesh.indices[i + 2]].position);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const glm::dvec3 outward = mesh.patches[patch].origin + a;
        EXPECT_GT(glm::dot(n, outward), 0.0);
    }
}

}  // namespace
}  // namespace orbis::globe
