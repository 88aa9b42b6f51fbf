#include "layers/vector/VectorLayer.h"

#include "base/Log.h"
#include "base/Secrets.h"
#include "engine/render/RenderContext.h"
#include "layers/vector/FeaturePick.h"
#include "layers/vector/LabelRenderer.h"
#include "layers/vector/MeshRenderer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace orbis::layers {

VectorLayer::VectorLayer(VectorLayerSettings settings)
    : settings_(std::move(settings)),
      // A KML's own icons are relative to the KML; the scene's were resolved when it was read.
      icons_(std::make_shared<vector::IconCache>(std::filesystem::path(settings_.content.read.source).parent_path().string())) {}

VectorLayer::~VectorLayer() {
    if (loading_) job_.wait();
    if (pagedLabelLoading_) pagedLabelJob_.wait();
    for (auto& job : tileJobs_) {
        job.cancel();
        job.wait();
    }
    if (meshLoading_) {
        meshJob_.cancel();
        meshJob_.wait();
    }
    if (refreshing_) {
        refreshJob_.cancel();
        refreshJob_.wait();
    }
}

void VectorLayer::onPrepare(const render::RenderServices& services) {
    services_ = services;
    // Labels only for a style that gives one: the fonts, the atlas and the pipelines.
    const bool labelled = settings_.content.style.namesLabel();
    if (labelled) {
        auto labels = vector::VectorLabels::create();
        if (labels) {
            labels_.emplace(std::move(*labels));
            ownBoard_ = std::make_shared<vector::LabelBoard>();
            labelRenderer_ = std::make_unique<LabelRenderer>(services, labels_->atlas().width(), labels_->atlas().height());
        } else {
            labelError_ = labels.message();
            log::error("vector layer \"", settings_.name, "\": no labels: ", labelError_);
        }
    }
    // A live source's listener: its own thread and connection, only for a layer that is shown.
    if (!settings_.refresh.listen.empty()) {
        vector::PgListener::Options listen;
        listen.name = "vector layer \"" + displayName() + "\"";
        listen.channel = settings_.refresh.listen;
        if (auto connection = vector::libpqConnection(settings_.content.read.source)) listen.connection = *connection;
        if (!settings_.refresh.triggerTable.empty())
            listen.setupSql = vector::pgNotifyTriggerSql(settings_.refresh.triggerTable, settings_.refresh.triggerGeometry, listen.channel);
        auto started = vector::PgListener::start(std::move(listen));
        if (started) listener_ = std::move(*started);
        else refreshError_ = started.message();
    }
    // Read on the pool: the first frames draw the rest of the scene meanwhile. The labels'
    // anchors (an interior point of each polygon) are worked out there too.
    loading_ = true;
    const auto read = [settings = settings_, labelled](const jobs::CancelToken&) -> Result<Loaded> {
        auto paged = openPaged(settings);
        if (!paged || paged->pages) return paged;
        auto content = vector::loadVectorContent(settings.content);
        if (!content) return content.error();
        Loaded loaded{std::move(*content), nullptr};
        if (labelled) loaded.anchors = std::make_shared<const vector::ContentAnchors>(vector::labelAnchors(*loaded.content));
        return loaded;
    };
    job_ = services.jobs().submit(0.0, jobs::CancelToken{}, read);
}

void VectorLayer::pollMeshes() {
    if (!meshLoading_ || !meshJob_.ready()) return;
    meshLoading_ = false;
    MeshBuild build;
    try {
        build = meshJob_.get();
    } catch (const jobs::Cancelled&) {
        // A newer build follows.
    } catch (const std::exception& e) {
        error_ = redactSecrets(settings_.content.read.source) + ": building its meshes failed: " + e.what();
        log::error("vector layer \"", settings_.name, "\": ", error_);
    }
    meshJob_ = {};
    if (!build.mesh) return;
    // The ground sampled for the features of now is kept for the next builds (time, scale).
    if (build.generation == meshGeneration_) ground_ = std::move(build.ground);
    mesh_ = std::move(build.mesh);
    for (const std::string& w : mesh_->warnings) log::warn("vector layer \"", settings_.name, "\": ", w);
    if (!meshRenderer_ && !mesh_->chunks.empty()) meshRenderer_ = std::make_unique<MeshRenderer>(services_, icons_);
    if (meshRenderer_) meshRenderer_->setMesh(mesh_);
}

void VectorLayer::poll() {
    pollRefresh();
    pollMeshes();
    pollPagedMeshes();
    pollPagedLabels();
    if (!loading_ || !job_.ready()) return;
    loading_ = false;
    Result<Loaded> r = makeError("vector: the read was cancelled");
    try {
        r = job_.get();
    } catch (const std::exception& e) {
        r = makeError(settings_.content.read.source + ": " + e.what());
    }
    job_ = {};
    if (!r) {
        error_ = r.message();
        log::error("vector layer \"", settings_.name, "\": ", error_);
        return;
    }
    if (r->pages) {
        pagedMeshes_ = settings_.content.style.namesExtrusion() || settings_.altitude != vector::AltitudeMode::Clamped;
        if (pagedMeshes_ && settings_.refresh.enabled() && settings_.refresh.glideSeconds != 0.0) {
            motion_ = std::make_unique<vector::MarkerMotion>(vector::GlideOptions{.seconds = settings_.refresh.glideSeconds});
            // The labels of points drawn as markers stand by their markers, moving with them.
            if (labels_) labels_->setMarkerPlace([this](uint32_t id) { return motion_->shownAt(id, glideClock()); });
        }
        pages_ = std::move(r->pages);
        pagedBounds_ = r->bounds;
        // Read again on a clock only: rows may come anywhere, unannounced; tiles are not kept
        // within the box read at the start.
        if (settings_.refresh.everySeconds > 0.0 && settings_.refresh.listen.empty()) pagedBounds_.reset();
        pagedFeatures_ = r->features;
        republish();
        return;
    }
    content_ = std::move(r->content);
    anchors_ = std::move(r->anchors);
    for (const std::string& w : content_->warnings) log::warn("vector layer \"", settings_.name, "\": ", w);
    styles_ = std::make_shared<const vector::ContentStyles>(vector::styleContent(*content_));
    shownSignature_ = vector::shownAtSignature(*content_, time_);
    if (labels_) labels_->setContent(content_, styles_, anchors_);
    restartMeshes();
    republish();
}

void VectorLayer::update(const scene::FrameContext& frame) {
    const TimeNs before = time_;
    time_ = frame.time;
    if (pages_ && time_ != before) {
        // Paged: paint again when the features shown by a page in memory change.
        for (const auto& page : pages_->loaded())
            if (vector::shownAtSignature(*page->content, before) != vector::shownAtSignature(*page->content, time_)) {
                republish();
                break;
            }
    }
    if (pages_) {
        updatePagedMeshes(frame);
        if (meshRenderer_) meshRenderer_->setGlideClock(glideClock());
        updatePagedLabels();
        updateLabels(frame);
        return;
    }
    if (!content_) return;
    // Features with times come and go with the clock: paint again only when the set changes.
    const uint64_t shown = vector::shownAtSignature(*content_, time_);
    if (shown != shownSignature_) {
        shownSignature_ = shown;
        meshStale_ = meshFeatures_ > 0;
        republish();
    }
    updateMeshes(frame);
    updateLabels(frame);
}

void VectorLayer::restartMeshes() {
    ground_.reset();
    ++meshGeneration_;
    meshStale_ = false;
    meshFeatures_ = 0;
    drapeStyles_ = styles_;
    drapesSomething_ = true;
    if (!content_) return;
    const vector::MeshGround features(*content_, *styles_, settings_.altitude);
    meshFeatures_ = features.features().size();
    if (meshFeatures_ == 0) {
        // Nothing to build; a mesh drawn before (a rule switched off) goes.
        if (mesh_) {
            mesh_ = std::make_shared<const vector::FeatureMesh>();
            if (meshRenderer_) meshRenderer_->setMesh(mesh_);
        }
        return;
    }
    // The drape leaves out what the meshes draw.
    auto drapeStyles = std::make_shared<vector::ContentStyles>(*styles_);
    for (const auto& [l, i] : features.features()) (*drapeStyles)[l][i].visible = false;
    drapesSomething_ = meshFeatures_ < content_->featureCount;
    drapeStyles_ = std::move(drapeStyles);
    meshStale_ = true;
}

void VectorLayer::updateMeshes(const scene::FrameContext& frame) {
    if (meshFeatures_ == 0) return;
    if (frame.groundVersion != groundVersion_) {
        // The ground changed (the terrain's exaggeration): sample it again.
        groundVersion_ = frame.groundVersion;
        ground_.reset();
        ++meshGeneration_;
        meshStale_ = true;
    }
    if (!meshStale_ || meshLoading_) return;
    meshStale_ = false;
    meshLoading_ = true;
    // The ground is sampled on the pool (once; the next builds reuse it), from a snapshot that
    // any thread may ask; the content and styles are shared read-only.
    const vector::MeshOptions options{
        .mode = settings_.altitude, .extrusionScale = settings_.extrusionScale, .time = time_, .icons = icons_.get()};
    scene::GroundHeightFn groundFn;
    if (!ground_ && frame.groundSnapshot) groundFn = frame.groundSnapshot();
    meshJob_ = services_.jobs().submit(
        0.0, jobs::CancelToken{},
        [content = content_, styles = styles_, ground = ground_, groundFn = std::move(groundFn), options,
         generation = meshGeneration_](const jobs::CancelToken& cancel) {
            MeshBuild build{ground, nullptr, generation};
            if (!build.ground) {
                auto sampled = std::make_shared<vector::MeshGround>(*content, *styles, options.mode);
                sampled->sample(groundFn, sampled->samples());
                build.ground = std::move(sampled);
            }
            build.mesh = std::make_shared<const vector::FeatureMesh>(vector::buildFeatureMesh(*content, *styles, *build.ground, options, &cancel));
            return build;
        });
}

void VectorLayer::updateLabels(const scene::FrameContext& frame) {
    board_ = nullptr;
    if (!labels_) return;
    if (!drawingLabels()) {
        labels_->clear();
        return;
    }
    // The vector layers drawing labels this frame, in scene order: the first one's board is
    // everyone's, and each layer's place in the list keeps its ids apart from the others'.
    uint64_t slot = 0;
    for (const scene::Drape& d : frame.drapes) {
        const auto* other = dynamic_cast<const VectorLayer*>(static_cast<const scene::Layer*>(d.owner));
        if (!other || !other->drawingLabels()) continue;
        if (!board_) board_ = other->ownBoard_;
        if (other == this) break;
        ++slot;
    }
    if (!board_) board_ = ownBoard_;
    labels_->setIdBase(slot << 56);
    labels_->gather(frame);
    board_->submit(frame.frameNumber, *labels_);
}

void VectorLayer::republish() {
    const vector::DrapeState state{.name = displayName(),
                                   .time = time_,
                                   .maxLevel = settings_.maxLevel,
                                   .simplifyPx = settings_.simplifyPx,
                                   .icons = icons_,
                                   .highlight = highlight_,
                                   .meshes = pagedMeshes_ ? std::optional(settings_.altitude) : std::nullopt};
    if (pages_ && pagedMeshes_ && !pagedDrapes_ && !labels_) {
        drape_.reset();   // nothing met yet that is not a mesh
        return;
    } else if (pages_) {
        drape_ = std::make_shared<const vector::VectorDrape>(state, pages_, settings_.content.style, pagedBounds_);
    } else if (!drapesSomething_ && !labels_) {
        // The labels' board is found through the drapes: a layer drawing labels keeps one.
        drape_.reset();
        return;
    } else {
        drape_ = std::make_shared<const vector::VectorDrape>(state, content_, drapeStyles_ ? drapeStyles_ : styles_);
    }
    ++version_;
    drapeChanges_.emplace_back(version_, std::nullopt);   // anywhere
    if (drapeChanges_.size() > 64) drapeChanges_.pop_front();
}

namespace {

scene::PickedAttributes pickedAttributes(const std::string& layerName, const vector::VectorContent& content, const vector::PickedFeature& hit) {
    const vector::VectorLayer& source = content.layers[hit.layer].data;
    const vector::Feature& f = source.features[hit.feature];
    scene::PickedAttributes out;
    out.layer = layerName + " / " + source.name;
    out.feature = "fid " + std::to_string(f.fid);
    for (size_t i = 0; i < source.fields.size() && i < f.attributes.size(); ++i)
        out.fields.emplace_back(source.fields[i].name, vector::attributeText(f.attributes[i]));
    return out;
}

}  // namespace

std::optional<scene::PickedAttributes> VectorLayer::pickPaged(const vector::PickQuery& q) {
    // What lies within the widest reach of the point, read whole (through the source's spatial
    // index), not cut into pages.
    const double reachDeg = (settings_.content.style.reachPx() + q.slopPx) * q.metresPerPixel / 111320.0;
    const double reachLon = std::min(180.0, reachDeg / std::max(0.01, std::cos(q.latDeg * M_PI / 180.0)));
    vector::VectorContentOptions options = settings_.content;
    options.read.within = vector::LonLatBounds{std::max(-180.0, q.lonDeg - reachLon), std::max(-90.0, q.latDeg - reachDeg),
                                               std::min(180.0, q.lonDeg + reachLon), std::min(90.0, q.latDeg + reachDeg), false};
    auto near = vector::loadVectorContent(options);
    if (!near) {
        log::warn("vector layer \"", settings_.name, "\": picking: ", near.message());
        return std::nullopt;
    }
    const vector::ContentStyles styles = vector::styleContent(**near);
    const auto hit = vector::pickFeature(**near, styles, q);
    std::optional<vector::DrapeFeature> now;
    if (hit) now = vector::DrapeFeature{hit->layer, hit->feature, (*near)->layers[hit->layer].data.features[hit->feature].fid};
    if (now.has_value() != highlight_.has_value() || (now && (now->layer != highlight_->layer || now->fid != highlight_->fid))) {
        highlight_ = now;
        if (meshRenderer_) meshRenderer_->setHighlight(now && now->fid >= 0 ? uint32_t(now->fid + 1) : 0);
        republish();
    }
    if (!hit) return std::nullopt;
    return pickedAttributes(displayName(), **near, *hit);
}

std::optional<scene::PickedAttributes> VectorLayer::pickAt(double lonDeg, double latDeg, double metresPerPixel) {
    const vector::PickQuery query{.lonDeg = lonDeg, .latDeg = latDeg, .metresPerPixel = metresPerPixel, .time = time_};
    if (pages_) return pickPaged(query);
    std::optional<vector::PickedFeature> hit;
    if (content_) hit = vector::pickFeature(*content_, *styles_, query);
    std::optional<vector::DrapeFeature> now;
    if (hit) now = vector::DrapeFeature{hit->layer, hit->feature, content_->layers[hit->layer].data.features[hit->feature].fid};
    if (now.has_value() != highlight_.has_value() || (now && (now->layer != highlight_->layer || now->feature != highlight_->feature))) {
        highlight_ = now;
        if (meshRenderer_) meshRenderer_->setHighlight(hit ? vector::meshFeatureId(*content_, hit->layer, hit->feature) : 0);
        republish();
    }
    if (!hit) return std::nullopt;
    return pickedAttributes(displayName(), *content_, *hit);
}

void VectorLayer::clearPick() {
    if (!highlight_) return;
    highlight_.reset();
    if (meshRenderer_) meshRenderer_->setHighlight(0);
    if (content_ || pages_) republish();
}

bool VectorLayer::drawsIn(scene::Pass pass) const {
    if (pass == scene::Pass::Opaque) return meshRenderer_ != nullptr;
    return pass == scene::Pass::Overlay && labelRenderer_ && settings_.labels && !labels_->glyphs().empty();
}

void VectorLayer::recordTransfers(const render::RecordContext& context) {
    if (meshRenderer_) meshRenderer_->recordTransfers(context);
    if (!labelRenderer_) return;
    if (board_ && context.frame) {
        // After every layer's update: the first layer here places every layer's labels.
        const vector::VectorLabelOptions& o = labels_->options();
        board_->resolve(context.frame->frameNumber, *context.frame,
                        {.screen = {double(context.frame->width), double(context.frame->height)},
                         .marginPx = o.marginPx,
                         .priorityHysteresis = o.priorityHysteresis});
    }
    labelRenderer_->recordTransfers(context, labels_->atlas(), labels_->glyphs());
}

void VectorLayer::record(scene::Pass pass, const render::RecordContext& context) {
    if (pass == scene::Pass::Opaque && meshRenderer_) meshRenderer_->record(context);
    if (pass == scene::Pass::Overlay && labelRenderer_) labelRenderer_->record(context);
}

uint64_t VectorLayer::cacheBytes() const {
    return (content_ ? content_->bytes : 0) + (mesh_ ? mesh_->bytes() : 0) + (pages_ ? pages_->bytes() : 0);
}

uint64_t VectorLayer::gpuBytes() const {
    return (labelRenderer_ ? labelRenderer_->gpuBytes() : 0) + (meshRenderer_ ? meshRenderer_->gpuBytes() : 0);
}

std::vector<scene::LayerSetting> VectorLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    std::vector<scene::LayerSetting> out = {
        {.name = "opacity", .label = "Opacity", .kind = Kind::Number, .value = settings_.opacity,
         .min = kOpacityRange.min, .max = kOpacityRange.max},
    };
    out.push_back({.name = "maxLevel", .label = "Finest level painted", .kind = Kind::Integer, .value = double(settings_.maxLevel),
                   .min = kMaxLevelRange.min, .max = kMaxLevelRange.max});
    out.push_back({.name = "simplifyPx", .label = "Simplification (px)", .kind = Kind::Number, .value = settings_.simplifyPx,
                   .min = kSimplifyRange.min, .max = kSimplifyRange.max});
    const vector::VectorStyle& style = settings_.content.style;
    if (meshFeatures_ > 0 || mesh_ || pagedMeshes_)
        out.push_back({.name = "extrusionScale", .label = "Extrusion scale", .kind = Kind::Number, .value = settings_.extrusionScale,
                       .min = kExtrusionScaleRange.min, .max = kExtrusionScaleRange.max});
    if (style.namesLabel())
        out.push_back({.name = "labels", .label = "Labels", .kind = Kind::Toggle, .value = settings_.labels ? 1.0 : 0.0,
                       .pointer = "/labels"});
    for (size_t i = 0; i < style.ruleCount(); ++i)
        out.push_back({.name = "rule" + std::to_string(i), .label = style.ruleName(i), .kind = Kind::Toggle,
                       .value = style.ruleEnabled(i) ? 1.0 : 0.0,
                       .pointer = "/style/rules/" + std::to_string(i) + "/enabled"});
    return out;
}

bool VectorLayer::setParameter(std::string_view name, double value) {
    if (name == "opacity" && kOpacityRange.contains(value)) {
        settings_.opacity = value;
        return true;
    }
    if ((name == "maxLevel" && kMaxLevelRange.contains(value) && value == std::floor(value)) ||
        (name == "simplifyPx" && kSimplifyRange.contains(value))) {
        if (name == "maxLevel") settings_.maxLevel = uint32_t(value);
        else settings_.simplifyPx = value;
        if (content_ || pages_) republish();
        return true;
    }
    if (name == "extrusionScale" && kExtrusionScaleRange.contains(value)) {
        if (value != settings_.extrusionScale) meshStale_ = meshFeatures_ > 0;
        if (value != settings_.extrusionScale && pagedMeshes_) ++tileMeshGeneration_;
        settings_.extrusionScale = value;
        return true;
    }
    if (name == "labels" && (value == 0.0 || value == 1.0)) {
        settings_.labels = value != 0.0;
        return true;
    }
    vector::VectorStyle& style = settings_.content.style;
    for (size_t i = 0; i < style.ruleCount(); ++i) {
        if (name != "rule" + std::to_string(i) || (value != 0.0 && value != 1.0)) continue;
        style.setRuleEnabled(i, value != 0.0);
        if (pages_) {
            republish();   // the drape switches the pages' rules itself
            pagedLabelsStale_ = true;
            ++tileMeshGeneration_;
        }
        if (content_) {
            for (vector::ContentLayer& layer : content_->layers) layer.style.setRuleEnabled(i, value != 0.0);
            styles_ = std::make_shared<const vector::ContentStyles>(vector::styleContent(*content_));
            // The labels follow the styles (a rule switched off may take its labels with it).
            if (labels_) labels_->setContent(content_, styles_, anchors_);
            restartMeshes();
            republish();
        }
        return true;
    }
    return false;
}

std::string VectorLayer::status() const {
    if (!error_.empty()) return "error: " + error_;
    if (loading_) return "reading " + settings_.content.read.source;
    std::ostringstream s;
    if (pages_) {
        s << pagedFeatures_ << " features, paged: " << pages_->loadedCount() << " feature tile(s) in memory (" << std::fixed
          << std::setprecision(1) << double(pages_->bytes()) / (1 << 20) << " of " << double(settings_.pageBudgetBytes) / (1 << 20)
          << " MB), " << pages_->reads() << " read";
        if (const size_t bad = pages_->failingCount(); bad > 0) s << ", " << bad << " unreadable: " << pages_->lastError();
    } else if (!content_) {
        return {};
    } else {
        s << content_->featureCount << " features in " << content_->layers.size() << " layer(s), " << content_->vertexCount
          << " vertices";
        if (!content_->warnings.empty()) s << ", " << content_->warnings.size() << " warning(s)";
    }
    if (listener_) {
        s << ", live: " << listener_->status() << " (" << refreshesApplied_ << " change(s) applied";
        if (listener_->reconnects() > 0) s << ", reconnected " << listener_->reconnects() << " time(s)";
        s << ")";
        if (const std::string e = listener_->setupError(); !e.empty()) s << ", " << e;
    } else if (settings_.refresh.everySeconds > 0.0) {
        s << ", read again every " << settings_.refresh.everySeconds << " s (" << refreshesApplied_ << " time(s))";
    }
    if (!refreshError_.empty()) s << ", refresh: " << refreshError_;
    if (!labelError_.empty()) s << ", no labels: " << labelError_;
    if (const auto bad = icons_->errors(); !bad.empty()) s << ", " << bad.size() << " icon(s) unreadable: " << bad.front();
    if (meshLoading_ && !mesh_) s << ", building " << meshFeatures_ << " mesh feature(s)";
    if (mesh_ && !mesh_->chunks.empty())
        s << ", " << mesh_->features << " in 3-D (" << mesh_->triangles << " triangles, " << mesh_->segments << " segments, "
          << mesh_->markers << " markers; " << (meshRenderer_ ? meshRenderer_->chunksDrawn() : 0) << " of " << mesh_->chunks.size()
          << " chunks drawn)";
    if (labels_ && settings_.labels) {
        const vector::VectorLabelStats& l = labels_->stats();
        s << ", labels " << l.placed << " of " << l.candidates << " seen (" << l.labelled << " labelled), "
          << std::fixed << std::setprecision(2) << l.frameMs << " ms";
    }
    return s.str();
}

}  // namespace orbis::layers
