#pragma once
// The glyphs of map labels in one single-channel (R8) texture, rasterised on demand from a font
// and its fallbacks, for the label renderer to upload and sample. No Vulkan.
//
// Signed distance fields rather than coverage: a glyph is rasterised once, at
// `rasterPixelsPerEm` (stbtt_GetGlyphSDF), and drawn at any label size by scaling its quad, the
// outline being the threshold `sdfOnEdge()` (a smoothstep a pixel wide around it); a halo is a
// second, lower threshold within the padding (`paddingPx` raster pixels of distance around
// every outline). Coverage bitmaps would need an entry per label size and a halo by dilation
// (many taps per fragment). The price: corners round off when a label is drawn much larger than
// the raster size (to 2-3 times is fine for labels).
//
// Packing: shelves (rows as tall as their tallest glyph, rounded up to 4 texels) with a texel
// of space around each glyph, so linear filtering never reads a neighbour. When a glyph does
// not fit, `full()` says so and the glyph has no texels (`pending`); the caller clears the atlas
// and lays its labels out again (`generation()` tells stale layouts). `dirty()` is what changed
// since the last upload.
//
// Threads: main thread only (laying out text adds glyphs to the atlas).

#include "base/Result.h"
#include "layers/vector/Font.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <unordered_map>
#include <vector>

namespace orbis::vector {

struct GlyphAtlasOptions {
    std::filesystem::path font = kDefaultFontPath;
    std::vector<std::filesystem::path> fallbackFonts;   ///< asked in order for what `font` lacks (a CJK face)
    int width = 1024, height = 1024;    ///< texels, 64..8192, at least 4 raster ems
    float rasterPixelsPerEm = 32.0f;    ///< the size glyphs are rasterised at, 8..256
    int paddingPx = 6;                  ///< distance-field range around each outline (raster pixels), 1..32
};

/// A rectangle of texels.
struct AtlasRect {
    int x = 0, y = 0, width = 0, height = 0;
    bool empty() const { return width <= 0 || height <= 0; }
};

/// One glyph of one font, as the layout places it.
struct GlyphEntry {
    uint32_t font = 0;          ///< 0: the main font, then the fallbacks in order
    uint32_t glyph = 0;         ///< in that font; 0 is .notdef (a code point no font has)
    float advanceEm = 0.0f;
    glm::vec2 offsetEm{0.0f};   ///< the bitmap's top-left from the pen on the baseline (em, y down)
    glm::vec2 sizeEm{0.0f};     ///< the bitmap's size (em), padding included
    AtlasRect rect;             ///< its texels; empty when there is nothing to draw
    bool pending = false;       ///< it has an outline but the atlas was full: not drawn
};

class GlyphAtlas {
public:
    /// Loads the fonts (an error names the first that cannot be read) and makes an empty atlas.
    static Result<GlyphAtlas> create(const GlyphAtlasOptions& options = {});

    /// The entry of `codePoint` (an index for `entry`), added and rasterised on first use: the
    /// glyph of the first font that has it, else the main font's .notdef. Never fails: when the
    /// atlas is full the new entry is `pending` and `full()` turns true. Main thread only.
    uint32_t entryFor(char32_t codePoint) {
        if (codePoint < kDirectCodePoints && direct_[codePoint] != kNoEntry) return direct_[codePoint];
        return addEntry(codePoint);
    }
    /// An entry by the index `entryFor` gave since the last `clear()` (indices die with it).
    const GlyphEntry& entry(uint32_t id) const { return entries_[id]; }
    /// The pen's adjustment between two entries (em; 0 across fonts). Cached: stb_truetype
    /// walks GPOS' lookups for every pair, several times the cost of the rest of a layout.
    /// Main thread only.
    float kerningEm(uint32_t left, uint32_t right) {
        const uint64_t key = uint64_t(left) << 32 | right;
        for (std::size_t slot = kerningSlot(key);; slot = (slot + 1) & (kerningKeys_.size() - 1)) {
            if (kerningKeys_[slot] == key) return kerningValues_[slot];
            if (kerningKeys_[slot] == kNoPair) return addKerning(left, right);
        }
    }

    int width() const { return width_; }
    int height() const { return height_; }
    /// width x height texels, top row first: the texture's contents.
    std::span<const uint8_t> pixels() const { return pixels_; }
    /// The texels changed since `clearDirty()` (empty when none): what the GPU side uploads.
    const AtlasRect& dirty() const { return dirty_; }
    void clearDirty() { dirty_ = {}; }
    /// A glyph did not fit since the last `clear()`.
    bool full() const { return full_; }
    /// Forgets every glyph: the whole texture is dirty (zeros) and `generation()` moves on, so
    /// layouts made before are stale. Main thread only.
    void clear();
    uint32_t generation() const { return generation_; }
    /// Distinct glyphs held (every font together).
    std::size_t glyphCount() const { return entries_.size(); }

    std::size_t fontCount() const { return fonts_.size(); }
    const Font& font(uint32_t index) const { return fonts_[index]; }
    float rasterPixelsPerEm() const { return sdf_.pixelsPerEm; }
    int paddingPx() const { return sdf_.paddingPx; }
    /// The distance field's encoding for the shader (texel values in 0..1): the outline's value,
    /// and the change of value per raster pixel of distance (inwards up).
    float sdfOnEdge() const { return float(sdf_.onEdge) / 255.0f; }
    float sdfValuePerPixel() const { return sdf_.valuePerPixel / 255.0f; }

private:
    static constexpr uint32_t kNoEntry = ~0u;
    /// Code points below this (Latin, Greek, Cyrillic, Hebrew, Arabic) are found by index.
    static constexpr char32_t kDirectCodePoints = 0x800;
    static constexpr uint64_t kNoPair = ~uint64_t(0);

    struct Shelf {
        int y = 0, height = 0, x = 0;
    };

    GlyphAtlas() = default;
    uint32_t addEntry(char32_t codePoint);
    uint32_t entryForGlyph(uint32_t font, uint32_t glyph);
    void rasterise(GlyphEntry& entry);
    bool place(int width, int height, AtlasRect& rect);
    float addKerning(uint32_t left, uint32_t right);
    void insertKerning(uint64_t key, float kern);
    void resetKerning(std::size_t slots);
    std::size_t kerningSlot(uint64_t key) const {   // Fibonacci hashing into a power-of-two table
        return std::size_t((key * 0x9E3779B97F4A7C15ull) >> kerningShift_);
    }

    std::vector<Font> fonts_;
    SdfParams sdf_;
    int width_ = 0, height_ = 0;
    std::vector<uint8_t> pixels_;
    std::vector<Shelf> shelves_;
    int nextShelfY_ = 1;
    AtlasRect dirty_;
    bool full_ = false;
    uint32_t generation_ = 0;

    std::vector<GlyphEntry> entries_;
    std::vector<uint32_t> direct_;                          ///< kDirectCodePoints code points to entries
    std::unordered_map<char32_t, uint32_t> byCodePoint_;    ///< the other code points
    std::unordered_map<uint64_t, uint32_t> byGlyph_;        ///< font << 32 | glyph to its entry
    // Pairs of entries (left << 32 | right) to their kerning: open addressing, at most half full.
    std::vector<uint64_t> kerningKeys_;
    std::vector<float> kerningValues_;
    std::size_t kerningPairs_ = 0;
    int kerningShift_ = 64;
};

}  // namespace orbis::vector
