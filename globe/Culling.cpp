#include "globe/Culling.h"

#include <cmath>

namespace orbis::globe {

ViewFrustum ViewFrustum::perspective(double fovYRad, double aspect, double nearPlane) {
    ViewFrustum f;
    const double ty = std::tan(0.5 * fovYRad), tx = ty * aspect;
    // A side plane through the origin containing the frustum edge; normal points inside.
    f.planes_[0] = glm::dvec4(glm::normalize(glm::dvec3(1.0, 0.0, -tx)), 0.0);    // left
    f.planes_[1] = glm::dvec4(glm::normalize(glm::dvec3(-1.0, 0.0, -tx)), 0.0);   // right
    f.planes_[2] = glm::dvec4(glm::normalize(glm::dvec3(0.0, 1.0, -ty)), 0.0);    // bottom
    f.planes_[3] = glm::dvec4(glm::normalize(glm::dvec3(0.0, -1.0, -ty)), 0.0);   // top
    f.planes_[4] = glm::dvec4(0.0, 0.0, -1.0, -nearPlane);                          // near
    return f;
}

bool ViewFrustum::intersectsSphere(const glm::dvec3& c, double radius) const {
    for (const auto& p : planes_)
        if (glm::dot(glm::dvec3(p), c) + p.w < -radius) return false;
    return true;
}

bool sphereBelowHorizon(const glm::dvec3& eye, const glm::dvec3& center, double radius, const Ellipsoid& ellipsoid) {
    // In the space where the ellipsoid is the unit sphere, a surface point P is visible from E
    // when dot(P, E) > 1. Scaling shrinks distances by at least 1/a and at most 1/b, so the
    // sphere's radius becomes at most radius/b there.
    const glm::dvec3 s(1.0 / ellipsoid.equatorialRadius(), 1.0 / ellipsoid.equatorialRadius(),
                       1.0 / ellipsoid.polarRadius());
    const glm::dvec3 e = eye * s, c = center * s;
    const double eyeLen = glm::length(e);
    if (eyeLen <= 1.0) return false;
    const double r = radius / ellipsoid.polarRadius();
    // Points inside the ellipsoid are hidden anyway; points above it are visible over the
    // horizon only where dot(P, E) > 1. The sphere is hidden when its largest dot stays below 1.
    return glm::dot(c, e) + r * eyeLen < 1.0;
}

}  // namespace orbis::globe
