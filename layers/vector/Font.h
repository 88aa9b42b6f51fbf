#pragma once
// One TrueType font in memory, read through stb_truetype (Debian's libstb, which holds the
// implementation: nothing in Orbis defines STB_TRUETYPE_IMPLEMENTATION). Every byte range
// stb_truetype will read is checked first (FontTables.h), so a missing, truncated or foreign
// file is an error that names it, never a read past the buffer. Metrics are in em (multiply by
// the pixel size); glyphs come out as signed distance fields. No Vulkan.
// Threads: a Font does not change after `load`; its const calls may run on any thread at once
// (stb_truetype keeps no state between calls).

#include "base/Result.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace orbis::vector {

/// Debian's fonts-dejavu-core: Latin, Greek and Cyrillic, no CJK.
inline constexpr const char* kDefaultFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// How a glyph becomes a signed distance field (stbtt_GetGlyphSDF).
struct SdfParams {
    float pixelsPerEm = 32.0f;     ///< the size the glyph is rasterised at
    int paddingPx = 6;             ///< room around the outline for the field (and a halo)
    uint8_t onEdge = 128;          ///< the value on the outline
    float valuePerPixel = 128.0f / 6.0f;   ///< the value's change per pixel (inwards up, outwards down)
    int maxSizePx = 1024;          ///< a bitmap larger than this on a side is refused
};

/// A glyph's distance field: `onEdge` on the outline, clamped to 0..255.
struct GlyphBitmap {
    std::vector<uint8_t> pixels;   ///< width x height, top row first
    int width = 0, height = 0;     ///< 0 x 0 for a glyph without an outline (a space)
    int left = 0, top = 0;         ///< the top-left texel from the pen on the baseline (pixels, y down)
};

class Font {
public:
    /// Reads and checks a TrueType file (.ttf, or the first face of a .ttc). The errors name the
    /// file: no such file, not a font, truncated or damaged (which table), CFF outlines, a
    /// character map stb_truetype does not read. Never throws.
    static Result<Font> load(const std::filesystem::path& file);
    /// The same for bytes already in memory; `name` stands for the file in messages.
    static Result<Font> fromBytes(std::string bytes, const std::string& name);

    Font(Font&&) noexcept;
    Font& operator=(Font&&) noexcept;
    ~Font();

    const std::string& name() const;
    uint32_t glyphCount() const;
    /// The glyph for `codePoint`, or 0 (.notdef) when the font has none. Always < glyphCount().
    uint32_t glyphIndex(char32_t codePoint) const;

    /// The line (hhea): ascent above the baseline, descent below it (positive down), line gap.
    float ascentEm() const;
    float descentEm() const;
    float lineGapEm() const;
    float advanceEm(uint32_t glyph) const;
    /// The pen's adjustment between two glyphs (GPOS pair kerning, else the 'kern' table).
    float kerningEm(uint32_t left, uint32_t right) const;

    /// The glyph's distance field. Nothing when its outline is damaged or the bitmap would be
    /// larger than `params.maxSizePx`; an empty bitmap for a glyph without an outline.
    std::optional<GlyphBitmap> signedDistanceField(uint32_t glyph, const SdfParams& params) const;

private:
    struct State;
    explicit Font(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;   // stable: stb_truetype's fontinfo points into its bytes
};

}  // namespace orbis::vector
