#include "ui/ProcessesPanel.h"

#include "base/Secrets.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace orbis::ui {
namespace {

namespace fs = std::filesystem;

template <class T>
bool ready(const std::future<T>& f) {
    return f.valid() && f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

fs::path defaultResultsFolder() {
    if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && *cache) return fs::path(cache) / "orbis" / "wps";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "orbis" / "wps";
    return fs::temp_directory_path() / "orbis-wps";
}

/// What the job was asked, for the result layer's "provenance" (a complex input's data is not
/// repeated: its size is).
nlohmann::json provenanceOf(const wps::WpsJob& job, const wps::SavedOutput& output) {
    nlohmann::json inputs = nlohmann::json::object();
    for (const wps::InputValue& v : job.inputs()) {
        if (v.kind == wps::DataKind::BoundingBox) inputs[v.identifier] = {v.bbox[0], v.bbox[1], v.bbox[2], v.bbox[3]};
        else if (v.kind == wps::DataKind::Complex)
            inputs[v.identifier] = v.reference.empty() ? (v.value.size() <= 4096 ? v.value : std::to_string(v.value.size()) + " bytes")
                                                       : v.reference;
        else inputs[v.identifier] = v.value;
    }
    nlohmann::json provenance = {{"wps", redactSecrets(job.url())}, {"process", job.process().identifier}, {"inputs", inputs},
                             {"output", output.identifier}};
    if (!output.reference.empty()) provenance["reference"] = redactSecrets(output.reference);
    return provenance;
}

/// The layer that shows a raster or vector output.
std::optional<scene::LayerDesc> layerFor(const wps::WpsJob& job, const wps::SavedOutput& output) {
    scene::LayerDesc d;
    d.name = job.process().title.empty() ? job.process().identifier : job.process().title;
    if (job.process().outputs.size() > 1) d.name += " - " + (output.title.empty() ? output.identifier : output.title);
    if (output.kind == wps::OutputKind::Raster) {
        d.type = "overlay";
        d.settings = {{"path", output.file.string()}, {"opacity", 0.75}};
    } else if (output.kind == wps::OutputKind::Vector) {
        d.type = "vector";
        d.settings = {{"path", output.file.string()},
                      {"style", {{"color", {1.0, 0.55, 0.1}}, {"width", 2.0}, {"fill", {1.0, 0.55, 0.1}}, {"fillOpacity", 0.25}}}};
    } else {
        return std::nullopt;
    }
    d.provenance = provenanceOf(job, output);
    return d;
}

/// The files the scene's layers read (a layer's "path", a terrain's elevation and imagery
/// files), resolved, with the layer's name: what a file input may send.
std::vector<std::pair<std::string, std::string>> layerFiles(const scene::SceneDesc& scene) {
    std::vector<std::pair<std::string, std::string>> files;
    const auto add = [&](const std::string& name, const nlohmann::json& entry) {
        const nlohmann::json* path = entry.is_string() ? &entry : entry.is_object() && entry.contains("path") ? &entry["path"] : nullptr;
        if (path && path->is_string() && !path->get<std::string>().empty())
            files.emplace_back(name, scene.resolveSource(path->get<std::string>()));
    };
    for (const auto& layer : scene.layers) {
        if (layer.settings.contains("path")) add(layer.name, layer.settings["path"]);
        for (const char* list : {"elevation", "imagery"})
            if (layer.settings.contains(list) && layer.settings[list].is_array())
                for (const auto& e : layer.settings[list]) add(layer.name + " (" + list + ")", e);
    }
    return files;
}

}  // namespace

ProcessesPanel::ProcessesPanel() = default;
ProcessesPanel::~ProcessesPanel() {
    for (Job& j : jobs_) j.job->stop();
    if (connecting_.valid()) connecting_.wait();
    if (describing_.valid()) describing_.wait();
}

void ProcessesPanel::setUp(std::vector<std::string> servers, fs::path resultsFolder) {
    servers_ = std::move(servers);
    if (!servers_.empty()) std::snprintf(url_, sizeof url_, "%s", servers_.front().c_str());
    resultsFolder_ = resultsFolder.empty() ? defaultResultsFolder() : std::move(resultsFolder);
}

bool ProcessesPanel::busy() const {
    if (connecting_.valid() || describing_.valid()) return true;
    return std::any_of(jobs_.begin(), jobs_.end(), [](const Job& j) { return !j.collected; });
}

void ProcessesPanel::poll() {
    if (ready(connecting_)) {
        auto c = connecting_.get();
        if (c) {
            capabilities_ = std::move(c).value();
            error_.clear();
        } else {
            error_ = c.message();
        }
    }
    if (ready(describing_)) {
        auto d = describing_.get();
        if (d) {
            process_ = std::move(d).value();
            form_ = wps::makeForm(*process_);
            std::printf("described \"%s\" in %.3f s: a form of %zu fields\n", process_->identifier.c_str(),
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - describeAsked_).count(), form_.size());
            std::fflush(stdout);
            boundRevision_ = ~0ull;
            error_.clear();
        } else {
            error_ = d.message();
        }
    }
}

void ProcessesPanel::serverSection(const RememberItem& remember) {
    const float s = ImGui::GetIO().FontGlobalScale;
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - 80 * s);
    ImGui::InputText("##wpsUrl", url_, sizeof url_);
    remember("url##wps");
    ImGui::SameLine();
    const bool connecting = connecting_.valid();
    if (ImGui::Button(connecting ? "..." : "Connect##wps", ImVec2(-1.0f, 0.0f)) && !connecting && url_[0]) {
        connectedUrl_ = url_;
        capabilities_.reset();
        process_.reset();
        form_.clear();
        connecting_ = std::async(std::launch::async, [url = connectedUrl_]() -> Result<wps::Capabilities> {
            auto client = wps::connectProcessing(url);
            if (!client) return client.error();
            return (*client)->capabilities();
        });
    }
    remember("Connect##wps");
    if (servers_.size() > 1 && ImGui::BeginCombo("##servers", "other servers")) {
        for (const auto& server : servers_)
            if (ImGui::Selectable(server.c_str())) std::snprintf(url_, sizeof url_, "%s", server.c_str());
        ImGui::EndCombo();
    }
    if (!capabilities_) return;
    ImGui::TextDisabled("%s: %zu processes", capabilities_->title.c_str(), capabilities_->processes.size());
    if (ImGui::BeginListBox("##processes", ImVec2(-1.0f, std::min<float>(6.0f, float(capabilities_->processes.size())) * ImGui::GetTextLineHeightWithSpacing() + 4)))
    {
        for (const auto& p : capabilities_->processes) {
            const bool chosen = process_ && process_->identifier == p.identifier;
            if (ImGui::Selectable((p.identifier + "##process").c_str(), chosen) && !describing_.valid()) {
                describeAsked_ = std::chrono::steady_clock::now();
                describing_ = std::async(std::launch::async, [url = connectedUrl_, id = p.identifier]() -> Result<wps::ProcessDescription> {
                    auto client = wps::connectProcessing(url);
                    if (!client) return client.error();
                    return (*client)->describe(id);
                });
            }
            remember(p.identifier + "##process");
            if (ImGui::IsItemHovered() && !p.title.empty()) ImGui::SetTooltip("%s", p.title.c_str());
        }
        ImGui::EndListBox();
    }
}

void ProcessesPanel::formSection(const Sketch& sketch, const scene::SceneDesc& scene, const RememberItem& remember) {
    if (!process_) return;
    const float s = ImGui::GetIO().FontGlobalScale;
    ImGui::Separator();
    ImGui::TextUnformatted(process_->title.empty() ? process_->identifier.c_str() : process_->title.c_str());
    if (!process_->abstract.empty()) ImGui::TextWrapped("%s", process_->abstract.c_str());
    // The drawing binds the inputs that name a place, each time it changes.
    if (boundRevision_ != sketch.revision()) {
        boundRevision_ = sketch.revision();
        if (!sketch.points().empty()) wps::bindPoint(form_, {sketch.points()[0].lonDeg, sketch.points()[0].latDeg});
    }
    for (wps::FormField& f : form_) {
        ImGui::PushID(f.identifier.c_str());
        if (!f.required) {
            ImGui::Checkbox("##send", &f.send);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("send this optional input");
            ImGui::SameLine();
        }
        ImGui::BeginDisabled(!f.send);
        const std::string label = f.title + (f.uom.empty() ? "" : " (" + f.uom + ")");
        ImGui::SetNextItemWidth(140 * s);
        char text[512];
        std::snprintf(text, sizeof text, "%s", f.text.c_str());
        switch (f.widget) {
            case wps::FieldWidget::Choice:
                if (ImGui::BeginCombo(label.c_str(), f.text.c_str())) {
                    for (const auto& c : f.choices)
                        if (ImGui::Selectable(c.c_str(), c == f.text)) f.text = c;
                    ImGui::EndCombo();
                }
                break;
            case wps::FieldWidget::Toggle: {
                bool on = f.text == "true" || f.text == "1";
                if (ImGui::Checkbox(label.c_str(), &on)) f.text = on ? "true" : "false";
                break;
            }
            case wps::FieldWidget::Area:
                if (const auto b = sketch.bounds(); b && (sketch.tool() == SketchTool::Box || sketch.tool() == SketchTool::Polygon))
                    ImGui::Text("%s: %.4f, %.4f .. %.4f, %.4f", f.title.c_str(), b->west, b->south, b->east, b->north);
                else
                    ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.4f, 1.0f), "%s: draw a box (Measure)", f.title.c_str());
                break;
            case wps::FieldWidget::Geometry: {
                // The drawn shape, or a layer's vector file.
                const std::string drawn = sketch.complete() && sketch.tool() != SketchTool::None
                                              ? std::string("the drawn ") + toString(sketch.tool()) : std::string("draw it (Measure)");
                const std::string shown = f.text.empty() ? drawn : std::filesystem::path(f.text).filename().string();
                if (ImGui::BeginCombo(label.c_str(), shown.c_str())) {
                    if (ImGui::Selectable(drawn.c_str(), f.text.empty())) f.text.clear();
                    for (const auto& [name, path] : layerFiles(scene))
                        if (ImGui::Selectable((name + "##" + path).c_str(), f.text == path)) f.text = path;
                    ImGui::EndCombo();
                }
                break;
            }
            case wps::FieldWidget::File: {
                // A file or an address typed in, or a layer's data picked from the scene.
                if (ImGui::InputText(label.c_str(), text, sizeof text)) f.text = text;
                const auto files = layerFiles(scene);
                if (!files.empty()) {
                    ImGui::SameLine();
                    if (ImGui::BeginCombo("##layerFile", "layer", ImGuiComboFlags_NoPreview)) {
                        for (const auto& [name, path] : files)
                            if (ImGui::Selectable((name + "##" + path).c_str())) f.text = path;
                        ImGui::EndCombo();
                    }
                }
                break;
            }
            default:
                if (ImGui::InputText(label.c_str(), text, sizeof text)) f.text = text;
                if (!f.hint.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.hint.c_str());
        }
        remember(f.identifier + "##input");
        ImGui::EndDisabled();
        ImGui::PopID();
    }
    if (process_->storeSupported && process_->statusSupported) {
        ImGui::Checkbox("synchronous##wps", &synchronous_);
        remember("synchronous##wps");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("wait on the request itself (no progress) instead of a stored job polled for its status");
    }
    if (ImGui::Button("Run##wps", ImVec2(-1.0f, 0.0f))) {
        wps::FormGeometry geometry;
        if (const auto b = sketch.bounds(); b && (sketch.tool() == SketchTool::Box || sketch.tool() == SketchTool::Polygon))
            geometry.bounds = std::array<double, 4>{b->west, b->south, b->east, b->north};
        geometry.geoJson = sketch.geoJson();
        if (!sketch.points().empty()) geometry.point = std::array<double, 2>{sketch.points()[0].lonDeg, sketch.points()[0].latDeg};
        auto inputs = wps::formInputs(*process_, form_, geometry);
        if (!inputs) {
            error_ = inputs.message();
        } else {
            error_.clear();
            const auto stamp = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
            Job job;
            job.started = std::chrono::steady_clock::now();
            job.job = std::make_unique<wps::WpsJob>(connectedUrl_, *process_, std::move(inputs).value(),
                                                    resultsFolder_ / (std::to_string(stamp) + "-" + process_->identifier),
                                                    wps::WaitOptions{}, synchronous_);
            jobs_.push_back(std::move(job));
        }
    }
    remember("Run##wps");
}

void ProcessesPanel::collect(Job& j, std::vector<scene::LayerDesc>& addLayers) {
    const auto snap = j.job->snapshot();
    j.collected = true;
    for (const wps::SavedOutput& o : snap.outputs) {
        if (auto layer = layerFor(*j.job, o)) {
            j.layers.push_back(layer->name);
            addLayers.push_back(std::move(*layer));
            lastResultRequested_ = j.started;
        } else if (o.kind == wps::OutputKind::Table && !j.table) {
            std::ifstream in(o.file, std::ios::binary);
            std::stringstream text;
            text << in.rdbuf();
            auto t = wps::parseTable(text.str(), o.file.string());
            if (t) j.table = std::move(t).value(), j.showTable = true;
            else j.tableError = t.message();
        }
    }
}

void ProcessesPanel::jobsSection(const RememberItem& remember) {
    if (jobs_.empty()) return;
    ImGui::Separator();
    ImGui::TextUnformatted("Jobs");
    for (size_t i = 0; i < jobs_.size(); ++i) {
        Job& j = jobs_[i];
        const auto snap = j.job->snapshot();
        ImGui::PushID(int(i));
        ImGui::Text("%s  %s  %.1f s", j.job->process().identifier.c_str(),
                    snap.running ? wps::toString(snap.state) : snap.stopped ? "stopped" : wps::toString(snap.state), snap.seconds);
        if (snap.running) {
            ImGui::SameLine();
            if (ImGui::SmallButton("Stop")) j.job->stop();
            remember("Stop##job" + std::to_string(i));
            ImGui::ProgressBar(float(snap.percent) / 100.0f, ImVec2(-1.0f, 0.0f));
        }
        if (!snap.message.empty()) {
            if (snap.state == wps::JobState::Failed) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", snap.message.c_str());
            else ImGui::TextDisabled("%s", snap.message.c_str());
        }
        for (const auto& o : snap.outputs)
            if (o.kind == wps::OutputKind::Literal || o.kind == wps::OutputKind::BoundingBox)
                ImGui::Text("%s: %s", (o.title.empty() ? o.identifier : o.title).c_str(), o.text.c_str());
        for (const auto& name : j.layers) ImGui::TextDisabled("layer \"%s\" added", name.c_str());
        if (j.table) {
            ImGui::Checkbox("plot", &j.showTable);
            remember("plot##job" + std::to_string(i));
        }
        if (!j.tableError.empty()) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", j.tableError.c_str());
        ImGui::PopID();
    }
}

void ProcessesPanel::drawPlots() {
    // Tables as plots: the last numeric column against the rows (a profile's heights).
    for (size_t i = 0; i < jobs_.size(); ++i) {
        Job& j = jobs_[i];
        if (!j.table || !j.showTable || j.table->rows() == 0) continue;
        const std::string title = "Table " + std::to_string(i + 1) + ": " + j.job->process().identifier;
        const float s = ImGui::GetIO().FontGlobalScale;
        ImGui::SetNextWindowPos(ImVec2(360 * s + 20 * float(i), 40 * s + 20 * float(i)), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(420 * s, 200 * s), ImGuiCond_FirstUseEver);
        if (ImGui::Begin(title.c_str(), &j.showTable)) {
            const auto& t = *j.table;
            const size_t column = t.columns.size() - 1;
            std::vector<float> v;
            float lo = 1e30f, hi = -1e30f;
            for (double x : t.values[column])
                if (std::isfinite(x)) lo = std::min(lo, float(x)), hi = std::max(hi, float(x));
            for (double x : t.values[column]) v.push_back(std::isfinite(x) ? float(x) : lo);
            ImGui::Text("%s over %zu rows (%s %.6g .. %.6g)", t.columns[column].c_str(), t.rows(), t.columns[0].c_str(), t.values[0].front(),
                        t.values[0].back());
            ImGui::PlotLines("##table", v.data(), int(v.size()), 0, nullptr, lo, std::max(hi, lo + 1.0f),
                             ImVec2(ImGui::GetContentRegionAvail().x, std::max(40.0f, ImGui::GetContentRegionAvail().y)));
        }
        ImGui::End();
    }
}

void ProcessesPanel::update(std::vector<scene::LayerDesc>& addLayers, bool& changed) {
    poll();
    for (Job& j : jobs_) {
        if (j.collected) continue;
        changed = true;   // its progress moves
        if (!j.job->snapshot().running) collect(j, addLayers);
    }
}

void ProcessesPanel::draw(const Sketch& sketch, const scene::SceneDesc& scene, const RememberItem& remember) {
    serverSection(remember);
    if (describing_.valid()) ImGui::TextDisabled("reading the description...");
    formSection(sketch, scene, remember);
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.5f, 0.4f, 1.0f), "%s", error_.c_str());
    jobsSection(remember);
}

}  // namespace orbis::ui
