#include "engine/scene/Scene.h"

#include "base/Log.h"
#include "engine/scene/CameraRig.h"
#include "globe/Ellipsoid.h"

#include <algorithm>
#include <utility>

namespace orbis::scene {

namespace {

/// What stands in for a layer that could not be built: it draws nothing and says why.
class FailedLayer : public Layer {
public:
    FailedLayer(std::string type, std::string error) : type_(std::move(type)), error_(std::move(error)) {}
    std::string_view type() const override { return type_; }
    bool drawsIn(Pass) const override { return false; }
    void record(Pass, const render::RecordContext&) override {}
    std::string status() const override { return "not loaded: " + error_; }

private:
    void onPrepare(const render::RenderServices&) override {}
    std::string type_, error_;
};

/// The resource for a layer of the scene file, its layer not yet made.
Resource resourceFor(const LayerDesc& layer, const LayerRegistry& registry) {
    Resource r;
    r.name = layer.name;
    r.type = layer.type;
    r.visible = layer.visible;
    r.viewpoint = layer.viewpoint;
    r.filePaths = registry.filePaths(layer.type);
    return r;
}

}  // namespace

Result<std::unique_ptr<Scene>> Scene::build(SceneDesc desc, const LayerRegistry& registry, const SceneBuildOptions& options) {
    std::unique_ptr<Scene> scene(new Scene(std::move(desc)));
    for (const LayerDesc& layer : scene->desc_.layers) {
        auto made = registry.create(layer, scene->desc_);
        Resource r = resourceFor(layer, registry);
        if (made) {
            r.layer = std::move(made).value();
        } else if (options.keepGoing) {
            log::error(made.message());
            r.error = made.message();
            r.visible = false;
            r.layer = std::make_unique<FailedLayer>(layer.type, made.message());
        } else {
            return made.error();
        }
        scene->resources_.push_back(std::move(r));
    }
    scene->annotations_ = scene->desc_.annotations;
    if (!scene->annotations_.empty())
        if (auto ok = scene->ensureAnnotationLayer(registry); !ok) return ok.error();
    TimeDesc t = scene->desc_.time;
    if (!t.given) {   // no "time" in the file: the span of the layers' data, from its start
        std::optional<TimeRange> all;
        for (const Resource& r : scene->resources_) {
            const MovingContent* moving = r.layer->asMovingContent();
            if (auto range = moving ? moving->timeRange() : std::nullopt) {
                if (!all) all = range;
                else all = TimeRange{std::min(all->start, range->start), std::max(all->end, range->end)};
            }
        }
        if (all) {
            t.start = t.current = all->start;
            t.end = all->end;
        }
    }
    if (auto ok = scene->time_.setRange(t.start, t.end); !ok) return ok.error();
    scene->time_.seek(t.current);
    scene->time_.setRate(t.rate);
    scene->time_.setLoop(t.loop);
    if (t.playing) scene->time_.play();
    scene->camera_.setVerticalFovDeg(scene->desc_.fovDeg);
    scene->goHome();
    if (scene->desc_.camera.mode != CameraMode::Free) {
        if (!scene->find(scene->desc_.camera.target)) {
            return makeError(scene->desc_.file.string() + ": /camera/target: no layer is named \"" + scene->desc_.camera.target + "\"");
        }
        scene->cameraMode_ = scene->desc_.camera;
    }
    return scene;
}

Result<void> Scene::ensureAnnotationLayer(const LayerRegistry& registry) {
    for (const Resource& r : resources_)
        if (r.type == kAnnotationLayerType) return {};
    if (!registry.has(kAnnotationLayerType)) return {};   // an app without it: pins are data only
    LayerDesc layer;
    layer.type = kAnnotationLayerType;
    layer.name = find("Annotations") ? "Annotations (pins)" : "Annotations";
    layer.settings = nlohmann::json::object();
    layer.jsonPath = "/annotations";
    auto made = registry.create(layer, desc_);
    if (!made) return made.error();
    Resource r;
    r.name = layer.name;
    r.type = layer.type;
    r.layer = std::move(made).value();
    resources_.push_back(std::move(r));
    return {};
}

Result<Resource*> Scene::addLayer(LayerDesc layer, const LayerRegistry& registry) {
    if (layer.name.empty()) layer.name = layer.type;
    for (int n = 2; find(layer.name); ++n) {
        const auto cut = layer.name.rfind(" (");
        if (n > 2 && cut != std::string::npos) layer.name.resize(cut);
        layer.name += " (" + std::to_string(n) + ")";
    }
    layer.jsonPath = "/layers/" + std::to_string(desc_.layers.size());
    layer.settings["type"] = layer.type;
    layer.settings["name"] = layer.name;
    auto made = registry.create(layer, desc_);
    if (!made) return made.error();
    Resource r = resourceFor(layer, registry);
    r.layer = std::move(made).value();
    // Before the pins' layer, which is not in desc_.layers and draws last.
    auto at = std::find_if(resources_.begin(), resources_.end(), [](const Resource& x) { return x.type == kAnnotationLayerType; });
    at = resources_.insert(at, std::move(r));
    desc_.layers.push_back(std::move(layer));
    return &*at;
}

Resource* Scene::find(const std::string& name) {
    return const_cast<Resource*>(std::as_const(*this).find(name));
}

const Resource* Scene::find(const std::string& name) const {
    for (const auto& r : resources_)
        if (r.name == name) return &r;
    return nullptr;
}

void Scene::goHome() { camera_.setPose(globe::poseFromViewpoint(desc_.viewpoint)); }

std::optional<double> Scene::heightAt(double lonDeg, double latDeg) const {
    for (const auto& r : resources_) {
        const GroundSource* ground = r.layer->asGroundSource();
        if (!ground || !r.visible || !r.layer->prepared()) continue;
        if (auto h = ground->groundHeightAt(lonDeg, latDeg)) return h;
    }
    return std::nullopt;
}

GroundHeightFn Scene::groundSnapshot() const {
    std::vector<GroundHeightFn> grounds;
    for (const auto& r : resources_) {
        const GroundSource* ground = r.layer->asGroundSource();
        if (ground && r.visible && r.layer->prepared()) grounds.push_back(ground->groundSnapshot());
    }
    return [grounds = std::move(grounds)](double lonDeg, double latDeg) -> std::optional<double> {
        for (const GroundHeightFn& g : grounds)
            if (auto h = g(lonDeg, latDeg)) return h;
        return std::nullopt;
    };
}

globe::Pose Scene::keptAboveGround(globe::Pose pose, double clearance) const {
    const auto& ellipsoid = globe::Ellipsoid::wgs84();
    globe::Geodetic eye = ellipsoid.toGeodetic(pose.position);
    const auto ground = heightAt(eye.lonDeg, eye.latDeg);
    if (ground && eye.height < *ground + clearance) {
        eye.height = *ground + clearance;
        pose.position = ellipsoid.toEcef(eye);
    }
    return pose;
}

void Scene::setCameraMode(const CameraModeSettings& settings, double flySeconds) {
    cameraMode_ = settings;
    warnedTarget_ = false;
    flight_.reset();
    if (flySeconds > 0.0 && settings.mode != CameraMode::Free) flight_ = Flight{camera_.pose(), flySeconds, std::chrono::steady_clock::now()};
}

std::optional<globe::Pose> Scene::cameraModePose(double aspect) const {
    if (cameraMode_.mode == CameraMode::Free) return std::nullopt;
    const Resource* target = find(cameraMode_.target);
    const MovingContent* moving = target ? target->layer->asMovingContent() : nullptr;
    if (!moving) return std::nullopt;
    const GroundHeightFn ground = [this](double lon, double lat) { return heightAt(lon, lat); };
    const TimeNs now = time_.now();
    if (cameraMode_.mode == CameraMode::Overview) {
        const auto bounds = moving->contentBounds();
        if (!bounds) return std::nullopt;
        return cameraForOverview(*bounds, camera_.verticalFovRad(), aspect);
    }
    const auto pose = moving->trackedPose(now, ground);
    if (!pose) return std::nullopt;
    glm::dvec3 travel(0.0);
    if (cameraMode_.mode == CameraMode::Follow) {
        // The direction of travel over the smoothing window: a function of the time alone.
        const TimeNs before = now - fromSeconds(std::max(cameraMode_.smoothingSeconds, 1e-3));
        if (const auto earlier = moving->trackedPose(before, ground)) travel = pose->position - earlier->position;
        if (glm::dot(travel, travel) < 1e-6) travel = pose->velocity;
    }
    return cameraForTarget(cameraMode_, *pose, travel);
}

void Scene::updateCamera(double aspect) {
    auto pose = cameraModePose(aspect);
    if (!pose) {
        if (cameraMode_.mode != CameraMode::Free && !warnedTarget_) {
            log::info("camera: ", toString(cameraMode_.mode), " mode: \"", cameraMode_.target, "\" has no pose now; the camera stays");
            warnedTarget_ = true;
        }
        return;
    }
    if (flight_) {
        const double f = std::chrono::duration<double>(std::chrono::steady_clock::now() - flight_->start).count() / flight_->seconds;
        if (f >= 1.0) flight_.reset();
        else *pose = blendPoses(flight_->from, *pose, f);
    }
    camera_.setPose(keptAboveGround(*pose, cameraMode_.mode == CameraMode::Below ? -1e9 : 0.5));
}

bool Scene::busy() const {
    for (const auto& r : resources_)
        if (r.visible && r.layer->prepared() && r.layer->busy()) return true;
    return false;
}

}  // namespace orbis::scene
