#include "engine/scene/Camera.h"

#include <algorithm>
#include <cmath>

namespace orbis::scene {

void Camera::setPose(const globe::Pose& pose) {
    position_ = pose.position;
    orientation_ = glm::normalize(pose.orientation);
}

void Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
    const glm::dvec3 f = glm::normalize(target - eye);
    glm::dvec3 r = glm::cross(f, up);
    if (glm::dot(r, r) < 1e-20) r = glm::cross(f, std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0));
    r = glm::normalize(r);
    const glm::dvec3 u = glm::cross(r, f);
    position_ = eye;
    orientation_ = glm::normalize(glm::quat_cast(glm::dmat3(r, u, -f)));
}

double Camera::autoNear(double heightAboveSurface) {
    return std::clamp(0.1 * std::abs(heightAboveSurface), 0.01, 1000.0);
}

glm::dmat4 Camera::viewRotation() const { return glm::dmat4(glm::mat3_cast(glm::conjugate(orientation_))); }

glm::dmat4 Camera::modelViewRelativeToEye(const glm::dvec3& originEcef) const {
    glm::dmat4 m = viewRotation();
    const glm::dvec3 t = glm::dmat3(m) * (originEcef - position_);
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

glm::dmat4 Camera::projection(double aspect) const {
    // x_clip = f/aspect x, y_clip = -f y (Vulkan's y points down), z_clip = near, w_clip = -z.
    // Depth = near / -z: 1 at the near plane, tending to 0 at infinity.
    const double f = 1.0 / std::tan(0.5 * fovYRad_);
    glm::dmat4 p(0.0);
    p[0][0] = f / aspect;
    p[1][1] = -f;
    p[2][3] = -1.0;
    p[3][2] = near_;
    return p;
}

glm::dvec3 Camera::rayDirection(double ndcX, double ndcY, double aspect) const {
    const double t = std::tan(0.5 * fovYRad_);
    const glm::dvec3 v(ndcX * t * aspect, -ndcY * t, -1.0);
    return glm::normalize(orientation_ * v);
}

}  // namespace orbis::scene
