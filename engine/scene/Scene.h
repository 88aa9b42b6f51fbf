#pragma once
// A scene as the application holds it: the list of displayable resources (name, visibility,
// default viewpoint, layer object), the camera and the virtual time.

#include "base/Result.h"
#include "engine/scene/Camera.h"
#include "engine/scene/CameraMode.h"
#include "engine/scene/Layer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/SceneDesc.h"
#include "engine/scene/TimeServer.h"

#include <chrono>
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
    std::unique_ptr<Layer> layer;   ///< never null: a layer that failed to build draws nothing
    std::string error;              ///< why the layer could not be built (SceneBuildOptions::keepGoing)
    /// Where its scene object names files (LayerType::filePaths), for saving the scene elsewhere.
    std::vector<std::string> filePaths;
};

struct SceneBuildOptions {
    /// A layer that cannot be built (a missing file, a bad setting) becomes a resource with
    /// its error and nothing to draw, and the rest of the scene loads: the viewer shows the
    /// error in its panel. Off (batch renders, benchmarks): the first such error fails the build.
    bool keepGoing = false;
};

class Scene {
public:
    /// Builds every layer the description names (and only those). Main thread only.
    static Result<std::unique_ptr<Scene>> build(SceneDesc desc, const LayerRegistry& registry,
                                                const SceneBuildOptions& options = {});

    const SceneDesc& desc() const { return desc_; }
    std::vector<Resource>& resources() { return resources_; }
    const std::vector<Resource>& resources() const { return resources_; }
    Resource* find(const std::string& name);
    const Resource* find(const std::string& name) const;

    /// The labelled pins, from the file and as the user edits them. After a change, call
    /// ensureAnnotationLayer() so that they are drawn.
    std::vector<Annotation>& annotations() { return annotations_; }
    const std::vector<Annotation>& annotations() const { return annotations_; }
    /// Adds the layer that draws the pins (type "annotations", resource "Annotations", last in
    /// the list) if the scene has none yet and `registry` knows the type. Scenes without pins
    /// never build it. An error only when the layer cannot be made.
    Result<void> ensureAnnotationLayer(const LayerRegistry& registry);
    /// Adds a layer while the scene is shown (a processing job's result): built from `layer`
    /// as a scene file's layer would be (its relative paths against the scene's folder), kept
    /// in desc() so that it is saved with the scene, and drawn before the pins. Its name is made
    /// unique (" (2)", ...). Returns the resource; an error, and nothing added, when the layer
    /// cannot be built. Main thread only, between frames.
    Result<Resource*> addLayer(LayerDesc layer, const LayerRegistry& registry);

    Camera& camera() { return camera_; }
    const Camera& camera() const { return camera_; }
    TimeServer& time() { return time_; }
    const TimeServer& time() const { return time_; }

    /// The elevation query: ground height (metres above the ellipsoid, as drawn) at a point
    /// from the first visible ground layer that knows it (terrain), else nothing (the
    /// ellipsoid). Used by camera collision, the near plane, clamping and FMV.
    std::optional<double> heightAt(double lonDeg, double latDeg) const;
    /// heightAt's answers now, as a function any thread may call while it is kept (it holds
    /// the visible ground layers' snapshots, GroundSource::groundSnapshot).
    GroundHeightFn groundSnapshot() const;
    /// `pose` with the eye lifted along the vertical, if needed, to at least `clearance` metres
    /// above the ground where heightAt knows it (orientation unchanged). Scripted camera paths
    /// go through it so that no frame is rendered from under the terrain.
    globe::Pose keptAboveGround(globe::Pose pose, double clearance = 2.0) const;
    /// True while a visible layer still loads what the current view needs.
    bool busy() const;

    /// Puts the camera at the scene's viewpoint (the "Home" view).
    void goHome();

    /// Switches the camera mode (CameraMode.h). With `flySeconds` > 0 the camera flies from
    /// where it is to the new mode's view over that many wall seconds; else it jumps there at
    /// the next updateCamera(). Free leaves the camera where it is (for the user to move).
    void setCameraMode(const CameraModeSettings& settings, double flySeconds = 0.0);
    const CameraModeSettings& cameraMode() const { return cameraMode_; }
    /// Puts the camera where its mode wants it at the current virtual time (the target layer's
    /// pose on the ground as loaded); does nothing in Free mode or while the target is hidden.
    /// The renderer calls it at the start of every frame, with the frame's aspect ratio.
    void updateCamera(double aspect);
    /// The view the mode gives at the current time, without moving the camera; nothing in Free
    /// mode, when the target does not exist or is hidden now.
    std::optional<globe::Pose> cameraModePose(double aspect) const;

private:
    explicit Scene(SceneDesc desc) : desc_(std::move(desc)) {}

    SceneDesc desc_;
    std::vector<Resource> resources_;
    std::vector<Annotation> annotations_;
    Camera camera_;
    TimeServer time_;
    CameraModeSettings cameraMode_;
    struct Flight {
        globe::Pose from;
        double seconds = 0.0;
        std::chrono::steady_clock::time_point start;
    };
    std::optional<Flight> flight_;
    bool warnedTarget_ = false;
};

}  // namespace orbis::scene
