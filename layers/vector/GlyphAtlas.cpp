#include "layers/vector/GlyphAtlas.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace orbis::vector {
namespace {

/// Shelves are as tall as their first glyph rounded up to this, so that glyphs of nearby heights
/// share them instead of opening a shelf each.
constexpr int kShelfRounding = 4;
/// The value on the outline: the middle of 0..255, so the field reaches as far out as in.
constexpr uint8_t kSdfOnEdge = 128;
/// The kerning cache's first size (pairs of glyphs seen side by side; it doubles as it fills).
constexpr std::size_t kKerningSlots = 1024;

Result<void> checkOptions(const GlyphAtlasOptions& o) {
    const auto fail = [](const std::string& what) { return makeError("glyph atlas: " + what); };
    if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
        return fail("the size " + std::to_string(o.width) + " x " + std::to_string(o.height) + " is outside 64..8192");
    if (!(o.rasterPixelsPerEm >= 8.0f && o.rasterPixelsPerEm <= 256.0f))
        return fail("the raster size " + std::to_string(o.rasterPixelsPerEm) + " px is outside 8..256");
    if (o.paddingPx < 1 || o.paddingPx > 32) return fail("the padding " + std::to_string(o.paddingPx) + " px is outside 1..32");
    if (float(std::min(o.width, o.height)) < 4.0f * o.rasterPixelsPerEm)
        return fail("the atlas is smaller than 4 raster ems on a side");
    return {};
}

void grow(AtlasRect& into, const AtlasRect& rect) {
    if (into.empty()) {
        into = rect;
        return;
    }
    const int x1 = std::max(into.x + into.width, rect.x + rect.width), y1 = std::max(into.y + into.height, rect.y + rect.height);
    into.x = std::min(into.x, rect.x);
    into.y = std::min(into.y, rect.y);
    into.width = x1 - into.x;
    into.height = y1 - into.y;
}

}  // namespace

Result<GlyphAtlas> GlyphAtlas::create(const GlyphAtlasOptions& options) {
    if (auto ok = checkOptions(options); !ok) return ok.error();
    GlyphAtlas atlas;
    auto main = Font::load(options.font);
    if (!main) return main.error();
    atlas.fonts_.push_back(std::move(*main));
    for (const auto& path : options.fallbackFonts) {
        auto fallback = Font::load(path);
        if (!fallback) return fallback.error();
        atlas.fonts_.push_back(std::move(*fallback));
    }
    atlas.width_ = options.width;
    atlas.height_ = options.height;
    atlas.sdf_ = {.pixelsPerEm = options.rasterPixelsPerEm,
                  .paddingPx = options.paddingPx,
                  .onEdge = kSdfOnEdge,
                  .valuePerPixel = float(kSdfOnEdge) / float(options.paddingPx),   // 0 at the padding's edge
                  .maxSizePx = std::min(options.width, options.height) - 2};
    atlas.pixels_.assign(size_t(atlas.width_) * size_t(atlas.height_), 0);
    atlas.direct_.assign(kDirectCodePoints, kNoEntry);
    atlas.resetKerning(kKerningSlots);
    atlas.dirty_ = {0, 0, atlas.width_, atlas.height_};
    return atlas;
}

void GlyphAtlas::clear() {
    entries_.clear();
    std::fill(direct_.begin(), direct_.end(), kNoEntry);
    byCodePoint_.clear();
    byGlyph_.clear();
    resetKerning(kKerningSlots);
    shelves_.clear();
    nextShelfY_ = 1;
    std::fill(pixels_.begin(), pixels_.end(), uint8_t(0));
    dirty_ = {0, 0, width_, height_};
    full_ = false;
    ++generation_;
}

uint32_t GlyphAtlas::addEntry(char32_t codePoint) {
    if (codePoint >= kDirectCodePoints) {
        if (auto it = byCodePoint_.find(codePoint); it != byCodePoint_.end()) return it->second;
    }
    uint32_t id = kNoEntry;
    for (uint32_t f = 0; f < fonts_.size() && id == kNoEntry; ++f)
        if (const uint32_t glyph = fonts_[f].glyphIndex(codePoint); glyph != 0) id = entryForGlyph(f, glyph);
    if (id == kNoEntry) id = entryForGlyph(0, 0);   // .notdef of the main font: the box
    if (codePoint < kDirectCodePoints) direct_[codePoint] = id;
    else byCodePoint_.emplace(codePoint, id);
    return id;
}

uint32_t GlyphAtlas::entryForGlyph(uint32_t font, uint32_t glyph) {
    const uint64_t key = uint64_t(font) << 32 | glyph;
    if (auto it = byGlyph_.find(key); it != byGlyph_.end()) return it->second;
    GlyphEntry entry;
    entry.font = font;
    entry.glyph = glyph;
    entry.advanceEm = fonts_[font].advanceEm(glyph);
    rasterise(entry);
    const auto id = uint32_t(entries_.size());
    entries_.push_back(entry);
    byGlyph_.emplace(key, id);
    return id;
}

void GlyphAtlas::rasterise(GlyphEntry& entry) {
    const auto bitmap = fonts_[entry.font].signedDistanceField(entry.glyph, sdf_);
    if (!bitmap || bitmap->width == 0) return;   // damaged or blank: nothing to draw
    const float emPerPixel = 1.0f / sdf_.pixelsPerEm;
    entry.offsetEm = glm::vec2(float(bitmap->left), float(bitmap->top)) * emPerPixel;
    entry.sizeEm = glm::vec2(float(bitmap->width), float(bitmap->height)) * emPerPixel;
    AtlasRect rect;
    if (!place(bitmap->width, bitmap->height, rect)) {
        entry.pending = true;
        full_ = true;
        return;
    }
    for (int row = 0; row < rect.height; ++row)
        std::copy_n(bitmap->pixels.begin() + ptrdiff_t(row) * bitmap->width, bitmap->width,
                    pixels_.begin() + (ptrdiff_t(rect.y + row) * width_ + rect.x));
    entry.rect = rect;
    grow(dirty_, rect);
}

bool GlyphAtlas::place(int width, int height, AtlasRect& rect) {
    // A texel of space right of and below each glyph (and the atlas' first row and column) keeps
    // bilinear samples at a glyph's edge off its neighbours.
    Shelf* best = nullptr;
    for (Shelf& shelf : shelves_) {
        if (shelf.height < height || shelf.x + width + 1 > width_) continue;
        if (!best || shelf.height < best->height) best = &shelf;   // the least height wasted
    }
    const int shelfHeight = (height + kShelfRounding - 1) / kShelfRounding * kShelfRounding;
    // A new shelf beats one that would waste more than a third of its height, while room lasts.
    const bool roomForShelf = nextShelfY_ + shelfHeight + 1 <= height_ && width + 2 <= width_;
    if (roomForShelf && (!best || best->height * 2 > shelfHeight * 3)) {
        shelves_.push_back({nextShelfY_, shelfHeight, 1});
        nextShelfY_ += shelfHeight + 1;
        best = &shelves_.back();
    }
    if (!best) return false;
    rect = {best->x, best->y, width, height};
    best->x += width + 1;
    return true;
}

void GlyphAtlas::resetKerning(std::size_t slots) {
    kerningKeys_.assign(slots, kNoPair);
    kerningValues_.assign(slots, 0.0f);
    kerningPairs_ = 0;
    kerningShift_ = 64 - std::countr_zero(slots);
}

float GlyphAtlas::addKerning(uint32_t left, uint32_t right) {
    const GlyphEntry &a = entries_[left], &b = entries_[right];
    const float kern = a.font == b.font ? fonts_[a.font].kerningEm(a.glyph, b.glyph) : 0.0f;
    if (2 * (kerningPairs_ + 1) > kerningKeys_.size()) {
        std::vector<uint64_t> keys = std::move(kerningKeys_);
        std::vector<float> values = std::move(kerningValues_);
        resetKerning(keys.size() * 2);
        for (std::size_t i = 0; i < keys.size(); ++i)
            if (keys[i] != kNoPair) insertKerning(keys[i], values[i]);
    }
    insertKerning(uint64_t(left) << 32 | right, kern);
    return kern;
}

void GlyphAtlas::insertKerning(uint64_t key, float kern) {
    std::size_t slot = kerningSlot(key);
    while (kerningKeys_[slot] != kNoPair) slot = (slot + 1) & (kerningKeys_.size() - 1);
    kerningKeys_[slot] = key;
    kerningValues_[slot] = kern;
    ++kerningPairs_;
}

}  // namespace orbis::vector
