#include "ui/Viewer.h"

#include "base/Log.h"
#include "base/Png.h"
#include "engine/gpu/Barriers.h"
#include "engine/gpu/Device.h"
#include "engine/gpu/Instance.h"
#include "engine/render/Renderer.h"
#include "engine/scene/LayerRegistry.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SceneDesc.h"
#include "engine/scene/SceneSave.h"
#include "layers/BuiltinLayers.h"
#include "ui/Gui.h"
#include "ui/InputScript.h"
#include "ui/InputSink.h"
#include "ui/Panels.h"
#include "ui/Swapchain.h"
#include "ui/Window.h"
#include "ui/input/MapTools.h"
#include "ui/input/NavigationController.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <csignal>
#include <cstdlib>
#include <variant>

namespace orbis::ui {
namespace {

using Clock = std::chrono::steady_clock;

/// A fixed frame time while a script plays: the same script gives the same pictures.
constexpr double kScriptFrameSeconds = 1.0 / 30.0;
/// Longest sleep in the event wait while idle (loads finishing on workers are noticed by then).
constexpr double kIdleWaitSeconds = 0.25;
constexpr double kSettleTimeoutSeconds = 300.0;

/// Set by SIGINT / SIGTERM: the viewer closes as if its window had been closed (the panel
/// layout is written, the device is idle before it goes), within one idle wait.
volatile std::sig_atomic_t gStopRequested = 0;

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

double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// Plays an input script: one step's events per frame, and the mouse ImGui should see.
class ScriptPlayer {
public:
    explicit ScriptPlayer(std::vector<ScriptStep> steps) : steps_(std::move(steps)) {}
    bool done() const { return index_ >= steps_.size(); }
    const ScriptStep* current() const { return done() ? nullptr : &steps_[index_]; }
    int frameInStep() const { return frame_; }
    void nextFrame() { ++frame_; }
    void finishStep() {
        ++index_;
        frame_ = 0;
    }
    double scriptTime() const { return time_; }
    void tick() { time_ += kScriptFrameSeconds; }

    glm::dvec2 mouse{0.0};
    bool buttons[3] = {false, false, false};

private:
    std::vector<ScriptStep> steps_;
    size_t index_ = 0;
    int frame_ = 0;
    double time_ = 1000.0;   // press times for double clicks, on the script's own clock
};

}  // namespace

int runViewer(const ViewerOptions& options) {
    auto desc = scene::parseSceneFile(options.scene);
    if (!desc) {
        std::fprintf(stderr, "orbis: %s\n", desc.message().c_str());
        return 1;
    }
    std::optional<ScriptPlayer> script;
    if (!options.script.empty()) {
        auto steps = readInputScript(options.script);
        if (!steps) {
            std::fprintf(stderr, "orbis: %s\n", steps.message().c_str());
            return 1;
        }
        script.emplace(std::move(steps).value());
    }

    try {
        gpu::InstanceOptions io;
        io.validation = options.validation;
        io.extensions = Window::requiredInstanceExtensions();
        gpu::Instance instance(io);
        Window window("Orbis - " + (desc->name.empty() ? options.scene.filename().string() : desc->name),
                      int(options.width), int(options.height));
        InputSink sink;
        installInputCallbacks(window.glfw(), sink);   // before ImGui's, which chain to them
        gpu::DeviceOptions dopt;
        dopt.select = options.device;
        dopt.surface = window.createSurface(instance.vk());
        gpu::Device device(instance, dopt);

        scene::LayerRegistry registry;
        layers::registerBuiltinLayers(registry);
        // A layer that fails to load shows its error in the panel; the others load.
        auto built = scene::Scene::build(std::move(desc).value(), registry, {.keepGoing = true});
        if (!built) {
            std::fprintf(stderr, "orbis: %s\n", built.message().c_str());
            return 1;
        }
        std::unique_ptr<scene::Scene> scene = std::move(built).value();
        uint32_t fbw = 0, fbh = 0;
        window.framebufferSize(fbw, fbh);
        render::Renderer renderer(device, std::max(fbw, 1u), std::max(fbh, 1u));
        const float uiScale = window.contentScale();
        Gui gui(device, window.glfw(), uiScale, script ? std::filesystem::path() : panelLayoutFile());
        Swapchain swapchain(device, dopt.surface, options.vsync);
        Panels panels;
        if (!options.panels) panels.toggleVisible();
        panels.setSavePath(options.saveTo.empty()
                               ? (options.scene.parent_path() / (options.scene.stem().string() + "-view.json")).string()
                               : options.saveTo.string());

        NavigationController nav;
        const HeightQuery ground = [&scene](double lon, double lat) { return scene->heightAt(lon, lat); };
        nav.setHeightQuery(ground);
        nav.setFovYRad(scene->camera().verticalFovRad());
        nav.setHomeViewpoint(scene->desc().viewpoint);
        nav.setPose(scene->camera().pose());
        int ww = 0, wh = 0;
        glfwGetWindowSize(window.glfw(), &ww, &wh);
        nav.handle(ViewportSize{double(ww), double(wh)});

        MapReadout readout;
        // Placing a pin: the press of the click that places it, and the placing itself.
        std::optional<glm::dvec2> pinPress;
        auto placePin = [&](const std::string& name, glm::dvec2 atPx) {
            const glm::dvec2 ndc(2.0 * atPx.x / std::max(ww, 1) - 1.0, 2.0 * atPx.y / std::max(wh, 1) - 1.0);
            const auto hit = pick(scene->camera().pose(), scene->camera().verticalFovRad(), double(ww) / std::max(wh, 1), ndc,
                                  ground);
            if (!hit) {
                readout.message = "no ground there: the pin needs a point on the globe";
                return;
            }
            scene::Annotation a;
            a.name = name.empty() ? "Pin " + std::to_string(scene->annotations().size() + 1) : name;
            a.lonDeg = hit->geodetic.lonDeg;
            a.latDeg = hit->geodetic.latDeg;
            a.height = hit->geodetic.height;
            scene->annotations().push_back(a);
            if (auto ok = scene->ensureAnnotationLayer(registry); !ok) {
                readout.message = ok.message();
                std::fprintf(stderr, "orbis: %s\n", ok.message().c_str());
            } else {
                char text[160];
                std::snprintf(text, sizeof text, "placed \"%s\" at lon %.5f lat %.5f", a.name.c_str(), a.lonDeg, a.latDeg);
                readout.message = text;
            }
            panels.stopPlacingPin(true);
        };

        ViewerStats stats;
        stats.vsync = swapchain.vsync();
        stats.device = device.info().name;
        std::optional<render::FrameResult> previous;
        std::vector<double> frameMs;   // a script's session prints their median at the end
        uint64_t drawnRevision = ~0ull;
        int uiFrames = 2;
        bool dirty = true;
        auto last = Clock::now();
        Clock::time_point idleUntil{}, settleStart{};
        double idleCpuStart = 0.0;
        bool quit = false;
        scene->time().advance(0.0);

        gStopRequested = 0;
        std::signal(SIGINT, [](int) { gStopRequested = 1; });
        std::signal(SIGTERM, [](int) { gStopRequested = 1; });
        while (!quit && !window.shouldClose() && !gStopRequested) {
            const bool idleStep = script && !script->done() && script->current()->kind == ScriptStep::Kind::Idle;
            const bool playingScript = script && !script->done() && !idleStep;
            const bool animating = nav.animating() || scene->time().playing() || scene->busy() ||
                                   scene->cameraMode().mode != scene::CameraMode::Free || nav.revision() != drawnRevision;
            const bool wantFrame = dirty || uiFrames > 0 || animating || playingScript;
            Window::pollEvents(!wantFrame, kIdleWaitSeconds);

            // Input: the window's events, or the script's (one step's worth per frame).
            std::vector<InputEvent> events = std::move(sink.input.events);
            sink.input.events.clear();
            if (sink.resized) {
                sink.resized = false;
                dirty = true;
                glfwGetWindowSize(window.glfw(), &ww, &wh);
                nav.handle(ViewportSize{double(ww), double(wh)});
            }
            if (std::exchange(sink.focusLost, false)) nav.releaseAll();
            bool wantScreenshot = std::exchange(sink.input.screenshot, false);
            bool wantSave = std::exchange(sink.input.saveScene, false);
            if (std::exchange(sink.input.escape, false)) {
                if (panels.placingPin()) {
                    panels.stopPlacingPin(false);
                    dirty = true;
                } else {
                    quit = true;
                }
            }
            if (std::exchange(sink.input.togglePanels, false)) {
                panels.toggleVisible();
                dirty = true;
            }
            std::filesystem::path screenshotFile;
            if (idleStep) {
                const ScriptStep& step = *script->current();
                if (script->frameInStep() == 0) {
                    idleUntil = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step.seconds));
                    idleCpuStart = processCpuSeconds();
                    script->nextFrame();
                } else if (Clock::now() >= idleUntil) {
                    const double cpu = processCpuSeconds() - idleCpuStart;
                    std::printf("idle: %.3f s of CPU over %.1f s (%.1f %% of one core)\n", cpu, step.seconds,
                                100.0 * cpu / step.seconds);
                    std::fflush(stdout);
                    script->finishStep();
                }
                if (!wantFrame && events.empty()) continue;
            }
            if (playingScript) {
                events.clear();   // a script owns the input while it plays
                const ScriptStep& step = *script->current();
                const int f = script->frameInStep();
                auto press = [&](MouseButton b, bool down, glm::dvec2 at) {
                    MouseButtonEvent e;
                    e.button = b;
                    e.pressed = down;
                    e.position = at;
                    e.timeSeconds = script->scriptTime();
                    events.push_back(e);
                    script->buttons[int(b)] = down;
                };
                auto moveTo = [&](glm::dvec2 at) {
                    script->mouse = at;
                    events.push_back(MouseMoveEvent{at});
                };
                bool finished = true;
                // Pointer steps move the mouse on their first frame and act from the next, as a hand
                // does: ImGui decides whether it owns the mouse from where it was last frame.
                // A step on a panel item: its rectangle, or a clear error when the panels show none.
                auto itemRect = [&](const std::string& label) {
                    auto r = panels.itemRect(label);
                    if (!r)
                        std::fprintf(stderr, "orbis: %s: the panels show no item \"%s\"\n", options.script.string().c_str(),
                                     label.c_str());
                    return r;
                };
                glm::dvec2 from(step.from[0], step.from[1]), to(step.to[0], step.to[1]);
                if (step.kind == ScriptStep::Kind::Drag && !step.item.empty()) {   // fractions of the item
                    const auto r = itemRect(step.item);
                    if (!r) return 1;
                    const glm::dvec2 lo((*r)[0], (*r)[1]), size((*r)[2] - (*r)[0], (*r)[3] - (*r)[1]);
                    from = lo + from * size;
                    to = lo + to * size;
                }
                switch (step.kind) {
                    case ScriptStep::Kind::Drag: {
                        const MouseButton b = step.button == "right" ? MouseButton::Right
                                              : step.button == "middle" ? MouseButton::Middle
                                                                         : MouseButton::Left;
                        finished = false;
                        if (f == 0) moveTo(from);
                        else if (f == 1) press(b, true, from);
                        else if (f <= step.frames + 1) moveTo(from + (to - from) * (double(f - 1) / step.frames));
                        else {
                            press(b, false, to);
                            finished = true;
                        }
                        break;
                    }
                    case ScriptStep::Kind::Scroll:
                        if (f == 0) {
                            moveTo(from);
                            finished = false;
                        } else {
                            events.push_back(ScrollEvent{0.0, step.lines});
                        }
                        break;
                    case ScriptStep::Kind::Key:
                        if (step.key == "F12") wantScreenshot = true;
                        else if (step.key == "Ctrl+S") wantSave = true;
                        else if (step.key == "F1") panels.toggleVisible();
                        else if (step.key == "Escape") {
                            if (panels.placingPin()) panels.stopPlacingPin(false);
                            else quit = true;
                        }
                        else if (auto k = navigationKey(step.key)) {
                            if (f == 0) events.push_back(KeyEvent{*k, true, {}});
                            if (f + 1 >= step.frames) events.push_back(KeyEvent{*k, false, {}});
                            finished = f + 1 >= step.frames;
                        }
                        break;
                    case ScriptStep::Kind::DoubleClick:
                        if (f == 0) {
                            moveTo(from);
                            finished = false;
                        } else {
                            press(MouseButton::Left, true, from);
                            press(MouseButton::Left, false, from);
                            press(MouseButton::Left, true, from);
                            press(MouseButton::Left, false, from);
                        }
                        break;
                    case ScriptStep::Kind::Click: {
                        glm::dvec2 at = from;
                        if (!step.item.empty()) {
                            const auto r = itemRect(step.item);
                            if (!r) return 1;
                            at = {0.5 * ((*r)[0] + (*r)[2]), 0.5 * ((*r)[1] + (*r)[3])};
                        }
                        // Down on one frame, up on the next, as ImGui needs to see a click.
                        if (f == 0) moveTo(at);
                        else if (f == 1) press(MouseButton::Left, true, at);
                        else press(MouseButton::Left, false, at);
                        finished = f >= 2;
                        break;
                    }
                    case ScriptStep::Kind::Settle:
                        if (f == 0) settleStart = Clock::now();
                        finished = f >= 2 && !scene->busy() && !nav.animating();
                        if (!finished && Clock::now() - settleStart > std::chrono::seconds(int(kSettleTimeoutSeconds))) {
                            log::warn("script: still loading after ", kSettleTimeoutSeconds, " s");
                            finished = true;
                        }
                        break;
                    case ScriptStep::Kind::Screenshot:
                        wantScreenshot = true;
                        screenshotFile = step.file;
                        break;
                    case ScriptStep::Kind::Quit: quit = true; break;
                    case ScriptStep::Kind::Idle: break;
                }
                if (finished) script->finishStep();
                else script->nextFrame();
                script->tick();
            }

            // Events to the navigation, unless ImGui has them (releases always pass: drags end).
            // While a pin is being placed, a left click on the globe places it instead.
            for (const InputEvent& e : events) {
                dirty = true;
                uiFrames = 2;
                std::visit(
                    [&](const auto& ev) {
                        using T = std::decay_t<decltype(ev)>;
                        if constexpr (std::is_same_v<T, MouseButtonEvent>) {
                            if (ev.pressed && gui.wantsMouse()) return;
                            if (ev.button == MouseButton::Left && panels.placingPin()) {
                                if (ev.pressed) {
                                    pinPress = ev.position;
                                } else if (pinPress && glm::length(ev.position - *pinPress) <= 4.0) {
                                    placePin(*panels.placingPin(), ev.position);
                                    pinPress.reset();
                                }
                                return;
                            }
                        } else if constexpr (std::is_same_v<T, ScrollEvent>) {
                            if (gui.wantsMouse()) return;
                        } else if constexpr (std::is_same_v<T, KeyEvent>) {
                            if (ev.pressed && gui.wantsKeyboard()) return;
                        }
                        if constexpr (!std::is_same_v<T, MouseMoveEvent>)
                            if (scene->cameraMode().mode != scene::CameraMode::Free) {
                                // The user takes the camera from a mode that was moving it.
                                nav.setPose(scene->camera().pose());
                                scene->setCameraMode(scene::CameraModeSettings{});
                            }
                        nav.handle(ev);
                    },
                    e);
            }

            window.framebufferSize(fbw, fbh);
            if (fbw == 0 || fbh == 0) continue;   // minimised: nothing to draw into
            const auto now = Clock::now();
            const double dt = script && !script->done() ? kScriptFrameSeconds
                                                        : std::min(0.25, std::chrono::duration<double>(now - last).count());
            last = now;
            nav.advance(dt);
            if (scene->cameraMode().mode == scene::CameraMode::Free) scene->camera().setPose(nav.pose());
            scene->time().advance(dt);

            // Read-outs for the status line and the map furniture.
            const globe::Pose pose = scene->camera().pose();
            readout.headingDeg = compassHeadingDeg(pose);
            readout.eyeHeightM = globe::Ellipsoid::wgs84().toGeodetic(pose.position).height;
            if (auto g = nav.groundUnderCursor()) {
                readout.lonDeg = g->geodetic.lonDeg;
                readout.latDeg = g->geodetic.latDeg;
                readout.heightM = g->geodetic.height;
            } else {
                readout.lonDeg.reset();
                readout.latDeg.reset();
                readout.heightM.reset();
            }
            readout.scaleBarPixels = 0.0;
            if (auto mpp = metresPerPixel(pose, scene->camera().verticalFovRad(), {double(ww), double(wh)},
                                          {0.5 * ww, double(wh) - 60.0}, ground))
                if (auto bar = niceScaleBar(*mpp, 150.0 * uiScale)) {
                    readout.scaleBarMetres = bar->metres;
                    readout.scaleBarPixels = bar->widthPx;
                }

            if (script && !script->done()) {
                Gui::MouseOverride mouse{float(script->mouse.x), float(script->mouse.y)};
                for (int b = 0; b < 3; ++b) mouse.buttons[b] = script->buttons[b];
                gui.newFrame(&mouse);
            } else {
                gui.newFrame();
            }
            const PanelActions actions = panels.draw(*scene, stats, readout, uiScale);
            if (actions.changed) dirty = true;
            if (actions.quit) quit = true;
            if (actions.home) nav.flyHome();
            if (actions.flyTo) nav.flyTo(*actions.flyTo);
            wantScreenshot = wantScreenshot || actions.screenshot;
            wantSave = wantSave || actions.saveScene;
            if (wantSave) {
                const std::filesystem::path to = panels.savePath();
                if (auto ok = scene::saveScene(*scene, to); !ok) {
                    readout.message = ok.message();
                    std::fprintf(stderr, "orbis: %s\n", ok.message().c_str());
                    if (script) return 1;   // a script expects its files
                } else {
                    readout.message = "saved " + to.filename().string();
                    std::printf("wrote %s\n", to.string().c_str());
                    std::fflush(stdout);
                }
            }

            auto acquired = swapchain.acquire(fbw, fbh);
            if (!acquired) {
                gui.endFrameWithoutDrawing();
                continue;
            }
            renderer.resize(fbw, fbh);
            render::FrameHooks hooks;
            hooks.overlay = [&gui](VkCommandBuffer cmd, gpu::RenderTarget& target) { gui.record(cmd, target); };
            hooks.finish = [&acquired](VkCommandBuffer cmd, gpu::RenderTarget& target) {
                gpu::Image& dst = *acquired->image;
                const gpu::ImageTransition uses[] = {{&target.color(), gpu::ImageUse::TransferSrc},
                                                     {&dst, gpu::ImageUse::TransferDst}};
                gpu::transition(cmd, uses);
                VkImageBlit region{};
                region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.dstSubresource = region.srcSubresource;
                region.srcOffsets[1] = {int32_t(target.width()), int32_t(target.height()), 1};
                region.dstOffsets[1] = {int32_t(dst.extent().width), int32_t(dst.extent().height), 1};
                const bool same = target.width() == dst.extent().width && target.height() == dst.extent().height;
                vkCmdBlitImage(cmd, target.color().vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst.vk(),
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, same ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
                gpu::transition(cmd, dst, gpu::ImageUse::Present);
            };
            VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
            wait.semaphore = acquired->acquired;
            wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
            signal.semaphore = acquired->rendered;
            signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            hooks.waits = {wait};
            hooks.signals = {signal};

            const auto frameStart = Clock::now();
            const render::FrameResult frame = renderer.render(*scene, wantScreenshot, hooks);
            swapchain.present(*acquired, frame.timelineValue);
            drawnRevision = nav.revision();
            dirty = false;
            if (uiFrames > 0) --uiFrames;
            ++stats.framesDrawn;
            stats.cpuMs = frame.cpuMs;
            if (previous) stats.gpu = renderer.gpuTimes(*previous);
            previous = frame;
            stats.frameMs = std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count();
            if (frameMs.size() < 100000) frameMs.push_back(stats.frameMs);

            if (wantScreenshot) {
                if (screenshotFile.empty()) {
                    const auto stamp = std::chrono::duration_cast<std::chrono::seconds>(
                                           std::chrono::system_clock::now().time_since_epoch()).count();
                    screenshotFile = options.screenshotFolder / ("orbis-" + std::to_string(stamp) + ".png");
                }
                ImageRgba8 image{renderer.width(), renderer.height(), renderer.readPixels(frame)};
                if (auto ok = writePng(screenshotFile, image); !ok) {
                    readout.message = ok.message();
                    std::fprintf(stderr, "orbis: %s\n", ok.message().c_str());
                    if (script) return 1;
                } else {
                    readout.message = "saved " + screenshotFile.filename().string();
                    std::printf("wrote %s\n", screenshotFile.string().c_str());
                    std::fflush(stdout);
                }
            }
        }
        vkDeviceWaitIdle(device.vk());
        if (script && !frameMs.empty()) {
            std::sort(frameMs.begin(), frameMs.end());
            std::printf("frames: %llu drawn, %ux%u, frame ms median %.1f, p95 %.1f (%s)\n",
                        static_cast<unsigned long long>(stats.framesDrawn), fbw, fbh, frameMs[frameMs.size() / 2],
                        frameMs[frameMs.size() * 95 / 100], device.info().name.c_str());
        }
        if (instance.validationMessages() > 0) {
            std::fprintf(stderr, "orbis: validation reported %d message(s); first: %s\n", instance.validationMessages(),
                         instance.firstValidationMessage().c_str());
            return 1;
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "orbis: %s\n", e.what());
        return 1;
    }
}

}  // namespace orbis::ui
