#include "base/LabelText.h"

#include <stb_easy_font.h>

#include <algorithm>
#include <cstring>

namespace orbis::label {

std::vector<LabelQuad> labelQuads(const std::string& input, glm::dvec2 anchorPx, double scale, std::size_t maxQuads) {
    std::vector<LabelQuad> out;
    if (maxQuads < 2 || input.empty()) return out;
    std::string text;
    for (char c : input) text.push_back(c >= 32 && c < 127 ? c : '?');
    if (text.size() > 64) text = text.substr(0, 61) + "...";

    // stb_easy_font: 4 vertices of 16 bytes a quad.
    std::vector<char> buffer((maxQuads - 1) * 64);
    const int quads = stb_easy_font_print(0.0f, 0.0f, text.data(), nullptr, buffer.data(), int(buffer.size()));
    const double width = stb_easy_font_width(text.data()) * scale;
    const double height = stb_easy_font_height(text.data()) * scale;
    const double pad = 3.0 * scale;
    const glm::dvec2 origin = anchorPx + glm::dvec2(8.0 * scale, -height - 8.0 * scale);

    out.push_back({origin - pad, origin + glm::dvec2(width, height) + pad, true});
    for (int q = 0; q < quads; ++q) {
        float v[16];
        std::memcpy(v, buffer.data() + size_t(q) * 64, sizeof(v));
        // Vertices 0 and 2 are opposite corners (x, y at floats 0, 1 and 8, 9).
        const glm::dvec2 a(v[0], v[1]), b(v[8], v[9]);
        out.push_back({origin + glm::min(a, b) * scale, origin + glm::max(a, b) * scale, false});
    }
    return out;
}

}  // namespace orbis::label
