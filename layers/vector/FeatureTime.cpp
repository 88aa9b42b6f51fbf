#include "layers/vector/FeatureTime.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace orbis::vector {
namespace {

constexpr size_t kMaxWarnings = 20;


/// A time from a value: ISO 8601 text or Unix seconds (a number, or text that is one); nullopt
/// for null; an error otherwise.
Result<std::optional<TimeNs>> timeOf(const AttributeValue& v) {
    if (std::holds_alternative<std::monostate>(v)) return std::optional<TimeNs>{};
    double seconds = 0.0;
    if (const auto* text = std::get_if<std::string>(&v)) {
        if (text->empty()) return std::optional<TimeNs>{};
        char* end = nullptr;
        seconds = std::strtod(text->c_str(), &end);
        if (end == text->c_str() || *end != '\0' || text->find_first_of("-:T ", 1) != std::string::npos) {
            auto t = parseIso8601(*text);
            if (!t) return t.error();
            return std::optional<TimeNs>{*t};
        }
    } else {
        seconds = std::holds_alternative<int64_t>(v) ? double(std::get<int64_t>(v)) : std::get<double>(v);
    }
    // Unix seconds within the years TimeNs holds.
    if (!std::isfinite(seconds) || std::abs(seconds) > 9.2e9) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", seconds);
        return makeError(std::string("the number ") + text + " is not a time");
    }
    return std::optional<TimeNs>{fromSeconds(seconds)};
}

}  // namespace

Result<FeatureTimes> featureTimes(const VectorLayer& layer, const FeatureTimeFields& asked) {
    // The fields: the scene's, else KML's (a TimeSpan's begin and end, or a TimeStamp).
    std::optional<size_t> begin, end, stamp;
    std::string beginName = asked.begin, endName = asked.end;
    if (asked.begin.empty() && asked.end.empty()) {
        begin = findField(layer.fields, "begin");
        end = findField(layer.fields, "end");
        stamp = findField(layer.fields, "timestamp");
        beginName = "begin";
        endName = "end";
    } else {
        for (const auto& [name, index] : {std::pair{&asked.begin, &begin}, std::pair{&asked.end, &end}}) {
            if (name->empty()) continue;
            *index = findField(layer.fields, *name);
            if (!*index)
                return makeError("layer '" + layer.name + "' has no time field '" + *name + "' (its fields: " +
                                 fieldNames(layer.fields) + ")");
        }
    }
    FeatureTimes out;
    if (!begin && !end && !stamp) return out;
    out.spans.resize(layer.features.size());
    size_t problems = 0;
    for (size_t i = 0; i < layer.features.size(); ++i) {
        const Feature& f = layer.features[i];
        FeatureTimeSpan& span = out.spans[i];
        const auto read = [&](std::optional<size_t> index, const std::string& name) -> std::optional<TimeNs> {
            if (!index || *index >= f.attributes.size() || span.hidden) return std::nullopt;
            auto t = timeOf(f.attributes[*index]);
            if (t) return *t;
            span.hidden = true;
            if (++problems <= kMaxWarnings)
                out.warnings.push_back("layer '" + layer.name + "': feature " + std::to_string(f.fid) + ": field '" + name +
                                       "': " + t.message() + " (the feature is not shown)");
            return std::nullopt;
        };
        span.begin = read(begin, beginName);
        span.end = read(end, endName);
        if (!span.begin && !span.end) span.begin = read(stamp, "timestamp");   // a TimeStamp: from then on
        if (span.hidden) {
            span.begin.reset();
            span.end.reset();
            continue;
        }
        for (const std::optional<TimeNs>& t : {span.begin, span.end})
            if (t) {
                out.first = out.first ? std::min(*out.first, *t) : *t;
                out.last = out.last ? std::max(*out.last, *t) : *t;
            }
    }
    if (problems > kMaxWarnings) out.warnings.push_back(std::to_string(problems - kMaxWarnings) + " more features with a bad time");
    return out;
}

}  // namespace orbis::vector
