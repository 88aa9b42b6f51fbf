// The double-precision camera: view relative to the eye, reversed-Z infinite projection.
#include "engine/scene/Camera.h"
#include "globe/Ellipsoid.h"

#include <gtest/gtest.h>

namespace orbis::scene {
namespace {

TEST(Camera, ReversedZMapsNearToOneAndFarToZero) {
    Camera cam;
    cam.setNear(2.0);
    const glm::dmat4 p = cam.projection(1.5);
    auto depth = [&](double z) {
        const glm::dvec4 c = p * glm::dvec4(0, 0, -z, 1);
        return c.z / c.w;
    };
    EXPECT_NEAR(depth(2.0), 1.0, 1e-15);
    EXPECT_NEAR(depth(4.0), 0.5, 1e-15);
    EXPECT_LT(depth(1e12), 1e-11);   // infinite far plane: tends to 0, never below
    EXPECT_GT(depth(1e12), 0.0);
}

TEST(Camera, ProjectionFlipsYForVulkan) {
    Camera cam;
    const glm::dmat4 p = cam.projection(1.0);
    const glm::dvec4 up = p * glm::dvec4(0, 1, -10, 1);
    EXPECT_LT(up.y / up.w, 0.0);   // Vulkan clip space: +y is down the screen
}

TEST(Camera, ModelViewRelativeToEyeKeepsPrecisionFarFromTheOrigin) {
    // An eye 1 m above a point on the equator, 6.4e6 m from the Earth's centre: the model-view
    // of an origin 0.25 m away must place it 0.25 m away to well under a millimetre, which a
    // float world-space matrix cannot do (float spacing at 6.4e6 is 0.5 m).
    Camera cam;
    const auto& e = globe::Ellipsoid::wgs84();
    const glm::dvec3 ground = e.toEcef(10.0, 0.0, 0.0);
    cam.lookAt(e.toEcef(10.0, 0.0, 1.0), ground, glm::dvec3(0, 0, 1));
    const glm::dvec3 origin = ground + glm::dvec3(0.0, 0.0, 0.25);
    const glm::mat4 mv = glm::mat4(cam.modelViewRelativeToEye(origin));   // what the GPU receives
    const glm::vec4 v = mv * glm::vec4(0, 0, 0, 1);
    const double expected = glm::length(origin - cam.position());
    EXPECT_NEAR(glm::length(glm::dvec3(v)), expected, 1e-6);
}

TEST(Camera, LookAtStraightDownAlongUpStaysFinite) {
    Camera cam;
    cam.lookAt(glm::dvec3(0, 0, 1e7), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1));   // forward parallel to up
    const glm::dvec3 f = cam.forward();
    EXPECT_NEAR(f.z, -1.0, 1e-12);
    EXPECT_TRUE(std::isfinite(cam.up().x) && std::isfinite(cam.right().y));
    EXPECT_NEAR(glm::dot(cam.up(), f), 0.0, 1e-12);
}

TEST(Camera, RayThroughCentreIsForward) {
    Camera cam;
    cam.lookAt(glm::dvec3(1e7, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1));
    const glm::dvec3 d = cam.rayDirection(0.0, 0.0, 16.0 / 9.0);
    EXPECT_NEAR(glm::dot(d, cam.forward()), 1.0, 1e-12);
    // NDC y = -1 is the top of the image: the ray tilts up.
    EXPECT_GT(glm::dot(cam.rayDirection(0.0, -1.0, 1.0), cam.up()), 0.0);
}

TEST(Camera, AutoNearFollowsHeight) {
    EXPECT_DOUBLE_EQ(Camera::autoNear(1.0), 0.1);
    EXPECT_DOUBLE_EQ(Camera::autoNear(0.0), 0.01);
    EXPECT_DOUBLE_EQ(Camera::autoNear(4.0e7), 1000.0);
    EXPECT_DOUBLE_EQ(Camera::autoNear(-400.0), 40.0);   // below the ellipsoid (Dead Sea): still positive
}

}  // namespace
}  // namespace orbis::scene
