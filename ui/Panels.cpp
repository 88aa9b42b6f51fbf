#include "ui/Panels.h"

#include "base/TimeFormat.h"
#include "engine/scene/Layer.h"
#include "engine/scene/Scene.h"
#include "ui/input/CurveEdit.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

namespace orbis::ui {
namespace {

constexpr size_t kHistory = 120;

std::string megabytes(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / (1024.0 * 1024.0));
    return text;
}

std::string distance(double metres) {
    char text[32];
    if (metres >= 1000.0) std::snprintf(text, sizeof text, "%g km", metres / 1000.0);
    else std::snprintf(text, sizeof text, "%g m", metres);
    return text;
}

/// A curve over a colour strip (a transfer function's opacity): click to add a point, drag a
/// point to move it, right-click a point to remove it. True when the layer took a change.
bool curveWidget(scene::LiveSettings& layer, const scene::LayerSetting& s, const std::string& label,
                 const std::function<void()>& remember) {
    const float k = ImGui::GetIO().FontGlobalScale;
    ImGui::TextUnformatted(s.label.c_str());
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 size(std::max(ImGui::GetContentRegionAvail().x, 40.0f * k), 70.0f * k);
    const ImGuiID id = ImGui::GetID(label.c_str());
    ImGui::InvisibleButton(label.c_str(), size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    remember();
    const CurveFrame frame{s.min, s.max, {origin.x, origin.y}, {size.x, size.y}};
    const glm::dvec2 mouse(ImGui::GetIO().MousePos.x, ImGui::GetIO().MousePos.y);
    const double reach = 7.0 * k;

    std::vector<glm::dvec2> points = s.points;
    ImGuiStorage* storage = ImGui::GetStateStorage();
    int dragging = storage->GetInt(id, -1);
    bool changed = false;
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (auto hit = pointUnder(points, frame, mouse, reach)) {
            dragging = int(*hit);
        } else {
            dragging = int(insertPoint(points, pixelsToCurve(frame, mouse)));
            changed = true;
        }
    } else if (ImGui::IsItemActive() && dragging >= 0 && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0.0f)) {
        changed = movePoint(points, size_t(dragging), pixelsToCurve(frame, mouse));
    }
    if (!ImGui::IsItemActive()) dragging = -1;
    if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Right))
        if (auto hit = pointUnder(points, frame, mouse, reach)) changed = removePoint(points, *hit) || changed;
    storage->SetInt(id, dragging);
    if (ImGui::IsItemHovered() && dragging < 0)
        ImGui::SetTooltip("click: add a point   drag: move it   right-click: remove it\nvalue %.4g  alpha %.3f",
                          pixelsToCurve(frame, mouse).x, pixelsToCurve(frame, mouse).y);

    // The colour map behind, the curve (flat beyond its ends) and its handles.
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 end(origin.x + size.x, origin.y + size.y);
    const size_t n = s.gradient.size();
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3& c = s.gradient[i];
        dl->AddRectFilled(ImVec2(origin.x + size.x * float(i) / float(n), origin.y),
                          ImVec2(origin.x + size.x * float(i + 1) / float(n), end.y),
                          ImGui::GetColorU32(ImVec4(c.r, c.g, c.b, 1.0f)));
    }
    if (n == 0) dl->AddRectFilled(origin, end, IM_COL32(40, 40, 40, 255));
    dl->AddRect(origin, end, IM_COL32(200, 200, 200, 255));
    if (!points.empty()) {
        std::vector<ImVec2> line;
        const glm::dvec2 first = curveToPixels(frame, points.front()), last = curveToPixels(frame, points.back());
        line.emplace_back(origin.x, float(first.y));
        for (const glm::dvec2& p : points) {
            const glm::dvec2 px = curveToPixels(frame, p);
            line.emplace_back(float(px.x), float(px.y));
        }
        line.emplace_back(end.x, float(last.y));
        dl->PushClipRect(origin, end, true);
        dl->AddPolyline(line.data(), int(line.size()), IM_COL32(0, 0, 0, 255), 0, 3.0f * k);
        dl->AddPolyline(line.data(), int(line.size()), IM_COL32(255, 255, 255, 255), 0, 1.5f * k);
        for (size_t i = 0; i < points.size(); ++i) {
            const glm::dvec2 px = curveToPixels(frame, points[i]);
            dl->AddCircleFilled(ImVec2(float(px.x), float(px.y)), 4.0f * k,
                                int(i) == dragging ? IM_COL32(255, 200, 60, 255) : IM_COL32(255, 255, 255, 255));
            dl->AddCircle(ImVec2(float(px.x), float(px.y)), 4.0f * k, IM_COL32(0, 0, 0, 255));
        }
        dl->PopClipRect();
    }
    return changed && layer.setCurve(s.name, points);
}

/// One generic widget per live setting; true when the user changed it.
/// `remember` notes the last item for scripts, as "<setting>##<resource>".
bool settingWidget(scene::LiveSettings& layer, const scene::LayerSetting& s, const std::string& id,
                   const std::function<void()>& remember) {
    using Kind = scene::LayerSetting::Kind;
    const std::string label = s.label + "##" + id + s.name;
    switch (s.kind) {
        case Kind::Toggle: {
            bool on = s.value != 0.0;
            if (ImGui::Checkbox(label.c_str(), &on)) return layer.setParameter(s.name, on ? 1.0 : 0.0);
            return false;
        }
        case Kind::Integer: {   // as a double: budgets go past 2^31
            double v = std::round(s.value);
            const ImGuiSliderFlags flags = s.logarithmic ? ImGuiSliderFlags_Logarithmic : 0;
            if (ImGui::SliderScalar(label.c_str(), ImGuiDataType_Double, &v, &s.min, &s.max, "%.0f", flags))
                return layer.setParameter(s.name, std::round(v));
            return false;
        }
        case Kind::Number: {
            float v = float(s.value);
            const ImGuiSliderFlags flags = s.logarithmic ? ImGuiSliderFlags_Logarithmic : 0;
            if (ImGui::SliderFloat(label.c_str(), &v, float(s.min), float(s.max), "%.3g", flags))
                return layer.setParameter(s.name, double(v));
            return false;
        }
        case Kind::Choice: {
            bool changed = false;
            if (ImGui::BeginCombo(label.c_str(), s.choice.c_str())) {
                for (const std::string& c : s.choices)
                    if (ImGui::Selectable(c.c_str(), c == s.choice) && c != s.choice) changed = layer.setOption(s.name, c);
                ImGui::EndCombo();
            }
            return changed;
        }
        case Kind::Curve: return curveWidget(layer, s, label, remember);
    }
    return false;
}

}  // namespace

void Panels::remember(const std::string& label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    items_.push_back({label, {a.x, a.y, b.x, b.y}});
}

std::optional<std::array<float, 4>> Panels::itemRect(const std::string& label) const {
    for (const Item& i : items_)
        if (i.label == label) return i.rect;
    return std::nullopt;
}

void Panels::setSavePath(const std::string& path) {
    std::snprintf(savePath_, sizeof savePath_, "%s", path.c_str());
}

PanelActions Panels::draw(scene::Scene& scene, const ViewerStats& stats, const MapReadout& map, float uiScale) {
    PanelActions actions;
    items_.clear();
    history_.push_back(float(stats.frameMs));
    while (history_.size() > kHistory) history_.pop_front();

    if (!visible_) return actions;   // F1: a clean view (screenshots); the keys still work
    if (ImGui::BeginMainMenuBar()) {
        if (ImGui::BeginMenu("File")) {
            if (ImGui::MenuItem("Save screenshot", "F12")) actions.screenshot = true;
            if (ImGui::MenuItem("Save scene", "Ctrl+S")) actions.saveScene = true;
            if (ImGui::MenuItem("Save scene as...")) openSaveAs_ = true;
            ImGui::Separator();
            if (ImGui::MenuItem("Quit", "Esc")) actions.quit = true;
            ImGui::EndMenu();
        }
        if (ImGui::BeginMenu("View")) {
            if (ImGui::MenuItem("Home", "Home")) actions.home = true;
            if (ImGui::MenuItem("Panels", "F1", visible_)) visible_ = !visible_;
            ImGui::EndMenu();
        }
        ImGui::EndMainMenuBar();
    }
    if (std::exchange(openSaveAs_, false)) ImGui::OpenPopup("Save scene as");
    if (ImGui::BeginPopupModal("Save scene as", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("The camera, time, layers and their settings, as a scene file:");
        ImGui::SetNextItemWidth(480 * uiScale);
        const bool enter = ImGui::InputText("##path", savePath_, sizeof savePath_, ImGuiInputTextFlags_EnterReturnsTrue);
        if (ImGui::Button("Save") || enter) {
            actions.saveScene = true;
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    resourcesPanel(scene, actions);
    timePanel(scene, actions);
    statsPanel(stats, scene);
    annotationsPanel(scene, actions);
    analysisPanel(scene, actions);
    feedsPanel(scene, actions);
    if (map.picked) featurePanel(*map.picked, actions);
    mapFurniture(map, uiScale);
    return actions;
}

/// One window on the right for the drawing tools and measures, and the processing servers.
void Panels::analysisPanel(scene::Scene& scene, PanelActions& actions) {
    processes_.update(actions.addLayers, actions.changed);
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 350 * s, 180 * s), ImGuiCond_FirstUseEver);
    // As tall as its contents, up to the bottom of the window.
    ImGui::SetNextWindowSizeConstraints(ImVec2(340 * s, 0.0f), ImVec2(340 * s, std::max(200.0f * s, io.DisplaySize.y - 210 * s)));
    if (ImGui::Begin("Analysis", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        const RememberItem rememberItem = [this](const std::string& label) { remember(label); };
        const bool measure = ImGui::CollapsingHeader("Measure", ImGuiTreeNodeFlags_DefaultOpen);
        remember("Measure##analysis");
        if (measure) measure_.draw(scene, rememberItem, actions.changed);
        const bool processes = ImGui::CollapsingHeader("Processes", processes_.hasServers() ? ImGuiTreeNodeFlags_DefaultOpen : 0);
        remember("Processes##analysis");
        if (processes) processes_.draw(measure_.sketch(), scene.desc(), rememberItem);
    }
    ImGui::End();
    processes_.drawPlots();
}

void Panels::feedsPanel(scene::Scene& scene, PanelActions& actions) {
    std::vector<std::pair<const scene::Resource*, scene::FeedStatus>> feeds;
    for (const scene::Resource& r : scene.resources())
        if (r.layer && r.visible)
            if (const scene::LiveFeed* feed = r.layer->asLiveFeed()) feeds.emplace_back(&r, feed->feedStatus());
    if (feeds.empty()) return;
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 470 * s, io.DisplaySize.y - 190 * s), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Feeds", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return;
    }
    const scene::CameraModeSettings& mode = scene.cameraMode();
    if (ImGui::BeginTable("feeds", 8, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
        for (const char* h : {"Feed", "State", "Mbit/s", "Latency", "Shown", "Lost", "", ""}) ImGui::TableSetupColumn(h);
        ImGui::TableHeadersRow();
        for (const auto& [r, f] : feeds) {
            ImGui::PushID(r->name.c_str());
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(r->name.c_str());
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s%s%s", f.url.c_str(), f.lastError.empty() ? "" : "\n", f.lastError.c_str());
            ImGui::TableSetColumnIndex(1);
            const ImVec4 colour = f.state == "live" ? ImVec4(0.4f, 0.9f, 0.4f, 1.0f)
                                  : f.state == "no signal" ? ImVec4(1.0f, 0.45f, 0.35f, 1.0f)
                                                           : ImVec4(0.9f, 0.7f, 0.2f, 1.0f);
            if (f.state == "no signal") ImGui::TextColored(colour, "no signal %.0f s", f.secondsSinceData);
            else ImGui::TextColored(colour, "%s", f.state.c_str());
            ImGui::TableSetColumnIndex(2);
            ImGui::Text("%.2f", f.bitsPerSecond * 1e-6);
            ImGui::TableSetColumnIndex(3);
            if (f.latencySeconds) ImGui::Text("%.0f ms", *f.latencySeconds * 1e3);
            else ImGui::TextDisabled("-");
            ImGui::TableSetColumnIndex(4);
            ImGui::Text("%llu", (unsigned long long)f.framesShown);
            ImGui::TableSetColumnIndex(5);
            ImGui::Text("%llu", (unsigned long long)f.framesLost);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%llu damaged packets", (unsigned long long)f.damagedPackets);
            ImGui::TableSetColumnIndex(6);
            // Fly to the sensor (the camera stays above it as it moves), or look through it
            // (pilot): any input gives the camera back (ViewerInput).
            if (ImGui::SmallButton("Fly to")) {
                scene.setCameraMode({.mode = scene::CameraMode::Above, .target = r->name, .distance = 2500.0}, 2.0);
                actions.changed = true;
            }
            remember("Fly to feed##" + r->name);
            ImGui::SameLine();
            const bool through = mode.mode == scene::CameraMode::Pilot && mode.target == r->name;
            if (ImGui::SmallButton(through ? "Free" : "Sensor view")) {
                scene.setCameraMode(through ? scene::CameraModeSettings{}
                                            : scene::CameraModeSettings{.mode = scene::CameraMode::Pilot, .target = r->name},
                                    through ? 0.0 : 2.0);
                actions.changed = true;
            }
            remember("Sensor view##" + r->name);
            // Record the stream as received into a file next to the scene (plays back as "path").
            ImGui::TableSetColumnIndex(7);
            const bool recording = !f.recording.empty();
            if (recording) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.75f, 0.15f, 0.15f, 1.0f));
            if (ImGui::SmallButton(recording ? "Stop" : "Record")) {
                auto file = r->layer->asLiveFeed()->setRecording(!recording);
                feedMessage_ = file ? (recording ? "recorded " : "recording to ") + (recording ? f.recording : *file) : file.message();
            }
            if (recording) {
                ImGui::PopStyleColor();
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("recording to %s", f.recording.c_str());
            }
            remember("Record##" + r->name);
            ImGui::PopID();
        }
        ImGui::EndTable();
    }
    if (!feedMessage_.empty()) ImGui::TextWrapped("%s", feedMessage_.c_str());
    ImGui::End();
}

void Panels::featurePanel(const scene::PickedAttributes& picked, PanelActions& actions) {
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 330 * s, 180 * s), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(320 * s, 260 * s), ImGuiCond_FirstUseEver);
    bool open = true;
    if (!ImGui::Begin("Feature", &open)) {
        ImGui::End();
        if (!open) actions.clearPick = true;
        return;
    }
    ImGui::TextUnformatted(picked.layer.c_str());
    ImGui::TextDisabled("%s", picked.feature.c_str());
    if (ImGui::BeginTable("attributes", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_Resizable)) {
        for (const auto& [name, value] : picked.fields) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(name.c_str());
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(value.c_str());
        }
        ImGui::EndTable();
    }
    ImGui::End();
    if (!open) {
        actions.clearPick = true;
        actions.changed = true;
    }
}

void Panels::resourcesPanel(scene::Scene& scene, PanelActions& actions) {
    const float s = ImGui::GetIO().FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(10 * s, 30 * s), ImGuiCond_FirstUseEver);
    const float below = ImGui::GetIO().DisplaySize.y - 170 * s;   // leave the time panel free
    ImGui::SetNextWindowSize(ImVec2(330 * s, std::clamp(below - 30 * s, 120 * s, 420 * s)), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Resources")) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.45f);
    for (scene::Resource& r : scene.resources()) {
        ImGui::PushID(r.name.c_str());
        const std::string visLabel = "##visible" + r.name;
        const bool failed = !r.error.empty();
        if (failed) ImGui::BeginDisabled();
        if (ImGui::Checkbox(visLabel.c_str(), &r.visible)) actions.changed = true;
        if (failed) ImGui::EndDisabled();
        remember("Visible##" + r.name);
        ImGui::SameLine();
        const bool open = ImGui::TreeNodeEx(r.name.c_str(), ImGuiTreeNodeFlags_DefaultOpen, "%s  (%s)", r.name.c_str(),
                                            r.type.c_str());
        if (r.viewpoint) {
            ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 50 * ImGui::GetIO().FontGlobalScale);
            if (ImGui::SmallButton("Fly to")) actions.flyTo = r.viewpoint;
            remember("Fly to##" + r.name);
        }
        if (open) {
            if (failed) {
                ImGui::PushTextWrapPos(0.0f);
                ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "not loaded: %s", r.error.c_str());
                ImGui::PopTextWrapPos();
            } else if (r.layer) {
                const std::string status = r.layer->status();
                if (!status.empty()) ImGui::TextWrapped("%s", status.c_str());
                if (r.layer->busy()) ImGui::TextColored(ImVec4(0.9f, 0.7f, 0.2f, 1.0f), "loading...");
                if (scene::LiveSettings* live = r.layer->asLiveSettings())
                    for (const scene::LayerSetting& setting : live->liveSettings())
                        if (settingWidget(*live, setting, r.name, [&] { remember(setting.name + "##" + r.name); }))
                            actions.changed = true;
            }
            ImGui::TreePop();
        }
        ImGui::PopID();
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

void Panels::timePanel(scene::Scene& scene, PanelActions& actions) {
    scene::TimeServer& time = scene.time();
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(10 * s, io.DisplaySize.y - 120 * s), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(std::min(720 * s, io.DisplaySize.x - 20 * s), 90 * s), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Time")) {
        ImGui::End();
        return;
    }
    const double span = toSeconds(time.end() - time.start());
    if (ImGui::Button(time.playing() ? "Pause" : "Play")) {
        time.playing() ? time.pause() : time.play();
        actions.changed = true;
    }
    remember("Play");
    ImGui::SameLine();
    const TimeNs stepNs = fromSeconds(span > 0.0 ? std::max(span / 100.0, 0.04) : 1.0);
    if (ImGui::ArrowButton("back", ImGuiDir_Left)) {
        time.step(-stepNs);
        actions.changed = true;
    }
    ImGui::SameLine();
    if (ImGui::ArrowButton("forward", ImGuiDir_Right)) {
        time.step(stepNs);
        actions.changed = true;
    }
    ImGui::SameLine();
    bool loop = time.loop();
    if (ImGui::Checkbox("Loop", &loop)) time.setLoop(loop);
    ImGui::SameLine();
    float rate = float(time.rate());
    ImGui::SetNextItemWidth(110 * s);
    if (ImGui::DragFloat("Rate", &rate, 0.02f * std::max(1.0f, std::abs(rate)), -1e6f, 1e6f, "%.2fx")) time.setRate(rate);
    ImGui::SameLine();
    ImGui::TextUnformatted(formatIso8601(time.now(), 1).c_str());
    if (span > 0.0) {
        float at = float(toSeconds(time.now() - time.start()));
        ImGui::SetNextItemWidth(-1.0f);
        if (ImGui::SliderFloat("##seek", &at, 0.0f, float(span), "%.1f s")) {
            time.seek(time.start() + fromSeconds(at));
            actions.changed = true;
        }
    }
    ImGui::End();
}

void Panels::statsPanel(const ViewerStats& stats, const scene::Scene& scene) {
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 290 * s, 30 * s), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(280 * s, 300 * s), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);   // open it for the figures
    if (!ImGui::Begin("Stats")) {
        ImGui::End();
        return;
    }
    ImGui::TextUnformatted(stats.device.c_str());
    ImGui::Text("frame %.2f ms   cpu %.2f ms", stats.frameMs, stats.cpuMs);
    std::vector<float> h(history_.begin(), history_.end());
    float top = 1.0f;
    for (float v : h) top = std::max(top, v);
    ImGui::PlotLines("##frames", h.data(), int(h.size()), 0, nullptr, 0.0f, top * 1.1f, ImVec2(-1.0f, 40 * s));
    double gpuTotal = 0.0;
    for (const auto& p : stats.gpu) gpuTotal += p.ms;
    ImGui::Text("gpu %.2f ms", gpuTotal);
    for (const auto& p : stats.gpu) ImGui::BulletText("%s %.2f ms", p.name.c_str(), p.ms);
    ImGui::Separator();
    uint64_t gpuBytes = 0, cacheBytes = 0;
    for (const scene::Resource& r : scene.resources())
        if (const scene::LayerStats* layer = r.layer ? r.layer->asStats() : nullptr) {
            gpuBytes += layer->gpuBytes();
            cacheBytes += layer->cacheBytes();
        }
    ImGui::Text("layers: GPU %s, caches %s", megabytes(gpuBytes).c_str(), megabytes(cacheBytes).c_str());
    ImGui::Text("frames drawn %llu, vsync %s", static_cast<unsigned long long>(stats.framesDrawn), stats.vsync ? "on" : "off");
    ImGui::End();
}

std::optional<std::string> Panels::placingPin() const {
    if (!placing_) return std::nullopt;
    return std::string(pinName_);
}

void Panels::annotationsPanel(scene::Scene& scene, PanelActions& actions) {
    const ImGuiIO& io = ImGui::GetIO();
    const float s = io.FontGlobalScale;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 290 * s, 60 * s), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(280 * s, 110 * s), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Annotations")) {
        ImGui::End();
        return;
    }
    std::vector<scene::Annotation>& pins = scene.annotations();
    if (pinName_[0] == '\0' && !placing_) std::snprintf(pinName_, sizeof pinName_, "Pin %zu", pins.size() + 1);
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - 90 * s);
    ImGui::InputText("##pinName", pinName_, sizeof pinName_);
    ImGui::SameLine();
    if (ImGui::Button(placing_ ? "Cancel" : "Place pin", ImVec2(-1.0f, 0.0f))) placing_ = !placing_;
    remember("Place pin");
    if (placing_) ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.4f, 1.0f), "Click on the globe to place the pin.");
    std::optional<size_t> remove;
    for (size_t i = 0; i < pins.size(); ++i) {
        const scene::Annotation& a = pins[i];
        ImGui::PushID(int(i));
        ImGui::TextUnformatted(a.name.c_str());
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("lon %.6f  lat %.6f  height %.1f m", a.lonDeg, a.latDeg, a.height);
        ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 100 * s);
        if (ImGui::SmallButton("Fly to")) {
            globe::Viewpoint vp;
            vp.lonDeg = a.lonDeg;
            vp.latDeg = a.latDeg;
            vp.height = a.height;
            vp.headingDeg = 0.0;
            vp.pitchDeg = -45.0;
            vp.range = 8000.0;
            actions.flyTo = vp;
        }
        remember("Fly to##pin" + std::to_string(i));
        ImGui::SameLine();
        if (ImGui::SmallButton("Delete")) remove = i;
        remember("Delete##pin" + std::to_string(i));
        ImGui::PopID();
    }
    if (remove) {
        pins.erase(pins.begin() + std::ptrdiff_t(*remove));
        actions.changed = true;
    }
    ImGui::End();
}

void Panels::mapFurniture(const MapReadout& map, float uiScale) {
    const ImGuiIO& io = ImGui::GetIO();
    ImDrawList* dl = ImGui::GetForegroundDrawList();
    const float s = uiScale;
    // Compass, bottom right: the needle points to north on the screen.
    const ImVec2 c(io.DisplaySize.x - 50 * s, io.DisplaySize.y - 80 * s);
    const float r = 26 * s;
    const float a = float(-map.headingDeg * M_PI / 180.0);   // north turns left as the view turns right
    const ImVec2 tip(c.x + r * std::sin(a), c.y - r * std::cos(a));
    const ImVec2 tail(c.x - r * std::sin(a), c.y + r * std::cos(a));
    const ImVec2 side(0.25f * r * std::cos(a), 0.25f * r * std::sin(a));
    dl->AddCircleFilled(c, r + 6 * s, IM_COL32(0, 0, 0, 110));
    dl->AddTriangleFilled(tip, ImVec2(c.x + side.x, c.y + side.y), ImVec2(c.x - side.x, c.y - side.y), IM_COL32(220, 60, 50, 255));
    dl->AddTriangleFilled(tail, ImVec2(c.x - side.x, c.y - side.y), ImVec2(c.x + side.x, c.y + side.y), IM_COL32(230, 230, 230, 255));
    dl->AddText(ImVec2(tip.x - 4 * s, tip.y - 16 * s), IM_COL32(255, 255, 255, 255), "N");
    // Scale bar, bottom right beside the compass, above the status line.
    const float y = io.DisplaySize.y - 34 * s;
    if (map.scaleBarPixels > 0.0) {
        const float x1 = io.DisplaySize.x - 100 * s, x0 = x1 - float(map.scaleBarPixels);
        dl->AddRectFilled(ImVec2(x0 - 4 * s, y - 18 * s), ImVec2(x1 + 4 * s, y + 4 * s), IM_COL32(0, 0, 0, 110));
        dl->AddLine(ImVec2(x0, y), ImVec2(x1, y), IM_COL32(255, 255, 255, 255), 2 * s);
        dl->AddLine(ImVec2(x0, y - 6 * s), ImVec2(x0, y), IM_COL32(255, 255, 255, 255), 2 * s);
        dl->AddLine(ImVec2(x1, y - 6 * s), ImVec2(x1, y), IM_COL32(255, 255, 255, 255), 2 * s);
        dl->AddText(ImVec2(x0 + 2 * s, y - 17 * s), IM_COL32(255, 255, 255, 255), distance(map.scaleBarMetres).c_str());
    }
    // Status line, along the bottom.
    char line[256];
    if (map.lonDeg && map.latDeg)
        std::snprintf(line, sizeof line, "lon %.6f  lat %.6f  height %.1f m   |   eye %s", *map.lonDeg, *map.latDeg,
                      map.heightM.value_or(0.0), distance(std::round(map.eyeHeightM)).c_str());
    else
        std::snprintf(line, sizeof line, "(no ground under the cursor)   |   eye %s", distance(std::round(map.eyeHeightM)).c_str());
    const float ly = io.DisplaySize.y - 20 * s;
    dl->AddRectFilled(ImVec2(0, ly - 2 * s), ImVec2(io.DisplaySize.x, io.DisplaySize.y), IM_COL32(0, 0, 0, 150));
    dl->AddText(ImVec2(8 * s, ly), IM_COL32(235, 235, 235, 255), line);
    if (placing_) {
        const char* hint = "click on the globe to place the pin (Esc: cancel)";
        dl->AddText(ImVec2(io.DisplaySize.x * 0.5f, ly - 22 * s), IM_COL32(255, 220, 120, 255), hint);
    }
    if (!map.message.empty())
        dl->AddText(ImVec2(io.DisplaySize.x * 0.5f, ly), IM_COL32(255, 220, 120, 255), map.message.c_str());
}

}  // namespace orbis::ui
