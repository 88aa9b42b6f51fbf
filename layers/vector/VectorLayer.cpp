#include "layers/vector/VectorLayer.h"

#include "base/Log.h"
#include "engine/render/RenderContext.h"
#include "layers/vector/FeaturePick.h"

#include <sstream>

namespace orbis::layers {

VectorLayer::VectorLayer(VectorLayerSettings settings) : settings_(std::move(settings)) {}

VectorLayer::~VectorLayer() {
    if (loading_) job_.wait();
}

void VectorLayer::onPrepare(const render::RenderServices& services) {
    // Read on the pool: the first frames draw the rest of the scene meanwhile.
    loading_ = true;
    job_ = services.jobs().submit(0.0, jobs::CancelToken{}, [options = settings_.content](const jobs::CancelToken&) {
        return vector::loadVectorContent(options);
    });
}

void VectorLayer::poll() {
    if (!loading_ || !job_.ready()) return;
    loading_ = false;
    Result<std::shared_ptr<vector::VectorContent>> r = makeError("vector: the read was cancelled");
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
    content_ = std::move(*r);
    for (const std::string& w : content_->warnings) log::warn("vector layer \"", settings_.name, "\": ", w);
    styles_ = std::make_shared<const vector::ContentStyles>(vector::styleContent(*content_));
    shownSignature_ = vector::shownAtSignature(*content_, time_);
    republish();
}

void VectorLayer::update(const scene::FrameContext& frame) {
    time_ = frame.time;
    if (!content_) return;
    // Features with times come and go with the clock: paint again only when the set changes.
    const uint64_t shown = vector::shownAtSignature(*content_, time_);
    if (shown != shownSignature_) {
        shownSignature_ = shown;
        republish();
    }
}

void VectorLayer::republish() {
    drape_ = std::make_shared<const vector::VectorDrape>(settings_.name.empty() ? settings_.content.read.source : settings_.name,
                                                         content_, styles_, time_, settings_.maxLevel, highlight_);
    ++version_;
}

std::optional<scene::PickedAttributes> VectorLayer::pickAt(double lonDeg, double latDeg, double metresPerPixel) {
    std::optional<vector::PickedFeature> hit;
    if (content_)
        hit = vector::pickFeature(*content_, *styles_, {.lonDeg = lonDeg, .latDeg = latDeg, .metresPerPixel = metresPerPixel, .time = time_});
    const std::optional<std::pair<size_t, size_t>> now = hit ? std::optional(std::make_pair(hit->layer, hit->feature)) : std::nullopt;
    if (now != highlight_) {
        highlight_ = now;
        republish();
    }
    if (!hit) return std::nullopt;
    const vector::VectorLayer& source = content_->layers[hit->layer].data;
    const vector::Feature& f = source.features[hit->feature];
    scene::PickedAttributes out;
    out.layer = (settings_.name.empty() ? settings_.content.read.source : settings_.name) + " / " + source.name;
    out.feature = "fid " + std::to_string(f.fid);
    for (size_t i = 0; i < source.fields.size() && i < f.attributes.size(); ++i)
        out.fields.emplace_back(source.fields[i].name, vector::attributeText(f.attributes[i]));
    return out;
}

void VectorLayer::clearPick() {
    if (!highlight_) return;
    highlight_.reset();
    if (content_) republish();
}

std::vector<scene::LayerSetting> VectorLayer::liveSettings() const {
    using Kind = scene::LayerSetting::Kind;
    std::vector<scene::LayerSetting> out = {
        {.name = "opacity", .label = "Opacity", .kind = Kind::Number, .value = settings_.opacity,
         .min = kOpacityRange.min, .max = kOpacityRange.max},
    };
    const vector::VectorStyle& style = settings_.content.style;
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
    vector::VectorStyle& style = settings_.content.style;
    for (size_t i = 0; i < style.ruleCount(); ++i) {
        if (name != "rule" + std::to_string(i) || (value != 0.0 && value != 1.0)) continue;
        style.setRuleEnabled(i, value != 0.0);
        if (content_) {
            for (vector::ContentLayer& layer : content_->layers) layer.style.setRuleEnabled(i, value != 0.0);
            styles_ = std::make_shared<const vector::ContentStyles>(vector::styleContent(*content_));
            republish();
        }
        return true;
    }
    return false;
}

std::string VectorLayer::status() const {
    if (!error_.empty()) return "error: " + error_;
    if (loading_) return "reading " + settings_.content.read.source;
    if (!content_) return {};
    std::ostringstream s;
    s << content_->featureCount << " features in " << content_->layers.size() << " layer(s), " << content_->vertexCount
      << " vertices";
    if (!content_->warnings.empty()) s << ", " << content_->warnings.size() << " warning(s)";
    return s.str();
}

}  // namespace orbis::layers
