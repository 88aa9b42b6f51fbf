#pragma once
// Where a model is at a virtual time: a fixed place, a trajectory read from a file, or a live
// position feed. The model layer asks for poses only through this interface. No Vulkan.

#include "base/Result.h"
#include "base/TimeFormat.h"
#include "engine/scene/Layer.h"
#include "formats/motion/GroundAttitude.h"
#include "formats/motion/Trajectory.h"

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::models {

/// Height of the ground above the ellipsoid at (lon, lat), or nothing where unknown.
using GroundFn = motion::GroundFn;

class ModelMotion {
public:
    virtual ~ModelMotion() = default;

    /// The body's pose at `t` (radius left at 1: the layer knows the model's size); nothing
    /// where the model is hidden (outside a trajectory with "hide" extrapolation, a live feed
    /// before its first fix).
    virtual std::optional<scene::TrackedPose> pose(TimeNs t, const GroundFn& ground) const = 0;
    /// The time span of the data; nothing for a fixed model.
    virtual std::optional<scene::TimeRange> range() const = 0;
    /// Positions (ECEF) along the path from `from` to `to`, at most `maxPoints`, for the path
    /// line; empty where there is no path.
    virtual std::vector<glm::dvec3> path(TimeNs from, TimeNs to, std::size_t maxPoints, const GroundFn& ground) const = 0;
    /// A sphere around the whole path (or the fixed place).
    virtual scene::ContentBounds bounds() const = 0;
    /// Once per frame on the main thread (Layer::poll), before pose(): a live feed takes its new
    /// fixes here.
    virtual void update() {}
    /// True when the poses depend on the ground (altitudes above the terrain).
    virtual bool usesGround() const { return false; }
    /// The vehicle's extent on the ground: poses on the ground (trajectories and live feeds,
    /// motion::Pose::onGround) pitch and roll with the terrain under it
    /// (formats/motion/GroundAttitude.h). Empty by default: the trajectory's attitude.
    virtual void setFootprint(const motion::Footprint& /*footprint*/) {}
    /// One line for the stats ("live tcp://...: 120 fixes, connected").
    virtual std::string status() const { return {}; }
};

/// A model standing at (lon, lat, height above the ellipsoid, or above the ground when
/// `onGround`) with the attitude heading/pitch/roll (degrees, formats/motion/Attitude.h).
std::unique_ptr<ModelMotion> makeFixedMotion(double lonDeg, double latDeg, double height, bool onGround,
                                             double headingDeg, double pitchDeg, double rollDeg);

/// A trajectory's pose as the scene's tracked pose (radius 1).
inline scene::TrackedPose toTrackedPose(const motion::Pose& p) {
    scene::TrackedPose out;
    out.position = p.ecef;
    out.bodyToEcef = p.orientation;
    out.velocity = p.velocity;
    return out;
}

/// A model moving along `trajectory` (formats/motion/Trajectory.h).
std::unique_ptr<ModelMotion> makeTrajectoryMotion(motion::Trajectory trajectory);

/// A model on a live position feed (formats/livefeed/LiveSource.h) from its scene settings
/// {"url": "tcp://host:port", "protocol": "auto" | "nmea" | "xml", "altitude": "ellipsoid" | "ground"};
/// `file` and `path` name the settings in messages. The feed's thread starts here.
Result<std::unique_ptr<ModelMotion>> makeLiveMotion(const nlohmann::json& settings, const std::string& file,
                                                    const std::string& path);

}  // namespace orbis::models
