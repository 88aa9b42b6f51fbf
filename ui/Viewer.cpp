#include "ui/Viewer.h"

#include "base/Log.h"
#include "engine/gpu/VkCheck.h"
#include "engine/scene/SceneSave.h"
#include "layers/BuiltinLayers.h"
#include "ui/InputScript.h"

#include <imgui.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>

namespace orbis::ui {
namespace {

/// Longest sleep in the event wait while idle (loads finishing on workers are noticed by then).
constexpr double kIdleWaitSeconds = 0.25;
/// The longest step of the clock when frames come slowly: a stall is not a jump in the animation.
constexpr double kMaxFrameSeconds = 0.25;

/// Set by SIGINT / SIGTERM: the viewer closes as if its window had been closed (the panel
/// layout is written, the device is idle before it goes), within one idle wait.
volatile std::sig_atomic_t gStopRequested = 0;

void installStopSignals() {
    gStopRequested = 0;
    std::signal(SIGINT, [](int) { gStopRequested = 1; });
    std::signal(SIGTERM, [](int) { gStopRequested = 1; });
}

/// Where an interactive session keeps the panels' layout: $XDG_CONFIG_HOME/orbis (or
/// ~/.config/orbis)/viewer-layout.ini; nothing when there is no such folder and it cannot be
/// made. Scripted sessions keep none, so that their pictures never depend on an earlier session.
std::filesystem::path panelLayoutFile() {
    std::filesystem::path base;
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) base = xdg;
    else if (const char* home = std::getenv("HOME"); home && *home) base = std::filesystem::path(home) / ".config";
    else return {};
    std::error_code ec;
    std::filesystem::create_directories(base / "orbis", ec);
    if (ec) {
        log::warn("viewer: the panel layout is not kept (", (base / "orbis").string(), ": ", ec.message(), ")");
        return {};
    }
    return base / "orbis" / "viewer-layout.ini";
}

gpu::InstanceOptions instanceOptions(const ViewerOptions& options) {
    gpu::InstanceOptions io;
    io.validation = options.validation;
    io.extensions = Window::requiredInstanceExtensions();
    return io;
}

gpu::DeviceOptions deviceOptions(const ViewerOptions& options, VkSurfaceKHR surface) {
    gpu::DeviceOptions dopt;
    dopt.select = options.device;
    dopt.surface = surface;
    return dopt;
}

std::string windowTitle(const scene::SceneDesc& desc, const std::filesystem::path& file) {
    return "Orbis - " + (desc.name.empty() ? file.filename().string() : desc.name);
}

}  // namespace

int runViewer(const ViewerOptions& options) {
    auto desc = scene::parseSceneFile(options.scene);
    if (!desc) {
        Viewer::printError(desc.message());
        return 1;
    }
    std::optional<ScriptPlayer> script;
    if (!options.script.empty()) {
        auto steps = readInputScript(options.script);
        if (!steps) {
            Viewer::printError(steps.message());
            return 1;
        }
        script.emplace(std::move(steps).value(), options.script);
    }
    try {
        Viewer viewer(options, windowTitle(*desc, options.scene), std::move(script));
        if (auto loaded = viewer.load(std::move(desc).value()); !loaded) {
            Viewer::printError(loaded.message());
            return 1;
        }
        return viewer.run();
    } catch (const std::exception& e) {
        Viewer::printError(e.what());
        return 1;
    }
}

void Viewer::printError(const std::string& message) { std::fprintf(stderr, "orbis: %s\n", message.c_str()); }

Viewer::Viewer(const ViewerOptions& options, const std::string& title, std::optional<ScriptPlayer> script)
    : options_(options),
      script_(std::move(script)),
      instance_(instanceOptions(options)),
      window_(title, int(options.width), int(options.height)),
      surface_(window_.createSurface(instance_.vk())),
      device_(instance_, deviceOptions(options, surface_)) {
    installInputCallbacks(window_.glfw(), sink_);   // before ImGui's, which chain to them
    layers::registerBuiltinLayers(registry_);
}

Result<void> Viewer::load(scene::SceneDesc desc) {
    auto built = scene::Scene::build(std::move(desc), registry_, {.keepGoing = true});
    if (!built) return built.error();
    scene_ = std::move(built).value();
    window_.framebufferSize(fbWidth_, fbHeight_);
    renderer_ = std::make_unique<render::Renderer>(device_, std::max(fbWidth_, 1u), std::max(fbHeight_, 1u));
    uiScale_ = window_.contentScale();
    gui_ = std::make_unique<Gui>(device_, window_.glfw(), uiScale_, script_ ? std::filesystem::path() : panelLayoutFile());
    swapchain_ = std::make_unique<Swapchain>(device_, surface_, options_.vsync);
    setUpPanels();
    setUpNavigation();
    stats_.vsync = swapchain_->vsync();
    stats_.device = device_.info().name;
    return {};
}

void Viewer::setUpPanels() {
    if (!options_.panels) panels_.toggleVisible();
    const std::filesystem::path& scene = options_.scene;
    panels_.setSavePath(options_.saveTo.empty() ? (scene.parent_path() / (scene.stem().string() + "-view.json")).string()
                                                : options_.saveTo.string());
    panels_.processes().setUp(options_.wpsServers, options_.resultsFolder);
}

void Viewer::setUpNavigation() {
    ground_ = [this](double lon, double lat) { return scene_->heightAt(lon, lat); };
    nav_.setHeightQuery(ground_);
    nav_.setFovYRad(scene_->camera().verticalFovRad());
    nav_.setHomeViewpoint(scene_->desc().viewpoint);
    nav_.setPose(scene_->camera().pose());
    window_.size(windowWidth_, windowHeight_);
    nav_.handle(ViewportSize{double(windowWidth_), double(windowHeight_)});
}

int Viewer::run() {
    last_ = Clock::now();
    scene_->time().advance(0.0);
    installStopSignals();
    try {
        while (!quit_ && !window_.shouldClose() && !gStopRequested)
            if (!runFrame()) return 1;
    } catch (const gpu::GpuError& e) {
        if (!device_.lost()) throw;
        return deviceLost(e.what());
    }
    return finish();
}

int Viewer::deviceLost(const std::string& what) {
    printError("the GPU device was lost: " + what);
    const std::filesystem::path to = panels_.savePath();
    if (auto saved = scene::saveScene(*scene_, to); !saved) {
        printError("the view could not be saved: " + saved.message());
    } else {
        printError("the view (camera, time, layers and their settings) is saved to " + to.string() +
                   ": open it again with orbis view " + to.string());
    }
    return kDeviceLostExit;
}

/// One turn of the loop: wait or poll, the input (the window's, then the script's), the clock,
/// the panels, the picture, and the files the frame asked for.
bool Viewer::runFrame() {
    const bool idleStep = script_ && script_->idling();
    const bool playingScript = script_ && script_->playing();
    const bool wantFrame = wantsFrame(playingScript);
    Window::pollEvents(!wantFrame, kIdleWaitSeconds);

    FrameRequests requests;
    FrameInput input = takeWindowInput();
    applyShortcuts(input, requests);
    if (idleStep) {
        script_->idle();
        if (!wantFrame && input.events.empty()) return true;   // asleep, as a user's viewer would be
    }
    if (playingScript) {   // a script owns the input while it plays
        auto played = script_->play(panels_, [this] { return !scene_->busy() && !nav_.animating() && !analysisBusy(); });
        if (!played) {
            printError(played.message());
            return false;
        }
        input = std::move(played).value();
        applyShortcuts(input, requests);
    }
    dispatch(input.events);

    window_.framebufferSize(fbWidth_, fbHeight_);
    if (fbWidth_ == 0 || fbHeight_ == 0) return true;   // minimised: nothing to draw into
    advance();
    updateReadout();
    drawPanels(requests);
    // A script expects its files: one that cannot be written ends the session.
    if (requests.saveScene && !saveScene() && script_) return false;
    const auto frame = drawFrame(requests.screenshot);
    if (resultRequested_ && frame && !scene_->busy()) {
        // The processing round trip: Run pressed to the result's layer drawn, loaded.
        std::printf("result on screen %.2f s after Run (%llu frames after its layer was added)\n",
                    std::chrono::duration<double>(Clock::now() - *resultRequested_).count(),
                    static_cast<unsigned long long>(stats_.framesDrawn - framesAtResult_));
        std::fflush(stdout);
        resultRequested_.reset();
    }
    if (frame && requests.screenshot && !writeScreenshot(*frame, requests.screenshotFile) && script_) return false;
    return true;
}

/// Whether this turn draws: something changed, moves, plays or loads, a live feed shows, or the
/// script plays.
bool Viewer::wantsFrame(bool playingScript) const {
    bool live = false;   // live video runs on the wall clock, whatever the scene's time does
    for (const scene::Resource& r : scene_->resources()) live |= r.visible && r.layer && r.layer->asLiveFeed();
    const bool animating = live || nav_.animating() || scene_->time().playing() || scene_->busy() || analysisBusy() ||
                           scene_->cameraMode().mode != scene::CameraMode::Free || nav_.revision() != drawnRevision_;
    return dirty_ || uiFrames_ > 0 || animating || playingScript;
}

/// The navigation, the camera and the scene's clock: a script's fixed step, else the wall time.
void Viewer::advance() {
    const auto now = Clock::now();
    const double dt = script_ && !script_->done() ? ScriptPlayer::kFrameSeconds
                                                  : std::min(kMaxFrameSeconds, std::chrono::duration<double>(now - last_).count());
    last_ = now;
    nav_.advance(dt);
    if (scene_->cameraMode().mode == scene::CameraMode::Free) scene_->camera().setPose(nav_.pose());
    scene_->time().advance(dt);
}

/// Read-outs for the status line and the map furniture.
void Viewer::updateReadout() {
    const globe::Pose pose = scene_->camera().pose();
    readout_.headingDeg = compassHeadingDeg(pose);
    readout_.eyeHeightM = globe::Ellipsoid::wgs84().toGeodetic(pose.position).height;
    if (auto g = nav_.groundUnderCursor()) {
        readout_.lonDeg = g->geodetic.lonDeg;
        readout_.latDeg = g->geodetic.latDeg;
        readout_.heightM = g->geodetic.height;
    } else {
        readout_.lonDeg.reset();
        readout_.latDeg.reset();
        readout_.heightM.reset();
    }
    readout_.scaleBarPixels = 0.0;
    const double w = windowWidth_, h = windowHeight_;
    // The scale bar measures the ground 60 px above the bottom, where it is drawn.
    if (auto mpp = metresPerPixel(pose, scene_->camera().verticalFovRad(), {w, h}, {0.5 * w, h - 60.0}, ground_))
        if (auto bar = niceScaleBar(*mpp, 150.0 * uiScale_)) {
            readout_.scaleBarMetres = bar->metres;
            readout_.scaleBarPixels = bar->widthPx;
        }
}

/// The ImGui frame and the panels (with the script's mouse while it plays), and their actions.
void Viewer::drawPanels(FrameRequests& requests) {
    if (script_ && !script_->done()) {
        const Gui::MouseOverride mouse = script_->mouse();
        gui_->newFrame(&mouse);
    } else {
        gui_->newFrame();
    }
    PanelActions actions = panels_.draw(*scene_, stats_, readout_, uiScale_);
    if (actions.changed) dirty_ = true;
    if (!actions.addLayers.empty()) addLayers(std::move(actions.addLayers));
    if (panels_.visible()) {
        // The sketch over the picture, in ImGui's units (window coordinates).
        const ImVec2 display = ImGui::GetIO().DisplaySize;
        const globe::Pose pose = scene_->camera().pose();
        const double fov = scene_->camera().verticalFovRad();
        const glm::dvec2 viewport(display.x, display.y);
        panels_.measure().drawOverlay(
            [&](const globe::Geodetic& g) { return projectToWindow(pose, fov, viewport, globe::Ellipsoid::wgs84().toEcef(g), 50.0); },
            [this](double lon, double lat) { return scene_->heightAt(lon, lat); });
    }
    if (actions.quit) quit_ = true;
    if (actions.home) nav_.flyHome();
    if (actions.flyTo) nav_.flyTo(*actions.flyTo);
    if (actions.clearPick) clearPicks();
    requests.screenshot = requests.screenshot || actions.screenshot;
    requests.saveScene = requests.saveScene || actions.saveScene;
}

bool Viewer::analysisBusy() const { return panels_.measure().busy() || panels_.processes().busy(); }

void Viewer::addLayers(std::vector<scene::LayerDesc> layers) {
    for (scene::LayerDesc& layer : layers) {
        auto added = scene_->addLayer(std::move(layer), registry_);
        if (!added) {
            readout_.message = added.message();
            printError(added.message());
            continue;
        }
        readout_.message = "added \"" + (*added)->name + "\"";
        resultRequested_ = panels_.processes().lastResultRequested();
        framesAtResult_ = stats_.framesDrawn;
        const double after = resultRequested_ ? std::chrono::duration<double>(Clock::now() - *resultRequested_).count() : 0.0;
        std::printf("added layer \"%s\" (%.2f s after Run)\n", (*added)->name.c_str(), after);
        std::fflush(stdout);
    }
    dirty_ = true;
}

/// After the loop: the device idle, a script's frame times, and validation's verdict.
int Viewer::finish() {
    vkDeviceWaitIdle(device_.vk());
    if (script_) script_->printFrameTimes(stats_.framesDrawn, fbWidth_, fbHeight_, device_.info().name);
    if (instance_.validationMessages() > 0) {
        std::fprintf(stderr, "orbis: validation reported %d message(s); first: %s\n", instance_.validationMessages(),
                     instance_.firstValidationMessage().c_str());
        return 1;
    }
    return 0;
}

}  // namespace orbis::ui
