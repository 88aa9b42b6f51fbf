#include "layers/volume/VolumeUniforms.h"

#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::layers {

namespace {

using Slice = VolumeSettings::Slice;

/// The smallest spacing between neighbouring samples of an axis (0 for one sample).
double finestSpacing(const std::vector<double>& axis) {
    double d = std::numeric_limits<double>::max();
    for (size_t i = 1; i < axis.size(); ++i) d = std::min(d, std::abs(axis[i] - axis[i - 1]));
    return axis.size() > 1 ? d : 0.0;
}

/// The surface at drawn height `height` in the form relative to `origin` that the shader's
/// shellHits takes: the origin scaled by the inverse semi-axes (xyz) and |that|^2 - 1 (w).
/// Returns the inverse semi-axes (equatorial, polar).
glm::dvec2 shellTerms(const glm::dvec3& origin, double height, glm::vec4& scaled) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const double a = ell.equatorialRadius(), b = ell.polarRadius();
    const glm::dvec3 inv(1.0 / (a + height), 1.0 / (a + height), 1.0 / (b + height));
    const glm::dvec3 os = origin * inv;
    scaled = glm::vec4(glm::vec3(os), float(glm::dot(os, os) - 1.0));
    return glm::dvec2(inv.x, inv.z);
}

/// One slice as an exact surface relative to `origin` (VolumeTypes.h, VolumeSlice).
shader::VolumeSlice packSlice(const Slice& sl, const glm::dvec3& origin, double lonFirst, double exaggeration) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const double a = ell.equatorialRadius();
    const double e2 = 1.0 - (1.0 - ell.flattening()) * (1.0 - ell.flattening());
    shader::VolumeSlice out{};
    if (sl.axis == Slice::Axis::Lon) {
        const double lam = glm::radians(sl.value);
        const glm::dvec3 n(-std::sin(lam), std::cos(lam), 0.0);
        const double lon = lonFirst + std::fmod(std::fmod(sl.value - lonFirst, 360.0) + 360.0, 360.0);
        out.vector = glm::vec3(n);
        out.kind = float(shader::kVolumeSliceLon);
        out.terms = glm::vec4(float(glm::dot(n, origin)), float(lon), 0.0f, 0.0f);
    } else if (sl.axis == Slice::Axis::Lat) {
        const double phi = glm::radians(sl.value), sinPhi = std::sin(phi);
        const double apex = -e2 * a / std::sqrt(1.0 - e2 * sinPhi * sinPhi) * sinPhi;   // normals meet the axis here
        const double k = std::tan(phi) * std::tan(phi);
        const glm::dvec3 o(origin.x, origin.y, origin.z - apex);
        out.vector = glm::vec3(o);
        out.kind = float(shader::kVolumeSliceLat);
        out.terms = glm::vec4(float(k), float(o.z * o.z - k * (o.x * o.x + o.y * o.y)), float(sl.value), 0.0f);
    } else {
        glm::vec4 scaled;
        const glm::dvec2 inv = shellTerms(origin, sl.value * exaggeration, scaled);
        out.vector = glm::vec3(scaled);
        out.kind = float(shader::kVolumeSliceHeight);
        out.terms = glm::vec4(scaled.w, float(inv.x), float(inv.y), float(sl.value));
    }
    return out;
}

/// The frame: the eye, the box and its origin, the view, the ellipsoid.
void packFrame(shader::VolumeUniforms& u, const VolumeFrameInputs& in) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const glm::dvec3& origin = in.box.origin;
    u.eyeFromOrigin = glm::vec3(in.eye - origin);
    u.forward = glm::vec3(in.forward);
    u.nearPlane = float(in.nearPlane);
    u.boxMin = glm::vec3(in.box.min);
    u.boxMax = glm::vec3(in.box.max);
    u.frameIndex = float(in.frame % 65536);
    u.originRho = float(std::hypot(origin.x, origin.y));
    u.originZ = float(origin.z);
    u.originLon = float(std::atan2(origin.y, origin.x));
    u.verticalExaggeration = float(in.settings.verticalExaggeration);
    u.equatorialRadius = float(ell.equatorialRadius());
    u.polarRadius = float(ell.polarRadius());
    u.oneMinusE2 = float((1.0 - ell.flattening()) * (1.0 - ell.flattening()));
}

/// The grid and what is drawn of it: axes, samples, bricks, values, range, isovalues, slices.
void packGrid(shader::VolumeUniforms& u, const VolumeFrameInputs& in) {
    const VolumeSettings& s = in.settings;
    u.lonFirst = float(in.lonRange.x), u.lonLast = float(in.lonRange.y);
    u.latFirst = float(in.latRange.x), u.latLast = float(in.latRange.y);
    u.heightFirst = float(in.heightRange.x), u.heightLast = float(in.heightRange.y);
    u.valueScale = float(in.valueScale.x), u.valueOffset = float(in.valueScale.y);
    u.samples = glm::vec3(in.samples);
    u.brickSize = float(in.brickSize);
    u.bricks = glm::vec3(in.bricks);
    const double rangeMin = s.transfer.rangeMin, rangeMax = s.transfer.rangeMax;
    u.rangeMin = float(rangeMin);
    u.rangeInvSpan = float(1.0 / (rangeMax - rangeMin));
    u.isoOpacity = float(s.isoOpacity);
    u.sliceOpacity = float(s.sliceOpacity);
    for (size_t i = 0; i < s.isovalues.size() && i < shader::kVolumeMaxIso; ++i)
        u.isovalues[i / 4][int(i % 4)] = float(s.isovalues[i]);
    for (size_t i = 0; i < s.slices.size() && i < shader::kVolumeMaxSlices; ++i)
        u.slices[i] = packSlice(s.slices[i], in.box.origin, in.lonRange.x, s.verticalExaggeration);
}

/// The shell, the march (steps, opacity, empty-space jumps) and the time steps.
void packMarch(shader::VolumeUniforms& u, const VolumeFrameInputs& in) {
    const VolumeSettings& s = in.settings;
    glm::vec4 lo, hi;
    const glm::dvec2 lowInv = shellTerms(in.box.origin, in.box.shellLow, lo);
    const glm::dvec2 highInv = shellTerms(in.box.origin, in.box.shellHigh, hi);
    u.shellLoInvAxes = glm::vec2(lowInv), u.shellHiInvAxes = glm::vec2(highInv);
    u.shellLoOrigin = glm::vec3(lo), u.shellLoC0 = lo.w;
    u.shellHiOrigin = glm::vec3(hi), u.shellHiC0 = hi.w;
    // "steps" across the diagonal of the normalised box (as a ray-caster counts samples along a
    // cube's diagonal), the longest step across the box's; opacity is per "opacityUnit" of the
    // normalised box.
    const double step = glm::length(in.box.max - in.box.min) / double(s.steps);
    u.stepLength = float(step);
    u.maxSteps = float(s.steps * 4 + 8);   // per segment
    u.normalisedStep = float(std::sqrt(3.0) / s.steps);
    u.minStep = float(std::max(step / 16384.0, 0.01));
    u.opacityPerUnit = float(1.0 / s.opacityUnit);
    u.probeLength = float(std::clamp(step * 0.01, 5.0, 2000.0));
    u.jumpMax = float(in.box.jumpLimit.x), u.jumpPerRho = float(in.box.jumpLimit.y);
    u.refineThreshold = float(s.refineThreshold);
    u.timeStepA = in.timeBlend.x, u.timeStepB = in.timeBlend.y, u.timeStepWeight = in.timeBlend.z;
    u.timeStepCount = float(in.timeSteps);
}

}  // namespace

VolumeBox makeVolumeBox(const std::vector<double>& lonDeg, const std::vector<double>& latDeg,
                        const std::vector<double>& heightM, double verticalExaggeration) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const double ex = verticalExaggeration;
    VolumeBox box;
    // The origin on the bottom surface at the box's centre; bounds from a dense sample of its
    // boundary (the top bulges outward between samples: a margin covers it).
    const double lonC = 0.5 * (lonDeg.front() + lonDeg.back()), latC = 0.5 * (latDeg.front() + latDeg.back());
    const double hLo = heightM.front() * ex, hHi = heightM.back() * ex;
    box.origin = ell.toEcef(lonC, latC, hLo);
    box.min = glm::dvec3(std::numeric_limits<double>::max());
    box.max = -box.min;
    constexpr int kSamples = 48;
    for (int i = 0; i <= kSamples; ++i)
        for (int j = 0; j <= kSamples; ++j)
            for (double h : {hLo, hHi}) {
                const double lon = lonDeg.front() + (lonDeg.back() - lonDeg.front()) * i / kSamples;
                const double lat = latDeg.front() + (latDeg.back() - latDeg.front()) * j / kSamples;
                const glm::dvec3 p = ell.toEcef(lon, lat, h) - box.origin;
                box.min = glm::min(box.min, p);
                box.max = glm::max(box.max, p);
            }
    const double spanLon = glm::radians(lonDeg.back() - lonDeg.front()) / kSamples;
    const double spanLat = glm::radians(latDeg.back() - latDeg.front()) / kSamples;
    const double bulge = (ell.equatorialRadius() + hHi) * (1.0 - std::cos(0.5 * std::max(spanLon, spanLat))) + 1.0;
    box.min -= glm::dvec3(bulge);
    box.max += glm::dvec3(bulge);
    // The shell's surfaces, a little outside the data's heights: a scaled ellipsoid's radius
    // differs from the ellipsoid's radius plus H by up to H times the flattening.
    const double margin = std::max({1.0, 1e-3 * (hHi - hLo), 0.004 * std::max(std::abs(hLo), std::abs(hHi))});
    box.shellLow = hLo - margin;
    box.shellHigh = hHi + margin;
    // Jumps over empty bricks extrapolate the voxel coordinates linearly; along a straight ray
    // height and latitude bend by about L^2 / 2R (longitude by L^2 / 2 rho, rho the distance from
    // the axis), so a jump of L metres is kept to a quarter of the finest voxel of each axis.
    const double radius = ell.equatorialRadius() + std::max(0.0, hHi);
    box.jumpLimit = glm::dvec2(std::min(std::sqrt(0.5 * radius * finestSpacing(heightM) * ex),
                                        radius * std::sqrt(0.5 * glm::radians(finestSpacing(latDeg)))),
                               std::sqrt(0.5 * glm::radians(finestSpacing(lonDeg))));
    return box;
}

shader::VolumeUniforms packVolumeUniforms(const VolumeFrameInputs& in) {
    shader::VolumeUniforms u{};
    packFrame(u, in);
    packGrid(u, in);
    packMarch(u, in);
    return u;
}

}  // namespace orbis::layers
