#include "layers/vector/VectorContent.h"

#include "base/Secrets.h"

namespace orbis::vector {

uint64_t featureBytes(const Feature& f) {
    uint64_t bytes = sizeof(Feature) + f.coords.size() * sizeof(glm::dvec3) + (f.parts.size() + f.polygons.size()) * sizeof(uint32_t) +
                     f.containsPole.size() + f.attributes.size() * sizeof(AttributeValue);
    for (const AttributeValue& a : f.attributes)
        if (const auto* text = std::get_if<std::string>(&a)) bytes += text->capacity();
    return bytes;
}

Result<std::shared_ptr<VectorContent>> loadVectorContent(const VectorContentOptions& options) {
    auto data = readVector(options.read);
    if (!data) return data.error();
    return contentFromData(std::move(*data), options);
}

Result<std::shared_ptr<VectorContent>> contentFromData(VectorData data, const VectorContentOptions& options) {
    auto content = std::make_shared<VectorContent>();
    content->source = data.source;
    for (VectorLayer& layer : data.layers) {
        ContentLayer out;
        out.style = options.style;
        if (auto bound = out.style.bind(layer.fields, layer.name); !bound)
            return makeError(redactSecrets(options.read.source) + ": " + bound.message());
        auto times = featureTimes(layer, options.timeFields);
        if (!times) return makeError(redactSecrets(options.read.source) + ": layer \"" + layer.name + "\": " + times.message());
        out.times = std::move(*times);
        for (const std::string& w : layer.warnings) content->warnings.push_back(layer.name + ": " + w);
        for (const std::string& w : out.times.warnings) content->warnings.push_back(layer.name + ": " + w);
        if (out.times.first && (!content->firstTime || *out.times.first < *content->firstTime))
            content->firstTime = out.times.first;
        if (out.times.last && (!content->lastTime || *out.times.last > *content->lastTime))
            content->lastTime = out.times.last;
        content->featureCount += layer.features.size();
        content->vertexCount += layer.vertexCount;
        for (const Feature& f : layer.features) content->bytes += featureBytes(f);
        out.data = std::move(layer);
        content->layers.push_back(std::move(out));
    }
    return content;
}

ContentStyles styleContent(const VectorContent& content) {
    ContentStyles styles(content.layers.size());
    for (size_t l = 0; l < content.layers.size(); ++l) {
        const ContentLayer& layer = content.layers[l];
        styles[l].reserve(layer.data.features.size());
        for (const Feature& f : layer.data.features) {
            const SourceStyle* own = f.style >= 0 && size_t(f.style) < layer.data.styles.size() ? &layer.data.styles[size_t(f.style)]
                                                                                                 : nullptr;
            styles[l].push_back(layer.style.evaluate(f.attributes, own));
        }
    }
    return styles;
}

uint64_t shownAtSignature(const VectorContent& content, TimeNs t) {
    // FNV-1a over the indices of the timed features shown at t.
    uint64_t h = 1469598103934665603ull;
    bool any = false;
    for (size_t l = 0; l < content.layers.size(); ++l) {
        const FeatureTimes& times = content.layers[l].times;
        for (size_t i = 0; i < times.spans.size(); ++i) {
            if (times.spans[i].always() || !times.spans[i].shows(t)) continue;
            any = true;
            h = (h ^ (uint64_t(l) << 40 ^ uint64_t(i))) * 1099511628211ull;
        }
    }
    return any ? h : 1;
}

}  // namespace orbis::vector
