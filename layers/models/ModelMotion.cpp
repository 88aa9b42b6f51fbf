#include "layers/models/ModelMotion.h"

#include "globe/Ellipsoid.h"
#include "formats/motion/Attitude.h"

#include <algorithm>
#include <cmath>

namespace orbis::models {
namespace {

class FixedMotion final : public ModelMotion {
public:
    FixedMotion(double lon, double lat, double height, bool onGround, double heading, double pitch, double roll)
        : lon_(lon), lat_(lat), height_(height), onGround_(onGround),
          q_(motion::bodyToEcef(lon, lat, heading, pitch, roll)) {}

    std::optional<scene::TrackedPose> pose(TimeNs, const GroundFn& ground) const override {
        double h = height_;
        if (onGround_) h += (ground ? ground(lon_, lat_) : std::nullopt).value_or(0.0);
        scene::TrackedPose p;
        p.position = globe::Ellipsoid::wgs84().toEcef(lon_, lat_, h);
        p.bodyToEcef = q_;
        return p;
    }
    std::optional<scene::TimeRange> range() const override { return std::nullopt; }
    std::vector<glm::dvec3> path(TimeNs, TimeNs, std::size_t, const GroundFn&) const override { return {}; }
    scene::ContentBounds bounds() const override {
        return {globe::Ellipsoid::wgs84().toEcef(lon_, lat_, height_), 0.0};
    }
    bool usesGround() const override { return onGround_; }

private:
    double lon_, lat_, height_;
    bool onGround_;
    glm::dquat q_;
};

class TrajectoryMotion final : public ModelMotion {
public:
    explicit TrajectoryMotion(motion::Trajectory trajectory) : t_(std::move(trajectory)) {
        for (const auto& s : t_.samples()) usesGround_ |= s.altRef == motion::AltitudeRef::Ground;
    }

    std::optional<scene::TrackedPose> pose(TimeNs t, const GroundFn& ground) const override {
        auto p = t_.pose(t, ground ? &ground : nullptr);
        if (!p) return std::nullopt;
        motion::followGround(*p, footprint_, ground);
        return toTrackedPose(*p);
    }
    void setFootprint(const motion::Footprint& footprint) override { footprint_ = footprint; }
    std::optional<scene::TimeRange> range() const override {
        const auto r = t_.timeRange();
        return scene::TimeRange{r.begin, r.end};
    }
    std::vector<glm::dvec3> path(TimeNs from, TimeNs to, std::size_t maxPoints, const GroundFn& ground) const override {
        return t_.pathEcef(from, to, maxPoints, ground ? &ground : nullptr);
    }
    scene::ContentBounds bounds() const override { return {t_.bounds().centerEcef, t_.bounds().radius}; }
    bool usesGround() const override { return usesGround_; }
    std::string status() const override {
        return t_.name() + ": " + std::to_string(t_.sampleCount()) + " samples";
    }

private:
    motion::Trajectory t_;
    bool usesGround_ = false;
    motion::Footprint footprint_;
};

}  // namespace

std::unique_ptr<ModelMotion> makeFixedMotion(double lonDeg, double latDeg, double height, bool onGround,
                                             double headingDeg, double pitchDeg, double rollDeg) {
    return std::make_unique<FixedMotion>(lonDeg, latDeg, height, onGround, headingDeg, pitchDeg, rollDeg);
}

std::unique_ptr<ModelMotion> makeTrajectoryMotion(motion::Trajectory trajectory) {
    return std::make_unique<TrajectoryMotion>(std::move(trajectory));
}

}  // namespace orbis::models
