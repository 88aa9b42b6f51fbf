#pragma once
// The checks a TrueType file must pass before stb_truetype reads it. stb_truetype trusts every
// offset and count in the file (it has no bounds checks, and Debian builds it with assertions
// on, so an unsupported cmap format aborts the process): a truncated download or a file that is
// not a font would read past the buffer. These functions walk exactly what stb_truetype will
// read (the table directory, head, hhea, hmtx, maxp, loca, the Unicode cmap subtable it picks,
// kern, GPOS pair kerning, and each glyph's outline before it is drawn) and say what is wrong.
// Only TrueType outlines (glyf): stb_truetype's CFF reader ignores the table's length.
// No Vulkan; no stb_truetype here, only the file format. Any thread (pure functions).

#include "base/Result.h"

#include <cstdint>
#include <span>

namespace orbis::vector::font {

/// Where one table lies in the file (absolute offset); length 0 when the font has none.
struct TableRange {
    uint32_t offset = 0, length = 0;
    bool present() const { return length > 0; }
};

/// What the checks found, for the glyph checks that follow and for the font's metrics.
struct FontTables {
    uint32_t faceOffset = 0;
    TableRange cmap, head, hhea, hmtx, maxp, loca, glyf, kern, gpos;
    uint16_t numGlyphs = 0;
    uint16_t numHMetrics = 0;
    uint16_t unitsPerEm = 0;
    bool longLoca = false;       ///< head.indexToLocFormat 1: loca holds 32-bit offsets
    bool kernUsable = false;     ///< the 'kern' pairs lie within their table
    bool gposUsable = false;     ///< every GPOS pair-kerning lookup lies within its table
};

/// Checks the face at `faceOffset` (0, or the collection's first face). `bytes` is the font's
/// own copy: the format-4 cmap's binary-search header (searchRange, entrySelector, rangeShift)
/// is rewritten from its segment count, since stb_truetype's search trusts it and FreeType
/// ignores it (fonts in the wild get it wrong). The error says what is wrong, without the path.
Result<FontTables> checkFontTables(std::span<uint8_t> bytes, uint32_t faceOffset);

/// Whether stb_truetype can read `glyph`'s outline within the glyf table: the points, flags and
/// coordinates of a simple glyph, and the components of a compound one (to 8 levels, so that a
/// glyph that contains itself is refused instead of recursing until the stack ends).
bool glyphOutlineIsSafe(std::span<const uint8_t> bytes, const FontTables& tables, uint32_t glyph);

}  // namespace orbis::vector::font
