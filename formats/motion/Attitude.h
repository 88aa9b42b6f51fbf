#pragma once
// Attitude of a vehicle: heading, pitch and roll in the local north-east-down frame, and the
// body-to-ECEF rotation they make. CPU only, double precision.
//
// The convention is MISB ST 0601's platform angles, the one layers/fmv/SensorModel.h uses, so a
// trajectory read from KLV and the FMV sensor camera agree:
//
//   body axes   x forward (the nose), y right (the right wing), z down (right-handed)
//   heading     clockwise from true north, degrees (0 north, 90 east)
//   pitch       positive nose up, degrees
//   roll        positive right wing down, degrees
//
//   bodyToEcef = R_ned(lon, lat) * Rz(heading) * Ry(pitch) * Rx(roll)
//
// intrinsic z-y-x (yaw, pitch, roll) rotations about the body's axes, where R_ned has the
// columns north, east, down of the local frame in ECEF. A body axis v maps to bodyToEcef * v.
//
// 3-D models: glTF is +Y up, +Z forward, +X left (glTF 2.0 spec, "Coordinate System and Units").
// gltfToBody() is that convention, the one place it is written: glTF +X (left) = body -y,
// +Y (up) = body -z, +Z (front) = body +x. gltfToEcef() puts it on a pose (the columns left,
// up, forward of the body in ECEF), and the model layer (layers/models) uses gltfToBody() too,
// so a model's local axes map straight onto the vehicle's body.
//
// All functions are pure and thread-safe.

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace orbis::motion {

struct HeadingPitchRoll {
    double headingDeg = 0.0;   ///< [0, 360), clockwise from true north
    double pitchDeg = 0.0;     ///< [-90, 90], nose up
    double rollDeg = 0.0;      ///< (-180, 180], right wing down
};

/// The local north-east-down frame at (lon, lat) as a rotation: its columns are north, east and
/// down in ECEF. Well defined at the poles (north is taken from the given longitude).
glm::dquat nedToEcef(double lonDeg, double latDeg);

/// Rz(heading) * Ry(pitch) * Rx(roll): the body in the local NED frame.
glm::dquat bodyToNed(double headingDeg, double pitchDeg, double rollDeg);

/// nedToEcef(lon, lat) * bodyToNed(heading, pitch, roll).
glm::dquat bodyToEcef(double lonDeg, double latDeg, double headingDeg, double pitchDeg, double rollDeg);

/// The angles of a body-in-NED rotation. At pitch ±90 (gimbal lock) heading and roll are not
/// separable: roll is reported as 0 and the whole turn as heading.
HeadingPitchRoll headingPitchRoll(const glm::dmat3& bodyInNed);

/// The angles of a body-to-ECEF rotation in the NED frame at (lon, lat).
HeadingPitchRoll headingPitchRoll(const glm::dquat& bodyToEcef, double lonDeg, double latDeg);

/// Heading and pitch of a direction of motion (ECEF) at (lon, lat): the course over ground and
/// the climb angle; roll 0. Nothing sensible for a zero vector: heading 0, pitch 0.
HeadingPitchRoll headingPitchFromDirection(const glm::dvec3& directionEcef, double lonDeg, double latDeg);

/// Unit vectors of the body in ECEF: forward (+x), right (+y), up (-z).
glm::dvec3 forwardAxis(const glm::dquat& bodyToEcef);
glm::dvec3 rightAxis(const glm::dquat& bodyToEcef);
glm::dvec3 upAxis(const glm::dquat& bodyToEcef);

/// glTF model axes -> body axes: its columns are glTF +X, +Y, +Z in body coordinates (see the
/// header). A rotation (determinant +1).
glm::dmat3 gltfToBody();

/// A glTF model's axes on the body: columns (+X left, +Y up, +Z forward) in ECEF, that is
/// R(bodyToEcef) * gltfToBody(). Right-handed.
glm::dmat3 gltfToEcef(const glm::dquat& bodyToEcef);

/// Spherical linear interpolation of unit quaternions, the short way round (q and -q are the
/// same rotation: `b` is negated when the two are more than 180 degrees apart). Exact in angle
/// for any separation; `f` = 0 gives `a`, 1 gives `b` (or -b).
glm::dquat slerpShortest(const glm::dquat& a, const glm::dquat& b, double f);

/// Angle of the rotation from `a` to `b`, degrees in [0, 180], precise also for tiny angles.
double angleBetweenDeg(const glm::dquat& a, const glm::dquat& b);

/// Wraps an angle into [0, 360).
double wrapHeadingDeg(double deg);

}  // namespace orbis::motion
