#include "ui/MeasurePanel.h"

#include "engine/scene/Scene.h"
#include "globe/ElevationSampler.h"
#include "globe/GdalSetup.h"
#include "globe/RasterSource.h"

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace orbis::ui {
namespace {

/// The first elevation source of the first terrain layer, resolved; "" when there is none.
std::string sceneDem(const scene::Scene& scene) {
    for (const auto& layer : scene.desc().layers) {
        if (layer.type != "terrain") continue;
        const auto it = layer.settings.find("elevation");
        if (it == layer.settings.end() || !it->is_array() || it->empty()) continue;
        const auto& first = it->front();
        if (first.is_string()) return scene.desc().resolveSource(first.get<std::string>());
        if (first.is_object() && first.contains("path") && first["path"].is_string())
            return scene.desc().resolveSource(first["path"].get<std::string>());
    }
    return {};
}

/// An sRGB colour as ImGui's vertices take it: the viewer's swapchain is sRGB, so they are
/// linear (what the panels' own style colours assume too).
ImU32 srgb(int r, int g, int b, int a = 255) {
    const auto linear = [](int c) { return int(std::lround(255.0 * std::pow(c / 255.0, 2.2))); };
    return IM_COL32(linear(r), linear(g), linear(b), a);
}

const ImU32 kLine = srgb(255, 210, 60);
const ImU32 kSeen = srgb(60, 220, 80);
const ImU32 kBlocked = srgb(235, 50, 40);

void label(ImDrawList* list, glm::dvec2 at, const std::string& text) {
    const ImVec2 size = ImGui::CalcTextSize(text.c_str());
    const ImVec2 p(float(at.x) + 8.0f, float(at.y) - size.y - 4.0f);
    list->AddRectFilled(ImVec2(p.x - 3, p.y - 2), ImVec2(p.x + size.x + 3, p.y + size.y + 2), IM_COL32(0, 0, 0, 170), 3.0f);
    list->AddText(p, IM_COL32(255, 255, 255, 255), text.c_str());
}

}  // namespace

MeasurePanel::MeasurePanel() = default;

MeasurePanel::~MeasurePanel() {
    if (running_.valid()) running_.wait();
}

bool MeasurePanel::busy() const { return running_.valid(); }

void MeasurePanel::collect() {
    if (!running_.valid() || running_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    Answer a = running_.get();
    if (a.dem) dem_ = a.dem;
    analysisError_ = a.error;
    profile_ = std::move(a.profile);
    sight_ = std::move(a.sight);
    sightFrom_ = a.from;
    sightTo_ = a.to;
}

void MeasurePanel::startAnalysis(const scene::Scene& scene) {
    const bool wantsProfile = sketch_.tool() == SketchTool::Path && sketch_.complete();
    const bool wantsSight = sketch_.tool() == SketchTool::Sight && sketch_.complete();
    if (!wantsProfile) profile_.reset();
    if (!wantsSight) sight_.reset();
    if (!wantsProfile && !wantsSight) {
        analysedRevision_ = sketch_.revision();
        return;
    }
    if (running_.valid()) return;   // the next frame starts it on the new sketch
    analysedRevision_ = sketch_.revision();
    if (demSource_.empty()) demSource_ = sceneDem(scene);
    if (demSource_.empty()) {
        analysisError_ = "the scene has no terrain layer with an elevation source to measure on";
        return;
    }
    std::vector<globe::LonLat> path;
    for (const auto& p : sketch_.points()) path.emplace_back(p.lonDeg, p.latDeg);
    running_ = std::async(std::launch::async, [dem = dem_, source = demSource_, path, wantsProfile, eye = eyeHeight_,
                                                target = targetHeight_]() mutable {
        Answer a;
        if (!dem) {
            globe::configureGdal();
            auto opened = globe::RasterSource::open({.path = source, .role = globe::RasterRole::Elevation});
            if (!opened) {
                a.error = opened.message();
                return a;
            }
            dem = globe::ElevationSampler::function(std::make_shared<const globe::ElevationSampler>(*opened));
        }
        a.dem = dem;
        if (wantsProfile) {
            a.profile = globe::terrainProfile(path, dem, std::max(1.0, globe::geodesicLength(path).metres / 1000.0), 2000);
            return a;
        }
        const auto h0 = dem(path[0].x, path[0].y), h1 = dem(path[1].x, path[1].y);
        if (!h0 || !h1) {
            a.error = "the DEM has no height under " + std::string(!h0 ? "the observer" : "the target");
            return a;
        }
        a.from = {path[0].x, path[0].y, *h0 + eye};
        a.to = {path[1].x, path[1].y, *h1 + target};
        a.sight = globe::lineOfSight(a.from, a.to, dem);
        return a;
    });
}

void MeasurePanel::draw(const scene::Scene& scene, const RememberItem& remember, bool& changed) {
    collect();
    if (analysedRevision_ != sketch_.revision()) startAnalysis(scene);
    const float s = ImGui::GetIO().FontGlobalScale;
    const struct { SketchTool tool; const char* label; } tools[] = {
        {SketchTool::None, "Off"}, {SketchTool::Point, "Point"}, {SketchTool::Path, "Path"},
        {SketchTool::Polygon, "Polygon"}, {SketchTool::Box, "Box"}, {SketchTool::Sight, "Sight"}};
    for (size_t i = 0; i < std::size(tools); ++i) {
        if (i % 3) ImGui::SameLine();
        if (ImGui::RadioButton((std::string(tools[i].label) + "##tool").c_str(), sketch_.tool() == tools[i].tool)) {
            sketch_.setTool(tools[i].tool);
            changed = true;
        }
        remember(std::string(tools[i].label) + "##tool");
    }
    if (drawing()) {
        if (ImGui::SmallButton("Undo##sketch")) sketch_.removeLast(), changed = true;
        remember("Undo##sketch");
        ImGui::SameLine();
        if (ImGui::SmallButton("Clear##sketch")) sketch_.clear(), changed = true;
        remember("Clear##sketch");
        ImGui::SameLine();
        ImGui::TextDisabled("left click on the globe");
    }
    const auto& pts = sketch_.points();
    if (sketch_.tool() == SketchTool::Point && !pts.empty())
        ImGui::Text("lon %.6f  lat %.6f  %.1f m", pts[0].lonDeg, pts[0].latDeg, pts[0].height);
    if (sketch_.lengthM() > 0.0) ImGui::Text("%s: %s", sketch_.tool() == SketchTool::Polygon || sketch_.tool() == SketchTool::Box ? "perimeter" : "length",
                                             formatLength(sketch_.lengthM()).c_str());
    if (const auto a = sketch_.area()) ImGui::Text("area: %s", formatArea(a->areaM2).c_str());
    if (const auto b = sketch_.bounds(); b && sketch_.tool() == SketchTool::Box)
        ImGui::Text("%.5f, %.5f .. %.5f, %.5f", b->west, b->south, b->east, b->north);
    if (sketch_.tool() == SketchTool::Sight) {
        ImGui::SetNextItemWidth(90 * s);
        if (ImGui::InputDouble("eye (m)##sight", &eyeHeight_, 1.0, 10.0, "%.1f")) analysedRevision_ = ~0ull, eyeHeight_ = std::clamp(eyeHeight_, 0.0, 100000.0);
        ImGui::SameLine();
        ImGui::SetNextItemWidth(90 * s);
        if (ImGui::InputDouble("target (m)##sight", &targetHeight_, 1.0, 10.0, "%.1f")) analysedRevision_ = ~0ull, targetHeight_ = std::clamp(targetHeight_, 0.0, 100000.0);
        if (sight_) {
            if (sight_->visible) ImGui::TextColored(ImVec4(0.3f, 0.9f, 0.35f, 1.0f), "visible over %s (clearance %.1f m)", formatLength(sight_->distanceM).c_str(), sight_->clearanceM);
            else ImGui::TextColored(ImVec4(0.95f, 0.3f, 0.25f, 1.0f), "blocked %s from the eye, by %.1f m of ground", formatLength(sight_->blockedAtM).c_str(), sight_->aboveLineM);
        }
    }
    if (profile_ && !profile_->samples.empty()) {
        std::vector<float> heights;
        heights.reserve(profile_->samples.size());
        const float floor = float(profile_->minHeight.value_or(0.0));
        for (const auto& x : profile_->samples) heights.push_back(x.height ? float(*x.height) : floor);
        const float top = float(profile_->maxHeight.value_or(1.0));
        ImGui::PlotLines("##profile", heights.data(), int(heights.size()), 0, nullptr, floor, std::max(top, floor + 1.0f),
                         ImVec2(ImGui::GetContentRegionAvail().x, 90 * s));
        remember("profile##plot");
        ImGui::Text("%s, %.0f .. %.0f m, up %.0f m, down %.0f m", formatLength(profile_->lengthM).c_str(), profile_->minHeight.value_or(0.0),
                    profile_->maxHeight.value_or(0.0), profile_->ascentM, profile_->descentM);
        if (profile_->unknown) ImGui::TextDisabled("%zu samples without data", profile_->unknown);
    }
    if (running_.valid()) ImGui::TextDisabled("reading the DEM...");
    if (!analysisError_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", analysisError_.c_str());
}

void MeasurePanel::drawOverlay(const Projector& project, const std::function<std::optional<double>(double, double)>& groundAt) const {
    const auto& pts = sketch_.points();
    if (pts.empty()) return;
    ImDrawList* list = ImGui::GetBackgroundDrawList();
    const auto ground = [&](double lon, double lat) { return groundAt(lon, lat).value_or(0.0); };
    // The outline along geodesics, on the ground.
    const auto outline = sketch_.outline();
    for (size_t i = 0; i + 1 < outline.size(); ++i) {
        const double leg = globe::geodesicBetween(outline[i], outline[i + 1]).metres;
        const auto along = globe::geodesicPoints(outline[i], outline[i + 1], std::max(leg / 48.0, 1.0), 64);
        std::optional<glm::dvec2> previous;
        for (const auto& p : along) {
            const auto px = project({p.x, p.y, ground(p.x, p.y)});
            if (px && previous && sketch_.tool() != SketchTool::Sight)
                list->AddLine(ImVec2(float(previous->x), float(previous->y)), ImVec2(float(px->x), float(px->y)), kLine, 2.5f);
            previous = px;
        }
    }
    // The vertices, with the distance so far on paths.
    const auto along = sketch_.along();
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto px = project(pts[i]);
        if (!px) continue;
        list->AddCircleFilled(ImVec2(float(px->x), float(px->y)), 5.0f, kLine);
        list->AddCircle(ImVec2(float(px->x), float(px->y)), 5.0f, IM_COL32(0, 0, 0, 200), 0, 1.5f);
        if (sketch_.tool() == SketchTool::Path && i > 0 && i < along.size()) label(list, *px, formatLength(along[i]));
    }
    if (sketch_.tool() == SketchTool::Point) {
        if (const auto px = project(pts[0])) {
            char text[96];
            std::snprintf(text, sizeof text, "%.5f, %.5f", pts[0].lonDeg, pts[0].latDeg);
            label(list, *px, text);
        }
    }
    if (const auto a = sketch_.area()) {
        double lon = 0.0, lat = 0.0;
        for (size_t i = 0; i + 1 < outline.size(); ++i) lon += outline[i].x, lat += outline[i].y;
        const double n = double(std::max<size_t>(1, outline.size() - 1));
        if (const auto px = project({lon / n, lat / n, ground(lon / n, lat / n)})) label(list, *px, formatArea(a->areaM2));
    }
    // The line of sight: a straight line in the air from the eye, green up to where the ground
    // rises above it, red from there.
    if (sketch_.tool() == SketchTool::Sight && sight_) {
        const auto& wgs84 = globe::Ellipsoid::wgs84();
        const glm::dvec3 a = wgs84.toEcef(sightFrom_), b = wgs84.toEcef(sightTo_);
        const double blockedT = sight_->visible ? 2.0 : sight_->blockedAtM / std::max(sight_->distanceM, 1e-9);
        std::optional<glm::dvec2> previous;
        constexpr int kSteps = 96;
        for (int i = 0; i <= kSteps; ++i) {
            const double t = double(i) / kSteps;
            const auto g = wgs84.toGeodetic(a + (b - a) * t);
            const auto px = project(g);
            if (px && previous)
                list->AddLine(ImVec2(float(previous->x), float(previous->y)), ImVec2(float(px->x), float(px->y)), t <= blockedT ? kSeen : kBlocked, 3.0f);
            previous = px;
        }
        if (!sight_->visible) {
            const auto& c = sight_->blockedAt;
            if (const auto px = project({c.x, c.y, sight_->blockingHeight})) {
                list->AddCircle(ImVec2(float(px->x), float(px->y)), 7.0f, kBlocked, 0, 2.5f);
                label(list, *px, "blocked at " + formatLength(sight_->blockedAtM));
            }
        }
    }
}

}  // namespace orbis::ui
