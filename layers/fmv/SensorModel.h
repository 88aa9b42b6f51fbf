#pragma once
// The camera of a UAV sensor from MISB ST 0601 metadata, and where its rays meet the ground.
// CPU only (no Vulkan), double precision throughout.
//
// Rotation order (ST 0601: platform heading/pitch/roll are Tait-Bryan angles of the platform
// in the local NED frame; the sensor's relative azimuth/elevation/roll are the same kind of
// angles of the sensor in the platform's frame). Each is a z-y-x (yaw, pitch, roll) sequence
// of intrinsic rotations:
//
//   R = R_ned(lat, lon) * Rz(heading) * Ry(pitch) * Rx(roll)          platform in ECEF
//       * Rz(azimuth) * Ry(elevation) * Rx(sensor roll)                 sensor in the platform
//
// with x forward (the boresight), y right, z down; a positive pitch or elevation raises x
// (nose up, looking up), a positive roll lowers y (right wing down). The image's columns go
// along +y and its rows along +z: pixel (u, v) in [-1, 1]^2 (u right, v down, corner 1 = upper
// left = (-1, -1)) looks along x + u tan(hfov/2) y + v tan(vfov/2) z.
//
// Rays that miss the ground (the sensor looking above the horizon) are clamped to the horizon
// in the ray's azimuth: a finite point, never NaN.

#include "base/Result.h"

#include <glm/glm.hpp>

#include <array>
#include <functional>
#include <optional>

namespace orbis::fmv {

struct St0601Packet;

struct SensorPose {
    double lonDeg = 0.0, latDeg = 0.0;
    double height = 0.0;   ///< above the WGS84 ellipsoid, metres
    double platformHeadingDeg = 0.0, platformPitchDeg = 0.0, platformRollDeg = 0.0;
    double sensorAzimuthDeg = 0.0, sensorElevationDeg = 0.0, sensorRollDeg = 0.0;
    double hfovDeg = 30.0, vfovDeg = 20.0;
    bool operator==(const SensorPose&) const = default;
};

/// The pose a packet describes. Height: the ellipsoid height tags (104, 75) when present, else
/// the true altitude (15, above mean sea level) plus `geoidHeight` (the geoid's height above
/// the ellipsoid there; callers look it up, e.g. EGM96 through PROJ). Errors name what is
/// missing: sensor position, field of view. Missing attitude angles count as 0.
Result<SensorPose> sensorPoseFromPacket(const St0601Packet& packet, double geoidHeight = 0.0);

class SensorCamera {
public:
    explicit SensorCamera(const SensorPose& pose);

    const SensorPose& pose() const { return pose_; }
    const glm::dvec3& position() const { return position_; }   ///< ECEF
    /// Columns: the sensor's x (boresight), y (image right), z (image down), in ECEF.
    const glm::dmat3& axes() const { return axes_; }
    /// The unit ray through image point (u, v), both in [-1, 1] (see above), in ECEF.
    glm::dvec3 ray(double u, double v) const;
    /// The ray through image corner i (0..3: upper left, upper right, lower right, lower left).
    glm::dvec3 cornerRay(int i) const;
    /// Projects an ECEF point into the image: (u, v, distance along the boresight); the point
    /// is in view when the distance is > 0 and |u|, |v| <= 1.
    glm::dvec3 project(const glm::dvec3& ecef) const;
    /// tan(hfov / 2) and tan(vfov / 2), the fields of view clamped to (0, 179.9] degrees.
    glm::dvec2 tanHalfFov() const { return {tanHalfH_, tanHalfV_}; }

private:
    SensorPose pose_;
    glm::dvec3 position_{0.0};
    glm::dmat3 axes_{1.0};
    double tanHalfH_ = 0.0, tanHalfV_ = 0.0;
};

/// Terrain heights above the ellipsoid (metres) at a longitude and latitude, and the range they
/// stay within (for bounding the search).
struct TerrainHeights {
    std::function<double(double lonDeg, double latDeg)> at;
    double minHeight = 0.0, maxHeight = 0.0;
};

struct GroundHit {
    glm::dvec3 ecef{0.0};
    double distance = 0.0;   ///< along the ray (to the horizon point when clamped)
    bool hit = false;        ///< false: the ray misses the ground, clamped to the horizon
};

/// Where the ray from `origin` along `direction` (unit) first meets the terrain (a search along
/// the ray in steps of at most `step` metres, then bisection to a millimetre), or, when it
/// misses, the horizon point in its azimuth. `terrain` may be null: the ellipsoid.
GroundHit intersectGround(const glm::dvec3& origin, const glm::dvec3& direction, const TerrainHeights* terrain,
                          double step = 5.0);

/// The point on the horizon, seen from `origin`, in the azimuth of `direction`, on the
/// ellipsoid raised by `height`. Finite for any origin off the centre; the nadir point when
/// the origin is below that surface.
glm::dvec3 horizonPoint(const glm::dvec3& origin, const glm::dvec3& direction, double height = 0.0);

/// The footprint: the four corner rays and the centre ray, on the ground.
struct Footprint {
    std::array<GroundHit, 4> corners;
    GroundHit centre;
};
Footprint footprint(const SensorCamera& camera, const TerrainHeights* terrain, double step = 5.0);

}  // namespace orbis::fmv
