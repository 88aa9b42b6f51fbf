#pragma once
// A scene as the application holds it: the list of displayable resources (name, visibility,
// default viewpoint, layer object), the camera and the virtual time.

#include "engine/core/Result.h"
#include "engine/scene/Camera.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/SceneDesc.h"
#include "engine/scene/TimeServer.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::scene {

struct Resource {
    std::string name;
    std::string type;
    bool visible = true;
    std::optional<globe::Viewpoint> viewpoint;
    std::unique_ptr<Layer> layer;
};

class Scene {
public:
    /// Builds every layer the description names (and only those). Main thread only.
    static Result<std::unique_ptr<Scene>> build(SceneDesc desc, const LayerRegistry& registry);

    const SceneDesc& desc() const { return desc_; }
    std::vector<Resource>& resources() { return resources_; }
    const std::vector<Resource>& resources() const { return resources_; }
    Resource* find(const std::string& name);

    Camera& camera() { return camera_; }
    const Camera& camera() const { return camera_; }
    TimeServer& time() { return time_; }
    const TimeServer& time() const { return time_; }

    /// The elevation query: ground height (metres above the ellipsoid, as drawn) at a point
    /// from the first visible ground layer that knows it (terrain), else nothing (the
    /// ellipsoid). Used by camera collision, the near plane, clamping and FMV.
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    /// `pose` with the eye lifted along the vertical, if needed, to at least `clearance` metres
    /// above the ground where heightAt knows it (orientation unchanged). Scripted camera paths
    /// go through it so that no frame is rendered from under the terrain.
    globe::Pose keptAboveGround(globe::Pose pose, double clearance = 2.0) const;
    /// True while a visible layer still loads what the current view needs.
    bool busy() const;

    /// Puts the camera at the scene's viewpoint (the "Home" view).
    void goHome();

private:
    explicit Scene(SceneDesc desc) : desc_(std::move(desc)) {}

    SceneDesc desc_;
    std::vector<Resource> resources_;
    Camera camera_;
    TimeServer time_;
};

}  // namespace orbis::scene
