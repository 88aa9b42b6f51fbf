#pragma once
// Visibility tests for bounding spheres: the view frustum (in view space, eye at the origin,
// infinite far plane) and the horizon of the ellipsoid. No Vulkan.

#include "globe/Ellipsoid.h"

#include <glm/glm.hpp>

namespace orbis::globe {

/// Planes of a symmetric perspective frustum in view space (looking along -Z), normals inward.
class ViewFrustum {
public:
    static ViewFrustum perspective(double fovYRad, double aspect, double nearPlane);
    /// True when a sphere (centre in view space) may be inside.
    bool intersectsSphere(const glm::dvec3& centerView, double radius) const;

private:
    glm::dvec4 planes_[5];   // left, right, bottom, top, near; dot(n, p) + d >= 0 inside
};

/// True when a sphere lies entirely below the horizon seen from `eye` (ECEF), i.e. hidden by
/// the ellipsoid itself. Conservative: it may say "visible" for a hidden sphere, never the
/// reverse. An eye below the surface culls nothing.
bool sphereBelowHorizon(const glm::dvec3& eye, const glm::dvec3& center, double radius,
                        const Ellipsoid& ellipsoid = Ellipsoid::wgs84());

}  // namespace orbis::globe
