#include "layers/vector/LabelLayout.h"

#include "base/Utf8.h"

#include <algorithm>
#include <limits>

namespace orbis::vector {
namespace {

constexpr uint32_t kNoGlyph = ~0u;

bool takesNoRoom(char32_t c) { return c < 0x20 || (c >= 0x7F && c < 0xA0); }   // C0, DEL, C1

/// The lines of one layout as they are built: quads go in at x from the line's start and y from
/// its baseline, and move to their place when their line ends.
class LineBuilder {
public:
    LineBuilder(TextLayout& out, const TextStyle& style, float lineAdvancePx)
        : out_(out), style_(style), lineAdvancePx_(lineAdvancePx) {}

    /// Ends the line at quad `end` (the rest move to the next line), `widthEm` wide.
    void finish(std::size_t end, float widthEm) {
        const float size = style_.pixelSize;
        const float leftEm = style_.align == TextAlign::Center ? -0.5f * widthEm : 0.0f;
        const glm::vec2 shift(leftEm * size, float(out_.lines) * lineAdvancePx_);
        for (std::size_t q = lineStart_; q < end; ++q) {
            out_.quads[q].min += shift;
            out_.quads[q].max += shift;
        }
        minEm_ = std::min(minEm_, leftEm);
        maxEm_ = std::max(maxEm_, leftEm + widthEm);
        widestEm_ = std::max(widestEm_, widthEm);
        ++out_.lines;
        lineStart_ = end;
    }
    /// Moves the quads from `first` on left by `em` (they start the new line).
    void shiftLeft(std::size_t first, float em) {
        const float px = em * style_.pixelSize;
        for (std::size_t q = first; q < out_.quads.size(); ++q) {
            out_.quads[q].min.x -= px;
            out_.quads[q].max.x -= px;
        }
    }
    float minEm() const { return minEm_; }
    float maxEm() const { return maxEm_; }
    float widestEm() const { return widestEm_; }

private:
    TextLayout& out_;
    const TextStyle& style_;
    float lineAdvancePx_;
    std::size_t lineStart_ = 0;
    float minEm_ = std::numeric_limits<float>::max(), maxEm_ = std::numeric_limits<float>::lowest(), widestEm_ = 0.0f;
};

void reset(TextLayout& out, uint32_t generation) {
    out.quads.clear();
    out.min = out.max = glm::vec2(0.0f);
    out.width = out.ascent = out.descent = 0.0f;
    out.lines = out.missing = out.invalid = 0;
    out.incomplete = false;
    out.generation = generation;
}

}  // namespace

void layoutText(GlyphAtlas& atlas, std::string_view utf8, const TextStyle& style, TextLayout& out) {
    reset(out, atlas.generation());
    if (utf8.empty() || !(style.pixelSize > 0.0f)) return;
    const Font& main = atlas.font(0);
    const float size = style.pixelSize;
    const float lineAdvancePx = style.lineSpacing * (main.ascentEm() + main.descentEm() + main.lineGapEm()) * size;
    const float maxWidthEm = style.maxWidthPx > 0.0f ? style.maxWidthPx / size : std::numeric_limits<float>::infinity();
    const glm::vec2 texel(1.0f / float(atlas.width()), 1.0f / float(atlas.height()));
    LineBuilder lines(out, style, lineAdvancePx);

    float penEm = 0.0f, inkEm = 0.0f;   // from the line's start: the pen, and the end of its last non-space glyph
    bool canBreak = false;              // a space on this line: where it may wrap
    std::size_t breakQuad = 0;
    float breakInkEm = 0.0f, breakPenEm = 0.0f;
    uint32_t previous = kNoGlyph;
    uint32_t fontsUsed = 1;             // a bit per font (the first 32), for the box's height

    for (std::size_t pos = 0; pos < utf8.size();) {
        bool valid = true;
        char32_t c = decodeUtf8(utf8, pos, valid);
        out.invalid += valid ? 0 : 1;
        if (c == U'\n') {
            lines.finish(out.quads.size(), inkEm);
            penEm = inkEm = 0.0f;
            canBreak = false;
            previous = kNoGlyph;
            continue;
        }
        if (c == U'\t') c = U' ';
        if (takesNoRoom(c)) continue;
        const uint32_t id = atlas.entryFor(c);
        const GlyphEntry& glyph = atlas.entry(id);
        out.missing += glyph.glyph == 0 ? 1 : 0;
        if (glyph.font < 32) fontsUsed |= 1u << glyph.font;
        if (previous != kNoGlyph) penEm += atlas.kerningEm(previous, id);
        previous = id;
        if (c == U' ') {
            canBreak = true;
            breakQuad = out.quads.size();
            breakInkEm = inkEm;
            penEm += glyph.advanceEm;
            breakPenEm = penEm;
            continue;
        }
        if (canBreak && penEm + glyph.advanceEm > maxWidthEm) {
            // The word since the last space starts the next line.
            lines.finish(breakQuad, breakInkEm);
            lines.shiftLeft(breakQuad, breakPenEm);
            penEm -= breakPenEm;
            inkEm = std::max(0.0f, inkEm - breakPenEm);
            canBreak = false;
        }
        if (!glyph.rect.empty()) {
            GlyphQuad& quad = out.quads.emplace_back();
            quad.min = glm::vec2(penEm + glyph.offsetEm.x, glyph.offsetEm.y) * size;
            quad.max = quad.min + glyph.sizeEm * size;
            quad.uvMin = glm::vec2(float(glyph.rect.x), float(glyph.rect.y)) * texel;
            quad.uvMax = glm::vec2(float(glyph.rect.x + glyph.rect.width), float(glyph.rect.y + glyph.rect.height)) * texel;
        } else if (glyph.pending) {
            out.incomplete = true;
        }
        penEm += glyph.advanceEm;
        inkEm = penEm;
    }
    lines.finish(out.quads.size(), inkEm);

    float ascentEm = 0.0f, descentEm = 0.0f;
    for (uint32_t f = 0; f < atlas.fontCount() && f < 32; ++f) {
        if (!(fontsUsed & (1u << f))) continue;
        ascentEm = std::max(ascentEm, atlas.font(f).ascentEm());
        descentEm = std::max(descentEm, atlas.font(f).descentEm());
    }
    out.width = lines.widestEm() * size;
    out.ascent = ascentEm * size;
    out.descent = descentEm * size;
    out.min = glm::vec2(lines.minEm() * size, -out.ascent);
    out.max = glm::vec2(lines.maxEm() * size, float(out.lines - 1) * lineAdvancePx + out.descent);
}

TextLayout layoutText(GlyphAtlas& atlas, std::string_view utf8, const TextStyle& style) {
    TextLayout out;
    layoutText(atlas, utf8, style, out);
    return out;
}

LabelCandidate labelCandidate(const TextLayout& layout, glm::dvec2 anchorPx, double haloPx, uint64_t id, double priority) {
    return {.id = id,
            .priority = priority,
            .min = anchorPx + glm::dvec2(layout.min) - haloPx,
            .max = anchorPx + glm::dvec2(layout.max) + haloPx};
}

}  // namespace orbis::vector
