#include "layers/annotations/PinOverlay.h"

#include "base/Color.h"
#include "base/LabelText.h"
#include "globe/Culling.h"
#include "globe/Ellipsoid.h"

#include <algorithm>
#include <cmath>

namespace orbis::layers {
namespace {

constexpr int kOcclusionSamples = 64;

struct Placed {
    size_t index;
    double distance;
    glm::dvec2 px;
};

}  // namespace

bool pinHidden(const glm::dvec3& eye, const glm::dvec3& point, const scene::GroundHeightFn& ground) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const double d = glm::length(point - eye);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    if (globe::sphereBelowHorizon(eye, point, 0.0)) return true;
    const double tEnd = 1.0 - std::max(5.0, 0.002 * d) / d;
    const double tolerance = std::max(1.0, 1e-4 * d);
    for (int i = 1; i <= kOcclusionSamples && tEnd > 0.0; ++i) {
        const double t = tEnd * double(i) / kOcclusionSamples;
        const globe::Geodetic g = wgs84.toGeodetic(eye + (point - eye) * t);
        const double floor = (ground ? ground(g.lonDeg, g.latDeg) : std::nullopt).value_or(0.0);
        if (g.height < floor - tolerance) return true;
    }
    return false;
}

PinLayout layoutPins(const std::vector<scene::Annotation>& pins, const scene::Camera& camera, uint32_t width,
                     uint32_t height, const scene::GroundHeightFn& ground, const PinStyle& style, std::size_t maxQuads) {
    PinLayout out;
    if (width == 0 || height == 0) return out;
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const glm::dvec3 eye = camera.position();
    const glm::dmat4 clipFromEye = camera.projection(double(width) / double(height)) * camera.viewRotation();

    std::vector<Placed> seen;
    for (size_t i = 0; i < pins.size(); ++i) {
        const scene::Annotation& a = pins[i];
        const glm::dvec3 p = wgs84.toEcef(globe::Geodetic{a.lonDeg, a.latDeg, a.height});
        const glm::dvec4 clip = clipFromEye * glm::dvec4(p - eye, 1.0);
        if (!(clip.w > 0.0)) continue;
        const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
        if (!(std::abs(ndc.x) <= 1.2 && std::abs(ndc.y) <= 1.2)) continue;   // NaN fails too
        if (pinHidden(eye, p, ground)) continue;
        seen.push_back({i, glm::length(p - eye), {(ndc.x * 0.5 + 0.5) * width, (ndc.y * 0.5 + 0.5) * height}});
    }
    std::sort(seen.begin(), seen.end(), [](const Placed& a, const Placed& b) { return a.distance < b.distance; });

    const glm::vec4 head(float(srgbToLinear(style.color.r)), float(srgbToLinear(style.color.g)),
                         float(srgbToLinear(style.color.b)), 1.0f);
    const glm::vec4 dark(0.0f, 0.0f, 0.0f, 0.8f), white(1.0f, 1.0f, 1.0f, 1.0f), box(0.0f, 0.0f, 0.0f, 0.55f);
    // Each pin's rectangles, nearest pin first; laid out back to front afterwards.
    std::vector<std::vector<PinQuad>> perPin;
    size_t used = 0;
    for (const Placed& s : seen) {
        std::vector<PinQuad> q;
        const glm::dvec2 p = s.px;
        const double stem = style.stemPx, h = style.headPx;
        const glm::dvec2 headMin(p.x - 0.5 * h, p.y - stem - h), headMax(p.x + 0.5 * h, p.y - stem);
        q.push_back({{p.x - 2.0, p.y - stem}, {p.x + 2.0, p.y + 1.0}, dark});   // stem, outlined
        q.push_back({{p.x - 1.0, p.y - stem}, {p.x + 1.0, p.y}, white});
        q.push_back({headMin - 1.5, headMax + 1.5, dark});
        q.push_back({headMin, headMax, head});
        if (style.labels && !pins[s.index].name.empty() && maxQuads > used + q.size() + 2) {
            // labelQuads puts the text 8 units right of and above its anchor: this centres a
            // line of text (7 units) on the head, just right of it.
            const double k = style.labelScale;
            const glm::dvec2 labelAnchor(headMax.x + 6.0 - 8.0 * k, 0.5 * (headMin.y + headMax.y) + 11.5 * k);
            const size_t room = std::min<size_t>(maxQuads - used - q.size(), 1024);
            for (const label::LabelQuad& l :
                 label::labelQuads(pins[s.index].name, labelAnchor, style.labelScale, room))
                q.push_back({l.min, l.max, l.background ? box : white});
        }
        if (used + q.size() > maxQuads) {
            out.dropped = seen.size() - perPin.size();
            break;
        }
        used += q.size();
        perPin.push_back(std::move(q));
    }
    out.drawn = perPin.size();
    out.quads.reserve(used);
    for (auto it = perPin.rbegin(); it != perPin.rend(); ++it) out.quads.insert(out.quads.end(), it->begin(), it->end());
    return out;
}

}  // namespace orbis::layers
