#include "layers/vector/Font.h"

#include "base/FileText.h"
#include "layers/vector/FontTables.h"

#include <stb_truetype.h>

#include <span>

namespace orbis::vector {
namespace {

/// Larger than any font a label needs (DejaVu Sans is 740 KB; a CJK face is 10-20 MB).
constexpr std::uintmax_t kMaxFontBytes = 64u << 20;

}  // namespace

struct Font::State {
    std::string name;
    std::string bytes;
    font::FontTables tables;
    stbtt_fontinfo info{};
    float emPerUnit = 0.0f;
    float ascentEm = 0.0f, descentEm = 0.0f, lineGapEm = 0.0f;

    unsigned char* data() { return reinterpret_cast<unsigned char*>(bytes.data()); }
    std::span<uint8_t> span() { return {reinterpret_cast<uint8_t*>(bytes.data()), bytes.size()}; }
    std::span<const uint8_t> span() const { return {reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}; }
};

Font::Font(std::unique_ptr<State> state) : state_(std::move(state)) {}
Font::Font(Font&&) noexcept = default;
Font& Font::operator=(Font&&) noexcept = default;
Font::~Font() = default;

Result<Font> Font::load(const std::filesystem::path& file) {
    auto bytes = readTextFile(file, kMaxFontBytes, "font file");
    if (!bytes) return bytes.error();
    return fromBytes(std::move(*bytes), file.string());
}

Result<Font> Font::fromBytes(std::string bytes, const std::string& name) {
    auto state = std::make_unique<State>();
    state->name = name;
    state->bytes = std::move(bytes);
    const auto fail = [&](const std::string& problem) { return makeError(name + ": " + problem); };
    // stbtt_GetFontOffsetForIndex reads up to 16 bytes (a collection's header) unchecked.
    if (state->bytes.size() < 16) return fail("too short to be a font (" + std::to_string(state->bytes.size()) + " bytes)");
    const int face = stbtt_GetFontOffsetForIndex(state->data(), 0);
    if (face < 0) return fail("not a TrueType font (neither a font nor a collection header at its start)");
    auto tables = font::checkFontTables(state->span(), uint32_t(face));
    if (!tables) return fail(tables.message());
    state->tables = *tables;
    if (!stbtt_InitFont(&state->info, state->data(), face)) return fail("stb_truetype cannot read it");
    // Kerning tables that failed their checks are left unread: the font still draws.
    if (!tables->gposUsable) state->info.gpos = 0;
    if (!tables->kernUsable) state->info.kern = 0;

    state->emPerUnit = 1.0f / float(tables->unitsPerEm);
    int ascent = 0, descent = 0, lineGap = 0;
    stbtt_GetFontVMetrics(&state->info, &ascent, &descent, &lineGap);
    state->ascentEm = float(ascent) * state->emPerUnit;
    state->descentEm = -float(descent) * state->emPerUnit;
    state->lineGapEm = float(lineGap) * state->emPerUnit;
    return Font(std::move(state));
}

const std::string& Font::name() const { return state_->name; }
uint32_t Font::glyphCount() const { return state_->tables.numGlyphs; }
float Font::ascentEm() const { return state_->ascentEm; }
float Font::descentEm() const { return state_->descentEm; }
float Font::lineGapEm() const { return state_->lineGapEm; }

uint32_t Font::glyphIndex(char32_t codePoint) const {
    if (codePoint > 0x10FFFF) return 0;
    const int glyph = stbtt_FindGlyphIndex(&state_->info, int(codePoint));
    // A character map may name glyphs the font does not have; those would index past hmtx.
    return glyph > 0 && uint32_t(glyph) < glyphCount() ? uint32_t(glyph) : 0u;
}

float Font::advanceEm(uint32_t glyph) const {
    if (glyph >= glyphCount()) return 0.0f;
    int advance = 0, leftBearing = 0;
    stbtt_GetGlyphHMetrics(&state_->info, int(glyph), &advance, &leftBearing);
    return float(advance) * state_->emPerUnit;
}

float Font::kerningEm(uint32_t left, uint32_t right) const {
    if (left >= glyphCount() || right >= glyphCount()) return 0.0f;
    return float(stbtt_GetGlyphKernAdvance(&state_->info, int(left), int(right))) * state_->emPerUnit;
}

std::optional<GlyphBitmap> Font::signedDistanceField(uint32_t glyph, const SdfParams& params) const {
    if (glyph >= glyphCount() || !font::glyphOutlineIsSafe(state_->span(), state_->tables, glyph)) return std::nullopt;
    const float scale = params.pixelsPerEm * state_->emPerUnit;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    stbtt_GetGlyphBitmapBox(&state_->info, int(glyph), scale, scale, &x0, &y0, &x1, &y1);
    if (x1 < x0 || y1 < y0) return std::nullopt;   // a box upside down: a damaged glyph header
    if (x1 == x0 || y1 == y0) return GlyphBitmap{};
    // Checked before stb_truetype allocates it: a damaged box could ask for gigabytes.
    if (x1 - x0 + 2 * params.paddingPx > params.maxSizePx || y1 - y0 + 2 * params.paddingPx > params.maxSizePx)
        return std::nullopt;
    GlyphBitmap out;
    unsigned char* field = stbtt_GetGlyphSDF(&state_->info, scale, int(glyph), params.paddingPx, params.onEdge,
                                             params.valuePerPixel, &out.width, &out.height, &out.left, &out.top);
    if (!field) return GlyphBitmap{};
    out.pixels.assign(field, field + size_t(out.width) * size_t(out.height));
    stbtt_FreeSDF(field, nullptr);
    return out;
}

}  // namespace orbis::vector
