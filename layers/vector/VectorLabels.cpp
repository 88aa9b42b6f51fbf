#include "layers/vector/VectorLabels.h"

#include "base/Color.h"
#include "globe/Ellipsoid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

namespace orbis::vector {
namespace {

constexpr double kPi = 3.14159265358979323846;

double millisecondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

uint32_t packSrgb(const glm::dvec4& c) {
    const auto byte = [](double v) { return uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
    return byte(c.r) | byte(c.g) << 8 | byte(c.b) << 16 | byte(c.a) << 24;
}

glm::dvec2 rotate(glm::dvec2 v, double c, double s) { return {c * v.x - s * v.y, s * v.x + c * v.y}; }

/// The entry into the ellipsoid raised by `height` of the line eye + t (point - eye), t in
/// [0, 1]: 0 when the eye is inside it, nothing when the line misses it.
std::optional<double> entryParameter(const glm::dvec3& eye, const glm::dvec3& point, double height) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const double a = wgs84.equatorialRadius() + height, b = wgs84.polarRadius() + height;
    const glm::dvec3 scale(1.0 / a, 1.0 / a, 1.0 / b);
    const glm::dvec3 o = eye * scale, d = (point - eye) * scale;
    const double qa = glm::dot(d, d), qb = glm::dot(o, d), qc = glm::dot(o, o) - 1.0;
    if (qc <= 0.0) return 0.0;
    const double disc = qb * qb - qa * qc;
    if (!(qa > 0.0) || disc < 0.0) return std::nullopt;
    const double t = (-qb - std::sqrt(disc)) / qa;
    if (t < 0.0) return std::nullopt;   // the ellipsoid is behind the eye
    return t;
}

/// ECEF to longitude, latitude (degrees) and height, approximately, for points within a few
/// tens of kilometres of the ellipsoid (the terrain test makes 32 of these a label, so the exact,
/// iterative conversion would cost more than the placement): the latitude is the geodetic
/// latitude of a point on the surface with the same z / r (off by h e^2 / N: under 20 m of
/// ground at 5 km up, 100 m at 30 km), the height is along the radius from the ellipsoid (off by
/// a factor cos(0.19 deg) at most: centimetres).
globe::Geodetic nearSurfaceGeodetic(const glm::dvec3& p) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    const double a = wgs84.equatorialRadius(), b = wgs84.polarRadius();
    const double e2 = 1.0 - (b * b) / (a * a);
    const double r2 = p.x * p.x + p.y * p.y, z2 = p.z * p.z, d2 = r2 + z2;
    const double radius = a * b * std::sqrt(d2 / (b * b * r2 + a * a * z2));   // the ellipsoid along p's direction
    return {std::atan2(p.y, p.x) * (180.0 / kPi), std::atan2(p.z, (1.0 - e2) * std::sqrt(r2)) * (180.0 / kPi),
            std::sqrt(d2) - radius};
}

}  // namespace

bool hiddenByEllipsoid(const glm::dvec3& eye, const glm::dvec3& point, double toleranceM) {
    const auto t = entryParameter(eye, point, 0.0);
    if (!t || *t == 0.0) return false;   // a miss, or an eye under the surface: nothing to hide behind
    return (1.0 - *t) * glm::length(point - eye) > toleranceM;
}

bool hiddenByGround(const glm::dvec3& eye, const glm::dvec3& point, const scene::GroundHeightFn& ground, int samples) {
    if (!ground || samples < 1) return false;
    const double d = glm::length(point - eye);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double tEnd = 1.0 - std::max(5.0, 0.002 * d) / d;
    const double tStart = entryParameter(eye, point, kGroundCeilingM).value_or(1.0);
    if (tEnd <= tStart) return false;
    const double tolerance = std::max(1.0, 1e-4 * d);
    for (int i = 1; i <= samples; ++i) {
        const double t = tStart + (tEnd - tStart) * double(i) / samples;
        const globe::Geodetic g = nearSurfaceGeodetic(eye + (point - eye) * t);
        if (g.height > kGroundCeilingM) continue;
        if (g.height < ground(g.lonDeg, g.latDeg).value_or(0.0) - tolerance) return true;
    }
    return false;
}

glm::dvec4 haloColor(const glm::dvec3& textSrgb) {
    const double luminance =
        0.2126 * srgbToLinear(textSrgb.r) + 0.7152 * srgbToLinear(textSrgb.g) + 0.0722 * srgbToLinear(textSrgb.b);
    // 0.18: mid-grey in linear light; light text gets the dark halo.
    return luminance >= 0.18 ? glm::dvec4(0.07, 0.07, 0.07, 1.0) : glm::dvec4(0.96, 0.96, 0.96, 1.0);
}

Result<VectorLabels> VectorLabels::create(const VectorLabelOptions& options) {
    auto atlas = GlyphAtlas::create(options.atlas);
    if (!atlas) return makeError("vector labels: " + atlas.message());
    return VectorLabels(std::move(*atlas), options);
}

void VectorLabels::setContent(std::shared_ptr<const VectorContent> content, std::shared_ptr<const ContentStyles> styles,
                              std::shared_ptr<const ContentAnchors> anchors, bool idsByFid) {
    content_ = std::move(content);
    styles_ = std::move(styles);
    anchors_ = std::move(anchors);
    entries_.clear();
    stats_ = {};
    if (!content_ || !styles_ || !anchors_) return;
    for (uint32_t l = 0; l < styles_->size() && l < anchors_->size(); ++l) {
        const auto& layerStyles = (*styles_)[l];
        const auto& layerAnchors = (*anchors_)[l];
        for (uint32_t i = 0; i < layerStyles.size() && i < layerAnchors.size(); ++i) {
            const FeatureStyle& s = layerStyles[i];
            const LabelAnchor& a = layerAnchors[i];
            if (!s.visible || s.label.empty() || !a.valid) continue;
            Entry& e = entries_.emplace_back();
            e.layer = l;
            e.feature = i;
            const int64_t fid = l < content_->layers.size() && i < content_->layers[l].data.features.size() ? content_->layers[l].data.features[i].fid : -1;
            e.id = uint64_t(l) << 40 | (idsByFid && fid >= 0 ? uint64_t(fid) & ((1ull << 40) - 1) : i);
            e.fid = fid;
            e.priority = labelPriority(a.kind, a.sizeM, s.rule);
            e.anchor = &a;
            e.style = &s;
        }
    }
    // Best first: when there are more candidates than the cap, the best are kept.
    std::stable_sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.priority > b.priority; });
    stats_.labelled = entries_.size();
}

void VectorLabels::clear() {
    candidates_.clear();
    seen_.clear();
    placed_.clear();
    glyphs_.clear();
    placer_.reset();
    const size_t labelled = stats_.labelled;
    stats_ = {};
    stats_.labelled = labelled;
}

void VectorLabels::locate(Entry& e, const scene::FrameContext& frame) {
    if (e.located && e.groundVersion == frame.groundVersion) return;
    const glm::dvec2 ll = e.anchor->lonLat;
    e.heightM = frame.groundHeight ? frame.groundHeight(globe::wrapLongitude(ll.x), ll.y).value_or(0.0) : 0.0;
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    e.ecef = wgs84.toEcef(ll.x, ll.y, e.heightM);
    e.surface = e.heightM >= 0.0 ? e.ecef : wgs84.toEcef(ll.x, ll.y, 0.0);
    e.groundVersion = frame.groundVersion;
    e.located = true;
}

const TextLayout& VectorLabels::layoutOf(Entry& e) {
    if (e.laidOut && e.layout.generation == atlas_.generation()) return e.layout;
    const double size = e.style->labelSizePx;
    TextStyle style{.pixelSize = float(size),
                    .align = e.anchor->kind == GeometryKind::Points ? TextAlign::Left : TextAlign::Center};
    // A polygon's name may run to several words ("Democratic Republic of the Congo"): lines of 8 em.
    if (e.anchor->kind == GeometryKind::Polygons) style.maxWidthPx = float(8.0 * size);
    layoutText(atlas_, e.style->label, style, e.layout);
    e.laidOut = true;
    return e.layout;
}

/// The frame's camera: ECEF to window pixels, in double.
struct VectorLabels::Projection {
    glm::dvec3 eye;
    glm::dmat4 clipFromEye;
    glm::dvec2 screen;

    /// False behind the eye.
    bool operator()(const glm::dvec3& p, glm::dvec2& px) const {
        const glm::dvec4 clip = clipFromEye * glm::dvec4(p - eye, 1.0);
        if (!(clip.w > 0.0)) return false;
        px = (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * screen;
        return true;
    }
};

bool VectorLabels::alongLine(const Entry& e, const TextLayout& layout, const Projection& project, Seen& s) {
    const auto& wgs84 = globe::Ellipsoid::wgs84();
    // The line on the screen at the anchor's height: the run of its samples in front of the eye
    // through the anchor (the middle sample), and the distance along it.
    const std::vector<glm::dvec2>& path = e.anchor->path;
    const size_t n = path.size(), mid = n / 2;
    std::vector<glm::dvec2> px(n);
    std::vector<char> front(n);
    for (size_t i = 0; i < n; ++i) front[i] = project(wgs84.toEcef(path[i].x, path[i].y, e.heightM), px[i]) ? 1 : 0;
    size_t first = mid, last = mid;
    if (n > 0 && front[mid]) {
        while (first > 0 && front[first - 1]) --first;
        while (last + 1 < n && front[last + 1]) ++last;
    }
    // Lengths over every part in front (as a line that leaves the view and comes back).
    double onScreen = 0.0;
    for (size_t i = 1; i < n; ++i)
        if (front[i] && front[i - 1]) onScreen += glm::length(px[i] - px[i - 1]);
    const double need = double(layout.width) + 2.0 * (options_.haloPx + options_.gapPx);
    if (onScreen < need) return false;
    glm::dvec2 ahead;
    if (!project(wgs84.toEcef(e.anchor->ahead.x, e.anchor->ahead.y, e.heightM), ahead)) return false;
    const glm::dvec2 direction = ahead - s.anchorPx;
    if (!(glm::length(direction) > 0.0)) return false;
    // Straight along the line at the anchor, upright: text never reads upside down.
    s.angle = std::atan2(direction.y, direction.x);
    if (s.angle > 0.5 * kPi) s.angle -= kPi;
    if (s.angle < -0.5 * kPi) s.angle += kPi;
    s.bentFirst = uint32_t(bent_.size());
    s.bentCount = 0;
    if (n == 0 || !front[mid] || last == first) return true;

    // Bent: each glyph's middle at its distance from the label's middle along the line, turned
    // with the line there. Only where the whole label fits on the run through the anchor and
    // the line bends gently under it; else the straight label stands.
    std::vector<double> arc(n, 0.0);
    for (size_t i = first + 1; i <= last; ++i) arc[i] = arc[i - 1] + glm::length(px[i] - px[i - 1]);
    const double centre = arc[mid], half = 0.5 * need;
    if (centre - half < 0.0 || centre + half > arc[last]) return true;
    // The point at `at` along the run, and the direction of the segment it lies on.
    const auto along = [&](double at, glm::dvec2& tangent) {
        size_t i = first;
        while (i + 1 < last && arc[i + 1] < at) ++i;
        const double len = arc[i + 1] - arc[i];
        tangent = len > 0.0 ? (px[i + 1] - px[i]) / len : glm::dvec2(std::cos(s.angle), std::sin(s.angle));
        return px[i] + tangent * std::clamp(at - arc[i], 0.0, len);
    };
    glm::dvec2 t0, t1;
    const bool reverse = along(centre + half, t1).x < along(centre - half, t0).x;   // read left to right
    constexpr double kMaxBend = kMaxBendDeg * kPi / 180.0;
    double previous = 0.0;
    for (size_t k = 0; k < layout.quads.size(); ++k) {
        const GlyphQuad& q = layout.quads[k];
        const double middle = 0.5 * double(q.min.x + q.max.x) + s.offset.x;   // from the label's middle
        glm::dvec2 tangent;
        const glm::dvec2 at = along(reverse ? centre - middle : centre + middle, tangent);
        if (reverse) tangent = -tangent;
        const double angle = std::atan2(tangent.y, tangent.x);
        if (k > 0 && std::abs(std::remainder(angle - previous, 2.0 * kPi)) > kMaxBend) {
            bent_.resize(s.bentFirst);   // too sharp a bend: straight
            return true;
        }
        previous = angle;
        const glm::dvec2 corner = at + rotate(glm::dvec2(double(q.min.x) - 0.5 * double(q.min.x + q.max.x), double(q.min.y) + s.offset.y),
                                              std::cos(angle), std::sin(angle));
        bent_.emplace_back(corner, angle);
    }
    s.bentCount = uint32_t(bent_.size() - s.bentFirst);
    return true;
}

LabelCandidate VectorLabels::candidateOf(const Entry& e, const TextLayout& layout, const Seen& s) const {
    // The text's box (halo and gap included), turned, and the icon's.
    const double grow = options_.haloPx + options_.gapPx;
    glm::dvec2 boxMin(std::numeric_limits<double>::max()), boxMax(std::numeric_limits<double>::lowest());
    if (const auto bent = bentOf(s); !bent.empty()) {   // bent: the glyphs' boxes together
        for (size_t k = 0; k < bent.size() && k < layout.quads.size(); ++k) {
            const glm::dvec2 size = glm::dvec2(layout.quads[k].max - layout.quads[k].min);
            const double c = std::cos(bent[k].z), sn = std::sin(bent[k].z);
            for (const glm::dvec2 corner : {glm::dvec2(-grow), glm::dvec2(size.x + grow, -grow), glm::dvec2(-grow, size.y + grow), size + grow}) {
                const glm::dvec2 p = glm::dvec2(bent[k]) + rotate(corner, c, sn);
                boxMin = glm::min(boxMin, p);
                boxMax = glm::max(boxMax, p);
            }
        }
        return {.id = idBase_ + e.id, .priority = e.priority, .min = boxMin, .max = boxMax};
    }
    const glm::dvec2 lo = glm::dvec2(layout.min) - grow, hi = glm::dvec2(layout.max) + grow;
    const double c = std::cos(s.angle), sn = std::sin(s.angle);
    for (const glm::dvec2 corner : {lo, glm::dvec2(hi.x, lo.y), glm::dvec2(lo.x, hi.y), hi}) {
        const glm::dvec2 p = s.anchorPx + rotate(corner + s.offset, c, sn);
        boxMin = glm::min(boxMin, p);
        boxMax = glm::max(boxMax, p);
    }
    if (e.anchor->kind == GeometryKind::Points) {
        const double iconHalf = 0.5 * s.iconPx + options_.gapPx;
        boxMin = glm::min(boxMin, s.anchorPx - iconHalf);
        boxMax = glm::max(boxMax, s.anchorPx + iconHalf);
    }
    return {.id = idBase_ + e.id, .priority = e.priority, .min = boxMin, .max = boxMax};
}

bool VectorLabels::gatherOnce(const scene::FrameContext& frame, const glm::dmat4& clipFromEye) {
    candidates_.clear();
    seen_.clear();
    bent_.clear();
    bool atlasFull = false;
    const Projection project{frame.camera->position(), clipFromEye, glm::dvec2(frame.width, frame.height)};
    for (uint32_t index = 0; index < entries_.size(); ++index) {
        Entry& e = entries_[index];
        const FeatureTimes& times = content_->layers[e.layer].times;
        if (times.timed() && !times.spans[e.feature].shows(frame.time)) continue;
        locate(e, frame);
        glm::dvec3 at = e.ecef, surface = e.surface;
        if (markerPlace_ && e.fid >= 0 && e.fid < int64_t(UINT32_MAX) && e.anchor->kind == GeometryKind::Points)
            if (const auto marker = markerPlace_(uint32_t(e.fid + 1))) at = surface = *marker;
        const double distance = glm::length(at - project.eye);
        if (distance < e.style->minRangeM || distance > e.style->maxRangeM) continue;
        glm::dvec2 px;
        if (!project(at, px) || px.x < 0.0 || px.y < 0.0 || px.x > project.screen.x || px.y > project.screen.y) continue;
        if (hiddenByEllipsoid(project.eye, surface)) continue;
        if (candidates_.size() >= options_.maxCandidates) {
            stats_.capped = true;
            break;
        }
        const TextLayout& layout = layoutOf(e);
        atlasFull = atlasFull || layout.incomplete;
        if (layout.quads.empty()) continue;

        Seen s{index, px, glm::dvec2(0.0), 0.0, e.style->iconSizeAt(distance)};
        s.at = at;
        const glm::dvec2 lo(layout.min), hi(layout.max);
        if (e.anchor->kind == GeometryKind::Points)   // right of the icon, centred on the point's height
            s.offset = glm::dvec2(0.5 * s.iconPx + options_.iconGapPx, -0.5 * (lo.y + hi.y));
        else   // centred on the anchor
            s.offset = -0.5 * (lo + hi);
        if (e.anchor->kind == GeometryKind::Lines && !alongLine(e, layout, project, s)) continue;
        candidates_.push_back(candidateOf(e, layout, s));
        seen_.push_back(s);
    }
    return !atlasFull;
}

void VectorLabels::addGlyphs(const Seen& s) {
    Entry& e = entries_[s.entry];
    const TextLayout& layout = e.layout;
    const double c = std::cos(s.angle), sn = std::sin(s.angle);
    const auto bent = bentOf(s);
    // Unturned text on whole pixels: the glyphs keep their sampling phase as the view pans.
    glm::dvec2 origin = s.anchorPx + rotate(s.offset, c, sn);
    if (s.angle == 0.0) origin = glm::round(origin);
    const double size = e.style->labelSizePx;
    const double valuePerScreenPixel = double(atlas_.sdfValuePerPixel()) * atlas_.rasterPixelsPerEm() / size;
    const double onEdge = atlas_.sdfOnEdge();
    // The halo ends inside the field's padding (the field is 0 beyond it).
    const double haloEdge = std::max(onEdge - options_.haloPx * valuePerScreenPixel, double(atlas_.sdfValuePerPixel()));
    const uint32_t text = packSrgb(glm::dvec4(e.style->labelColor, 1.0));
    const uint32_t halo = packSrgb(haloColor(e.style->labelColor));
    for (size_t k = 0; k < layout.quads.size(); ++k) {
        const GlyphQuad& q = layout.quads[k];
        const glm::dvec2 lo(q.min), hi(q.max);
        shader::LabelGlyph g{};
        if (k < bent.size()) {   // bent along a line: each glyph at its own place and angle
            const double gc = std::cos(bent[k].z), gs = std::sin(bent[k].z);
            g.origin = glm::vec2(glm::dvec2(bent[k]));
            g.axisX = glm::vec2(rotate(glm::dvec2(hi.x - lo.x, 0.0), gc, gs));
            g.axisY = glm::vec2(rotate(glm::dvec2(0.0, hi.y - lo.y), gc, gs));
        } else {
            g.origin = glm::vec2(origin + rotate(lo, c, sn));
            g.axisX = glm::vec2(rotate(glm::dvec2(hi.x - lo.x, 0.0), c, sn));
            g.axisY = glm::vec2(rotate(glm::dvec2(0.0, hi.y - lo.y), c, sn));
        }
        g.uv = glm::vec4(q.uvMin, q.uvMax);
        g.edges = glm::vec2(float(onEdge), float(haloEdge));
        g.color = text;
        g.halo = halo;
        glyphs_.push_back(g);
    }
}

void VectorLabels::setIdBase(uint64_t base) {
    if (base == idBase_) return;
    idBase_ = base;
    placer_.reset();   // last frame's ids are not this frame's
}

void VectorLabels::gather(const scene::FrameContext& frame) {
    const auto t0 = std::chrono::steady_clock::now();
    placed_.clear();
    glyphs_.clear();
    const size_t labelled = stats_.labelled;
    stats_ = {};
    stats_.labelled = labelled;
    if (!frame.camera || frame.width == 0 || frame.height == 0 || !content_ || entries_.empty()) {
        candidates_.clear();
        seen_.clear();
        return;
    }
    const glm::dmat4 clipFromEye = frame.camera->projection(frame.aspect()) * frame.camera->viewRotation();
    if (!gatherOnce(frame, clipFromEye)) {
        // A glyph did not fit: start the atlas again with this frame's labels only.
        atlas_.clear();
        gatherOnce(frame, clipFromEye);
    }
    stats_.candidates = candidates_.size();
    stats_.gatherMs = millisecondsSince(t0);
}

bool VectorLabels::hiddenByGround(uint32_t index, const scene::FrameContext& frame) const {
    return frame.camera && vector::hiddenByGround(frame.camera->position(), seen_[index].at, frame.groundHeight);
}

void VectorLabels::build(std::span<const uint32_t> chosen, double placementMs, size_t hidden) {
    const auto t0 = std::chrono::steady_clock::now();
    placed_.clear();
    glyphs_.clear();
    for (uint32_t i : chosen) {
        const Entry& e = entries_[seen_[i].entry];
        placed_.push_back({.id = candidates_[i].id, .layer = e.layer, .feature = e.feature, .min = candidates_[i].min,
                           .max = candidates_[i].max});
        addGlyphs(seen_[i]);
    }
    stats_.placed = placed_.size();
    stats_.glyphs = glyphs_.size();
    stats_.hidden = hidden;
    stats_.placementMs = placementMs;
    stats_.frameMs = stats_.gatherMs + placementMs + millisecondsSince(t0);
}

void VectorLabels::update(const scene::FrameContext& frame) {
    gather(frame);
    const auto t0 = std::chrono::steady_clock::now();
    const LabelPlacementOptions placement{.screen = {double(frame.width), double(frame.height)},
                                          .marginPx = options_.marginPx,
                                          .priorityHysteresis = options_.priorityHysteresis};
    const auto visible = [&](uint32_t i) { return !hiddenByGround(i, frame); };
    const std::vector<uint32_t> chosen = frame.groundHeight ? placer_.place(candidates_, placement, visible)
                                                            : placer_.place(candidates_, placement);
    build(chosen, millisecondsSince(t0), placer_.stats().rejectedHidden);
}

}  // namespace orbis::vector
