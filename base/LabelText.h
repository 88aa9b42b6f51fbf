#pragma once
// Text of a label (a model's name, an annotation) as screen-space rectangles, from
// stb_easy_font's stroke font (no font file, no texture): a translucent box first, then the
// strokes of the glyphs. No Vulkan.

#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace orbis::label {

struct LabelQuad {
    glm::dvec2 min, max;      ///< pixels, x right, y down
    bool background = false;  ///< the box behind the text
};

/// The label for `text` (printable ASCII; other bytes show as '?'; at most 64 characters, then
/// "...") placed right of and above `anchorPx`, glyphs scaled by `scale` (1: 7 pixels a line).
/// At most `maxQuads` rectangles, the box included.
std::vector<LabelQuad> labelQuads(const std::string& text, glm::dvec2 anchorPx, double scale, std::size_t maxQuads);

}  // namespace orbis::label
