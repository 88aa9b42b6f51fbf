#pragma once
// Label text laid out for drawing: quads in screen pixels around the label's anchor, with their
// atlas coordinates, kerned between glyphs of one font, on one line or wrapped at spaces into a
// few; and the text's box, which the label placement (LabelPlacement.h) takes as the label's
// rectangle (`labelCandidate`). No Vulkan. Main thread only: glyphs seen for the first time are
// added to the atlas.
//
// Geometry (pixels, x right, y down): `pixelSize` is the em, what a font size means in CSS or
// FreeType (DejaVu Sans' line is 1.16 em from ascent to descent). The first line's baseline is
// at y = 0; each further line is one line height (the main font's ascent + descent + line gap,
// times `lineSpacing`) lower. Left: the text starts at x = 0; Center: each line is centred on
// x = 0. The box spans the lines' advances (trailing spaces left out), from the highest ascent
// to the lowest descent of the fonts the text uses; a quad is a glyph's distance-field bitmap,
// padding included, so a halo drawn in the padding lies inside the quad (and may stick out of
// the box by the halo's width: grow the label's rectangle by it).

#include "layers/vector/GlyphAtlas.h"
#include "layers/vector/LabelPlacement.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string_view>
#include <vector>

namespace orbis::vector {

enum class TextAlign { Left, Center };

struct TextStyle {
    float pixelSize = 16.0f;          ///< the em, screen pixels
    TextAlign align = TextAlign::Center;
    float maxWidthPx = 0.0f;          ///< > 0: wrap at spaces into lines this wide at most (a longer word keeps a line to itself)
    float lineSpacing = 1.0f;         ///< times the main font's line height
};

/// One glyph to draw.
struct GlyphQuad {
    glm::vec2 min{0.0f}, max{0.0f};       ///< pixels from the anchor
    glm::vec2 uvMin{0.0f}, uvMax{0.0f};   ///< in the atlas, 0..1
};

struct TextLayout {
    std::vector<GlyphQuad> quads;
    glm::vec2 min{0.0f}, max{0.0f};   ///< the box, pixels from the anchor (empty text: all 0)
    float width = 0.0f;               ///< the widest line (pixels)
    float ascent = 0.0f;              ///< above the first baseline (pixels)
    float descent = 0.0f;             ///< below the last baseline (pixels)
    uint32_t lines = 0;
    uint32_t missing = 0;             ///< code points no font has: drawn as the main font's .notdef box
    uint32_t invalid = 0;             ///< ill-formed UTF-8 sequences: drawn as U+FFFD
    bool incomplete = false;          ///< glyphs the full atlas could not hold have no quad: clear it, lay out again
    uint32_t generation = 0;          ///< the atlas generation the quads' coordinates belong to
};

/// Lays out `utf8` with `style` into `out` (its buffers are reused: no allocation once warm).
/// '\n' breaks the line; a tab is a space; other control characters take no room.
void layoutText(GlyphAtlas& atlas, std::string_view utf8, const TextStyle& style, TextLayout& out);
TextLayout layoutText(GlyphAtlas& atlas, std::string_view utf8, const TextStyle& style);

/// The label's rectangle for LabelPlacer: the layout's box placed at `anchorPx`, grown by the
/// halo's width on every side.
LabelCandidate labelCandidate(const TextLayout& layout, glm::dvec2 anchorPx, double haloPx, uint64_t id, double priority);

}  // namespace orbis::vector
