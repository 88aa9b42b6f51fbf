#pragma once
// A ground vehicle's attitude on sloping terrain: it keeps the heading its trajectory gives and
// takes pitch and roll from the ground under its footprint. CPU only, double precision.
//
// The ground is sampled at four points around the vehicle's reference point (the pose's
// position), along the local horizontal: `halfLength` ahead and behind along the heading,
// `halfWidth` to the right and the left. They make a plane through the reference point with
// slopes sx = (ahead - behind) / (2 halfLength) along the heading and sy = (right - left) /
// (2 halfWidth) across it. The body's forward axis is the heading's direction lifted onto that
// plane (pitch = atan(sx)), its down axis the plane's downward normal, its right axis completes
// them: on a pure cross slope roll = atan(-sy), right wing down where the right side is lower.
// The four queries see the terrain at that spacing: bumps shorter than the vehicle are smoothed
// over, as a wheelbase would.
//
// Which poses follow the ground: those whose altitude is entirely "above ground" (Ground samples
// on both sides of the time) and within kOnGroundAglMetres of it (Pose::onGround): a car, a
// train, a ship at sea level on a DEM. A drone flying 50 m above the ground keeps its own pitch
// and roll. Where the ground is unknown at any of the four points the trajectory's attitude is
// kept.

#include "formats/motion/Trajectory.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <optional>

namespace orbis::motion {

/// Half the vehicle's extent along its forward (body x) and right (body y) axes, metres.
struct Footprint {
    double halfLength = 0.0;
    double halfWidth = 0.0;
};

/// The body-to-ECEF attitude of a vehicle at (lon, lat) heading `headingDeg` on the ground
/// that `ground` describes, or nothing where one of the four samples is unknown (or the
/// footprint is empty: both halves under 1 cm).
std::optional<glm::dquat> groundAttitude(double lonDeg, double latDeg, double headingDeg, const Footprint& footprint,
                                         const GroundFn& ground);

/// Sets the attitude of an on-ground pose (Pose::onGround) from the ground (groundAttitude):
/// orientation, pitch and roll; the heading stays. Other poses are left as they are.
void followGround(Pose& pose, const Footprint& footprint, const GroundFn& ground);

}  // namespace orbis::motion
