#pragma once
// The camera, in double precision: ECEF position, orientation (camera-to-world, looking along
// -Z with +Y up) and vertical field of view. The GPU never sees ECEF: the view matrix is a pure
// rotation (eye at the origin) and every object's model-view is built here in double from its
// own origin, then sent as float.

#include "globe/Viewpoint.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace orbis::scene {

class Camera {
public:
    Camera() = default;

    void setPose(const globe::Pose& pose);
    globe::Pose pose() const { return {position_, orientation_}; }
    void setPosition(const glm::dvec3& ecef) { position_ = ecef; }
    void setOrientation(const glm::dquat& cameraToWorld) { orientation_ = glm::normalize(cameraToWorld); }
    /// Looks from `eye` at `target`, `up` giving the roll (falls back to another axis when parallel).
    void lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);

    const glm::dvec3& position() const { return position_; }
    const glm::dquat& orientation() const { return orientation_; }
    glm::dvec3 forward() const { return orientation_ * glm::dvec3(0, 0, -1); }
    glm::dvec3 up() const { return orientation_ * glm::dvec3(0, 1, 0); }
    glm::dvec3 right() const { return orientation_ * glm::dvec3(1, 0, 0); }

    void setVerticalFovDeg(double fovDeg) { fovYRad_ = glm::radians(fovDeg); }
    double verticalFovRad() const { return fovYRad_; }
    /// Distance of the near plane. Follows the height above the terrain (see autoNear).
    void setNear(double metres) { near_ = metres; }
    double nearPlane() const { return near_; }
    /// A near plane for a camera `heightAboveSurface` metres above whatever is below it:
    /// reversed-Z float depth keeps its precision over any range, so the near plane only has
    /// to stay in front of the closest surface.
    static double autoNear(double heightAboveSurface);

    /// World-to-view rotation only: the eye is the origin of view space.
    glm::dmat4 viewRotation() const;
    /// Model-view for geometry given relative to `originEcef`: rotation * (origin - eye), all
    /// in double, so the float matrix sent to the GPU holds only small numbers.
    glm::dmat4 modelViewRelativeToEye(const glm::dvec3& originEcef) const;
    /// Reversed-Z projection with an infinite far plane (depth 1 at near, 0 at infinity),
    /// Vulkan clip space (y down).
    glm::dmat4 projection(double aspect) const;
    /// World direction of the ray through normalised device coordinates (x right, y down, -1..1).
    glm::dvec3 rayDirection(double ndcX, double ndcY, double aspect) const;

private:
    glm::dvec3 position_{2.0e7, 0.0, 0.0};
    glm::dquat orientation_{1.0, 0.0, 0.0, 0.0};
    double fovYRad_ = glm::radians(45.0);
    double near_ = 1.0;
};

}  // namespace orbis::scene
