// The ray caster's numbers packed on the CPU (layers/volume/VolumeUniforms.h): the box's frame,
// its shell, the slices, ranges and isovalues, the march and the time steps, on known inputs.
// Values are packed from doubles into floats: comparisons are to float precision unless stated.
#include "layers/volume/VolumeUniforms.h"

#include "globe/Ellipsoid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace orbis::layers {
namespace {

const globe::Ellipsoid& wgs84() { return globe::Ellipsoid::wgs84(); }

std::vector<double> axis(double first, double last, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(first + (last - first) * i / (n - 1));
    return v;
}

/// The uniforms of a 16^3 grid over `lon` x `lat` x `height` (data metres) in `box`.
shader::VolumeUniforms pack(const VolumeSettings& s, const VolumeBox& box, glm::dvec2 lon = {-10, 10},
                            glm::dvec2 lat = {40, 60}, glm::dvec2 height = {0, 100000}) {
    return packVolumeUniforms({.settings = s, .box = box, .lonRange = lon, .latRange = lat, .heightRange = height,
                               .samples = glm::uvec3(16), .bricks = glm::uvec3(2), .brickSize = 8});
}

/// A vector packed as float, back in double.
glm::dvec3 d(const glm::vec3& v) { return glm::dvec3(v); }

}  // namespace

TEST(VolumeUniforms, ShellTermsAtTheEquatorAreTheOriginOverTheShellsSemiAxes) {
    const VolumeBox box = makeVolumeBox(axis(-5, 5, 11), axis(-5, 5, 11), axis(0, 100000, 11), 1.0);
    const double a = wgs84().equatorialRadius(), b = wgs84().polarRadius();
    EXPECT_NEAR(glm::length(box.origin - glm::dvec3(a, 0, 0)), 0.0, 1e-6);   // lon 0, lat 0, height 0
    // The shell lies a margin outside the data's heights (here 0.004 of the top: 400 m).
    EXPECT_DOUBLE_EQ(box.shellLow, -400.0);
    EXPECT_DOUBLE_EQ(box.shellHigh, 100400.0);
    const shader::VolumeUniforms u = pack({}, box);
    EXPECT_FLOAT_EQ(u.shellLoInvAxes.x, float(1.0 / (a - 400.0)));
    EXPECT_FLOAT_EQ(u.shellLoInvAxes.y, float(1.0 / (b - 400.0)));
    EXPECT_FLOAT_EQ(u.shellHiInvAxes.x, float(1.0 / (a + 100400.0)));
    EXPECT_FLOAT_EQ(u.shellHiInvAxes.y, float(1.0 / (b + 100400.0)));
    EXPECT_FLOAT_EQ(u.shellLoOrigin.x, float(a / (a - 400.0)));
    EXPECT_NEAR(u.shellLoOrigin.y, 0.0f, 1e-12f);
    EXPECT_NEAR(u.shellLoOrigin.z, 0.0f, 1e-12f);
    // |O / axes|^2 - 1 comes from doubles: small (the origin is 400 m above the bottom surface)
    // and exact to float precision, where the float O / axes would leave only ~4 digits of it.
    const double c0Lo = (a / (a - 400.0)) * (a / (a - 400.0)) - 1.0;
    const double c0Hi = (a / (a + 100400.0)) * (a / (a + 100400.0)) - 1.0;
    EXPECT_FLOAT_EQ(u.shellLoC0, float(c0Lo));
    EXPECT_FLOAT_EQ(u.shellHiC0, float(c0Hi));
    EXPECT_GT(u.shellLoC0, 0.0f);   // the origin is above the bottom surface...
    EXPECT_LT(u.shellHiC0, 0.0f);   // ...and below the top one
}

TEST(VolumeUniforms, ShellTermsAtAPoleScaleTheOriginByThePolarSemiAxis) {
    const double a = wgs84().equatorialRadius(), b = wgs84().polarRadius();
    VolumeBox box;
    box.origin = wgs84().toEcef(0.0, 90.0, 1000.0);
    box.shellLow = 500.0, box.shellHigh = 5000.0;
    EXPECT_NEAR(glm::length(box.origin - glm::dvec3(0, 0, b + 1000.0)), 0.0, 1e-6);
    const shader::VolumeUniforms u = pack({}, box);
    EXPECT_NEAR(u.originRho, 0.0f, 1e-6f);
    EXPECT_FLOAT_EQ(u.originZ, float(b + 1000.0));
    EXPECT_NEAR(u.shellLoOrigin.x, 0.0f, 1e-12f);
    EXPECT_NEAR(u.shellLoOrigin.y, 0.0f, 1e-12f);
    EXPECT_FLOAT_EQ(u.shellLoOrigin.z, float((b + 1000.0) / (b + 500.0)));
    EXPECT_FLOAT_EQ(u.shellHiOrigin.z, float((b + 1000.0) / (b + 5000.0)));
    const double zLo = (b + 1000.0) / (b + 500.0), zHi = (b + 1000.0) / (b + 5000.0);
    EXPECT_FLOAT_EQ(u.shellLoC0, float(zLo * zLo - 1.0));
    EXPECT_FLOAT_EQ(u.shellHiC0, float(zHi * zHi - 1.0));
    EXPECT_FLOAT_EQ(u.shellLoInvAxes.x, float(1.0 / (a + 500.0)));
    EXPECT_FLOAT_EQ(u.shellLoInvAxes.y, float(1.0 / (b + 500.0)));
    // The ellipsoid's own numbers travel with the frame.
    EXPECT_FLOAT_EQ(u.equatorialRadius, float(a));
    EXPECT_FLOAT_EQ(u.polarRadius, float(b));
    EXPECT_FLOAT_EQ(u.oneMinusE2, float((b / a) * (b / a)));
}

TEST(VolumeUniforms, BoxNearAPoleIsCentredOnItsGrid) {
    const VolumeBox box = makeVolumeBox(axis(-180, 180, 37), axis(80, 90, 11), axis(0, 50000, 6), 2.0);
    const globe::Geodetic o = wgs84().toGeodetic(box.origin);
    EXPECT_NEAR(o.lonDeg, 0.0, 1e-9);
    EXPECT_NEAR(o.latDeg, 85.0, 1e-9);
    EXPECT_NEAR(o.height, 0.0, 1e-6);
    // Every corner of the grid (heights drawn twice as high) lies in the box and in the shell.
    for (double lon : {-180.0, 0.0, 180.0})
        for (double lat : {80.0, 90.0})
            for (double h : {0.0, 100000.0}) {
                const glm::dvec3 p = wgs84().toEcef(lon, lat, h) - box.origin;
                EXPECT_TRUE(glm::all(glm::lessThanEqual(box.min, p)) && glm::all(glm::lessThanEqual(p, box.max)))
                    << lon << " " << lat << " " << h;
            }
    EXPECT_LT(box.shellLow, 0.0);
    EXPECT_GT(box.shellHigh, 100000.0);
    EXPECT_GT(box.jumpLimit.x, 0.0);
    EXPECT_GT(box.jumpLimit.y, 0.0);
}

TEST(VolumeUniforms, LonSliceIsTheMeridianPlaneWrappedIntoTheBox) {
    VolumeSettings s;
    s.slices = {{VolumeSettings::Slice::Axis::Lon, 365.0}};   // = 5 deg, inside [-10, 10]
    const VolumeBox box = makeVolumeBox(axis(-10, 10, 16), axis(40, 60, 16), axis(0, 100000, 16), 1.0);
    const shader::VolumeSlice sl = pack(s, box).slices[0];
    EXPECT_EQ(sl.kind, float(shader::kVolumeSliceLon));
    EXPECT_FLOAT_EQ(sl.terms.y, 5.0f);
    EXPECT_NEAR(sl.vector.x, float(-std::sin(glm::radians(5.0))), 1e-7f);
    EXPECT_NEAR(sl.vector.y, float(std::cos(glm::radians(5.0))), 1e-7f);
    EXPECT_EQ(sl.vector.z, 0.0f);
    // Points of that meridian (relative to the origin) are on the plane: n . (p - O) + n . O = 0,
    // to float precision of n and n . O (a few metres at 6000 km).
    for (double lat : {40.0, 50.0, 60.0}) {
        const glm::dvec3 p = wgs84().toEcef(5.0, lat, 30000.0) - box.origin;
        EXPECT_NEAR(glm::dot(d(sl.vector), p) + sl.terms.x, 0.0, 5.0) << lat;
    }
}

TEST(VolumeUniforms, LatSliceIsTheConeOfItsGeodeticNormals) {
    VolumeSettings s;
    s.slices = {{VolumeSettings::Slice::Axis::Lat, 45.0}};
    const VolumeBox box = makeVolumeBox(axis(-10, 10, 16), axis(40, 60, 16), axis(0, 100000, 16), 1.0);
    const shader::VolumeSlice sl = pack(s, box).slices[0];
    EXPECT_EQ(sl.kind, float(shader::kVolumeSliceLat));
    EXPECT_FLOAT_EQ(sl.terms.x, 1.0f);   // tan^2(45 deg)
    EXPECT_FLOAT_EQ(sl.terms.z, 45.0f);
    // The constant term is the cone's equation at the origin: (Oz - apex)^2 - k rho^2.
    const glm::dvec3 A = d(sl.vector);
    EXPECT_NEAR(sl.terms.y, A.z * A.z - 1.0 * (A.x * A.x + A.y * A.y), 1e-5 * glm::dot(A, A));
    // Every point at latitude 45, whatever its longitude and height, is on the cone
    // (z - apex)^2 = k rho^2 (relative to |A|^2: float precision of A).
    for (double lon : {-10.0, 0.0, 7.0})
        for (double h : {0.0, 80000.0}) {
            const glm::dvec3 q = A + (wgs84().toEcef(lon, 45.0, h) - box.origin);
            EXPECT_NEAR((q.z * q.z - (q.x * q.x + q.y * q.y)) / glm::dot(A, A), 0.0, 1e-6) << lon << " " << h;
        }
}

TEST(VolumeUniforms, HeightSliceIsTheScaledEllipsoidAtItsDrawnHeight) {
    VolumeSettings s;
    s.verticalExaggeration = 2.0;
    s.slices = {{VolumeSettings::Slice::Axis::Height, 10000.0}};   // drawn at 20 km
    const VolumeBox box = makeVolumeBox(axis(-10, 10, 16), axis(40, 60, 16), axis(0, 50000, 16), 2.0);
    const shader::VolumeSlice sl = pack(s, box).slices[0];
    const double a = wgs84().equatorialRadius(), b = wgs84().polarRadius(), H = 20000.0;
    EXPECT_EQ(sl.kind, float(shader::kVolumeSliceHeight));
    const glm::dvec3 os = box.origin / glm::dvec3(a + H, a + H, b + H);
    EXPECT_FLOAT_EQ(sl.vector.x, float(os.x));
    EXPECT_FLOAT_EQ(sl.vector.y, float(os.y));
    EXPECT_FLOAT_EQ(sl.vector.z, float(os.z));
    EXPECT_FLOAT_EQ(sl.terms.x, float(glm::dot(os, os) - 1.0));
    EXPECT_FLOAT_EQ(sl.terms.y, float(1.0 / (a + H)));
    EXPECT_FLOAT_EQ(sl.terms.z, float(1.0 / (b + H)));
    EXPECT_FLOAT_EQ(sl.terms.w, 10000.0f);   // the data's height, for the colour
}

TEST(VolumeUniforms, RangeIsovaluesAndOpacitiesArePackedInOrder) {
    VolumeSettings s;
    s.transfer.rangeMin = 200.0, s.transfer.rangeMax = 310.0;
    s.isovalues = {250, 260, 270, 280, 290};
    s.isoOpacity = 0.5, s.sliceOpacity = 0.25;
    const shader::VolumeUniforms u = pack(s, VolumeBox{});
    EXPECT_FLOAT_EQ(u.rangeMin, 200.0f);
    EXPECT_FLOAT_EQ(u.rangeInvSpan, float(1.0 / 110.0));
    EXPECT_EQ(u.isovalues[0], glm::vec4(250, 260, 270, 280));   // isovalue i at [i / 4][i % 4]
    EXPECT_EQ(u.isovalues[1], glm::vec4(290, 0, 0, 0));
    EXPECT_EQ(u.isoOpacity, 0.5f);
    EXPECT_EQ(u.sliceOpacity, 0.25f);
    for (const shader::VolumeSlice& sl : u.slices) EXPECT_EQ(sl.terms, glm::vec4(0.0f));   // no slices
}

TEST(VolumeUniforms, StepLengthFollowsTheBoxDiagonalAndTheSteps) {
    VolumeSettings s;
    s.steps = 100;
    s.opacityUnit = 0.25;
    VolumeBox box;
    box.min = glm::dvec3(-1000, -2000, 0), box.max = glm::dvec3(2000, 2000, 12000);   // diagonal 13 km
    shader::VolumeUniforms u = pack(s, box);
    EXPECT_FLOAT_EQ(u.stepLength, 130.0f);
    EXPECT_FLOAT_EQ(u.maxSteps, 408.0f);   // 4 steps + 8 per step across the diagonal
    EXPECT_FLOAT_EQ(u.normalisedStep, float(std::sqrt(3.0) / 100.0));
    EXPECT_FLOAT_EQ(u.minStep, 0.01f);       // 130 m / 16384, at least 1 cm
    EXPECT_FLOAT_EQ(u.probeLength, 5.0f);    // 1 % of a step, at least 5 m
    EXPECT_FLOAT_EQ(u.opacityPerUnit, 4.0f);
    s.steps = 1;
    u = pack(s, box);
    EXPECT_FLOAT_EQ(u.stepLength, 13000.0f);
    EXPECT_FLOAT_EQ(u.minStep, float(13000.0 / 16384.0));
    EXPECT_FLOAT_EQ(u.probeLength, 130.0f);
    EXPECT_FLOAT_EQ(u.maxSteps, 12.0f);
}

TEST(VolumeUniforms, TimeStepsFrameAndCameraArePackedAsGiven) {
    VolumeBox box;
    box.origin = wgs84().toEcef(30.0, 0.0, 0.0);
    box.jumpLimit = {5000.0, 0.002};
    VolumeSettings s;
    s.verticalExaggeration = 3.0;
    const VolumeFrameInputs in{.settings = s, .box = box, .lonRange = {20, 40}, .latRange = {-10, 10},
                               .heightRange = {-500, 9000}, .samples = {33, 17, 9}, .bricks = {5, 3, 2},
                               .brickSize = 8, .valueScale = {2.0, -1.0}, .timeSteps = 3,
                               .timeBlend = {1.0f, 2.0f, 0.25f}, .eye = box.origin + glm::dvec3(100, -200, 300),
                               .forward = {0, 1, 0}, .nearPlane = 2.5, .frame = 65536 + 7};
    const shader::VolumeUniforms u = packVolumeUniforms(in);
    EXPECT_EQ(u.timeStepA, 1.0f);
    EXPECT_EQ(u.timeStepB, 2.0f);
    EXPECT_EQ(u.timeStepWeight, 0.25f);
    EXPECT_EQ(u.timeStepCount, 3.0f);
    EXPECT_EQ(u.frameIndex, 7.0f);   // modulo 65536
    EXPECT_EQ(u.eyeFromOrigin, glm::vec3(100, -200, 300));
    EXPECT_EQ(u.forward, glm::vec3(0, 1, 0));
    EXPECT_EQ(u.nearPlane, 2.5f);
    EXPECT_FLOAT_EQ(u.originLon, float(glm::radians(30.0)));
    EXPECT_EQ(u.verticalExaggeration, 3.0f);
    EXPECT_EQ(glm::vec4(u.lonFirst, u.lonLast, u.latFirst, u.latLast), glm::vec4(20, 40, -10, 10));
    EXPECT_EQ(glm::vec2(u.heightFirst, u.heightLast), glm::vec2(-500, 9000));
    EXPECT_EQ(u.samples, glm::vec3(33, 17, 9));
    EXPECT_EQ(u.bricks, glm::vec3(5, 3, 2));
    EXPECT_EQ(u.brickSize, 8.0f);
    EXPECT_EQ(glm::vec2(u.valueScale, u.valueOffset), glm::vec2(2, -1));
    EXPECT_EQ(glm::vec2(u.jumpMax, u.jumpPerRho), glm::vec2(5000.0f, 0.002f));
}

}  // namespace orbis::layers
