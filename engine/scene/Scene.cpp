#include "engine/scene/Scene.h"

#include "globe/Ellipsoid.h"

namespace orbis::scene {

Result<std::unique_ptr<Scene>> Scene::build(SceneDesc desc, const LayerRegistry& registry) {
    std::unique_ptr<Scene> scene(new Scene(std::move(desc)));
    for (const LayerDesc& layer : scene->desc_.layers) {
        auto made = registry.create(layer, scene->desc_);
        if (!made) return made.error();
        Resource r;
        r.name = layer.name;
        r.type = layer.type;
        r.visible = layer.visible;
        r.viewpoint = layer.viewpoint;
        r.layer = std::move(made).value();
        scene->resources_.push_back(std::move(r));
    }
    const TimeDesc& t = scene->desc_.time;
    if (auto ok = scene->time_.setRange(t.start, t.end); !ok) return ok.error();
    scene->time_.seek(t.current);
    scene->time_.setRate(t.rate);
    scene->time_.setLoop(t.loop);
    if (t.playing) scene->time_.play();
    scene->camera_.setVerticalFovDeg(scene->desc_.fovDeg);
    scene->goHome();
    return scene;
}

Resource* Scene::find(const std::string& name) {
    for (auto& r : resources_)
        if (r.name == name) return &r;
    return nullptr;
}

void Scene::goHome() { camera_.setPose(globe::poseFromViewpoint(desc_.viewpoint)); }

std::optional<double> Scene::heightAt(double lonDeg, double latDeg) const {
    for (const auto& r : resources_)
        if (r.visible && r.layer->prepared())
            if (auto h = r.layer->groundHeightAt(lonDeg, latDeg)) return h;
    return std::nullopt;
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

bool Scene::busy() const {
    for (const auto& r : resources_)
        if (r.visible && r.layer->prepared() && r.layer->busy()) return true;
    return false;
}

}  // namespace orbis::scene
