#include "layers/vector/Font.h"
#include "layers/vector/GlyphAtlas.h"
#include "layers/vector/LabelLayout.h"
#include "base/Utf8.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace fs = std::filesystem;
using namespace orbis::vector;
using orbis::decodeUtf8;
using orbis::kReplacementCharacter;

namespace {

const char* const kMonoFont = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";

#define SKIP_WITHOUT_DEJAVU()                                                                                   \
    if (!fs::exists(kDefaultFontPath)) GTEST_SKIP() << kDefaultFontPath << " is absent (Debian: fonts-dejavu-core)"

std::string fileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A folder of its own for files a test writes.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / ("orbis-glyph-" + std::to_string(::getpid()) + "-" + name)) {
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const std::string& name, const std::string& bytes) const {
        std::ofstream(path / name, std::ios::binary) << bytes;
        return path / name;
    }
};

GlyphAtlas makeAtlas(GlyphAtlasOptions options = {}) {
    auto atlas = GlyphAtlas::create(options);
    EXPECT_TRUE(atlas.ok()) << (atlas.ok() ? "" : atlas.message());
    return std::move(atlas).value();
}

TextStyle leftAligned(float pixelSize = 16.0f) { return {.pixelSize = pixelSize, .align = TextAlign::Left}; }

}  // namespace

// --- UTF-8 -----------------------------------------------------------------------------------

TEST(GlyphUtf8, DecodesLatinGreekCyrillicAndAstralPlanes) {
    EXPECT_EQ(decodeUtf8("A\xC3\xA9\xCE\xA9\xD0\x96\xE2\x82\xAC\xF0\x9F\x98\x80"), (std::u32string{U'A', 0xE9, 0x3A9, 0x416, 0x20AC, 0x1F600}));
}

TEST(GlyphUtf8, LoneContinuationByteIsOneReplacement) {
    EXPECT_EQ(decodeUtf8("a\x80" "b"), (std::u32string{U'a', kReplacementCharacter, U'b'}));
    std::size_t pos = 1;
    bool valid = true;
    EXPECT_EQ(decodeUtf8("a\x80", pos, valid), kReplacementCharacter);
    EXPECT_FALSE(valid);
    EXPECT_EQ(pos, 2u);
}

TEST(GlyphUtf8, TruncatedSequenceIsOneReplacementAndNothingPastTheEndIsRead) {
    // The euro sign's last byte lies just past the view: decoding must not see it.
    const std::string euro = "\xE2\x82\xAC";
    EXPECT_EQ(decodeUtf8(std::string_view(euro).substr(0, 2)), std::u32string(1, kReplacementCharacter));
    EXPECT_EQ(decodeUtf8(euro), std::u32string(1, 0x20AC));
    // The byte that breaks a sequence is not swallowed: it starts the next code point.
    EXPECT_EQ(decodeUtf8("x\xF0\x9F\x98!"), (std::u32string{U'x', kReplacementCharacter, U'!'}));
    EXPECT_EQ(decodeUtf8("\xC3"), std::u32string(1, kReplacementCharacter));
}

TEST(GlyphUtf8, OverlongSurrogateAndOutOfRangeFormsAreReplaced) {
    const std::u32string two(2, kReplacementCharacter), three(3, kReplacementCharacter), four(4, kReplacementCharacter);
    EXPECT_EQ(decodeUtf8("\xC0\xAF"), two);                 // overlong '/'
    EXPECT_EQ(decodeUtf8("\xE0\x80\xAF"), three);           // overlong '/' in three bytes
    EXPECT_EQ(decodeUtf8("\xED\xA0\x80"), three);           // U+D800, a surrogate
    EXPECT_EQ(decodeUtf8("\xF4\x90\x80\x80"), four);        // U+110000
    EXPECT_EQ(decodeUtf8("\xFF"), std::u32string(1, kReplacementCharacter));
}

// --- fonts -----------------------------------------------------------------------------------

TEST(GlyphFont, MissingFileIsAnErrorNamingIt) {
    const auto font = Font::load("/nonexistent/orbis/NoSuchFont.ttf");
    ASSERT_FALSE(font.ok());
    EXPECT_NE(font.message().find("/nonexistent/orbis/NoSuchFont.ttf"), std::string::npos) << font.message();
}

TEST(GlyphFont, FileThatIsNotAFontIsAnErrorNamingIt) {
    const TempDir dir("junk");
    for (const std::string& junk : {std::string("not a font"), std::string(4096, 'x'), std::string("ttcf\0\1\0\0\0\0\0\1\xFF\xFF\xFF\xF0", 16)}) {
        const fs::path path = dir.write("junk.ttf", junk);
        const auto font = Font::load(path);
        ASSERT_FALSE(font.ok());
        EXPECT_NE(font.message().find(path.string()), std::string::npos) << font.message();
    }
}

TEST(GlyphFont, TruncatedFontIsAnErrorNamingIt) {
    SKIP_WITHOUT_DEJAVU();
    const std::string whole = fileBytes(kDefaultFontPath);
    const TempDir dir("truncated");
    const fs::path path = dir.write("DejaVuSans-10k.ttf", whole.substr(0, 10 * 1024));
    const auto font = Font::load(path);
    ASSERT_FALSE(font.ok());
    EXPECT_NE(font.message().find(path.string()), std::string::npos) << font.message();
    EXPECT_NE(font.message().find("truncated"), std::string::npos) << font.message();
    // Every cut, through the header, the directory or any table, is refused the same way.
    for (std::size_t cut : {std::size_t(0), std::size_t(5), std::size_t(12), std::size_t(100), std::size_t(331),
                            std::size_t(50000), whole.size() / 2, whole.size() - 1}) {
        const auto cutFont = Font::fromBytes(whole.substr(0, cut), "cut.ttf");
        ASSERT_FALSE(cutFont.ok()) << cut;
        EXPECT_EQ(cutFont.message().rfind("cut.ttf: ", 0), 0u) << cutFont.message();
    }
}

TEST(GlyphFont, DamagedFontsNeverCrash) {
    SKIP_WITHOUT_DEJAVU();
    // Random bytes written over the directory and the tables stb_truetype reads: every font
    // either fails its checks or draws without reading past its buffer (a crash fails the run).
    const std::string whole = fileBytes(kDefaultFontPath);
    std::mt19937 rng(7);
    int loaded = 0;
    for (int trial = 0; trial < 400; ++trial) {
        std::string bytes = whole;
        const std::size_t region = trial % 2 == 0 ? 700 : bytes.size();   // the directory and GPOS' head, or anywhere
        for (int n = 0; n < 1 + trial % 4; ++n) bytes[rng() % region] = char(rng());
        const auto font = Font::fromBytes(std::move(bytes), "damaged.ttf");
        if (!font.ok()) continue;
        ++loaded;
        uint32_t previous = 0;
        for (char32_t c : std::u32string(U"AVé\u0416\u03A9\uFFFD\U0001F600")) {
            const uint32_t glyph = font->glyphIndex(c);
            EXPECT_LT(glyph, font->glyphCount());
            (void)font->advanceEm(glyph);
            (void)font->kerningEm(previous, glyph);
            (void)font->signedDistanceField(glyph, SdfParams{.pixelsPerEm = 12.0f, .paddingPx = 2, .valuePerPixel = 64.0f});
            previous = glyph;
        }
    }
    EXPECT_GT(loaded, 0);   // most damage lands in glyph data, which is checked glyph by glyph
}

TEST(GlyphFont, CompoundGlyphThatContainsItselfIsRefusedNotRecursedInto) {
    SKIP_WITHOUT_DEJAVU();
    std::string bytes = fileBytes(kDefaultFontPath);
    const auto u16 = [&](size_t at) { return uint32_t(uint8_t(bytes[at])) << 8 | uint8_t(bytes[at + 1]); };
    const auto u32 = [&](size_t at) { return u16(at) << 16 | u16(at + 2); };
    const auto table = [&](const char* tag) {
        for (size_t r = 12; r < 12 + 16 * u16(4); r += 16)
            if (bytes.compare(r, 4, tag) == 0) return size_t(u32(r + 8));
        return size_t(0);
    };
    const auto font = Font::fromBytes(bytes, "DejaVuSans.ttf");
    ASSERT_TRUE(font.ok()) << font.message();
    // é is a compound in DejaVu Sans (e + acute): point its first component at itself.
    const uint32_t glyph = font->glyphIndex(0xE9);
    const size_t loca = table("loca"), glyf = table("glyf");
    const bool longLoca = u16(table("head") + 50) == 1;
    const size_t at = glyf + (longLoca ? u32(loca + 4 * glyph) : 2 * u16(loca + 2 * glyph));
    ASSERT_LT(int16_t(u16(at)), 0) << "é is not a compound glyph in this DejaVu Sans";
    bytes[at + 12] = char(glyph >> 8);
    bytes[at + 13] = char(glyph & 0xFF);
    const auto looped = Font::fromBytes(bytes, "looped.ttf");
    ASSERT_TRUE(looped.ok()) << looped.message();   // the font is fine but for that glyph
    EXPECT_FALSE(looped->signedDistanceField(glyph, {}).has_value());
    EXPECT_TRUE(looped->signedDistanceField(looped->glyphIndex(U'e'), {}).has_value());
}

TEST(GlyphFont, LatinGreekAndCyrillicLettersHaveGlyphsAndAdvances) {
    SKIP_WITHOUT_DEJAVU();
    const auto font = Font::load(kDefaultFontPath);
    ASSERT_TRUE(font.ok()) << font.message();
    for (char32_t c : {U'A', char32_t(0xE9) /* é */, char32_t(0x416) /* Ж */, char32_t(0x3A9) /* Ω */}) {
        const uint32_t glyph = font->glyphIndex(c);
        EXPECT_NE(glyph, 0u) << uint32_t(c);
        EXPECT_GT(font->advanceEm(glyph), 0.0f) << uint32_t(c);
    }
    EXPECT_EQ(font->glyphIndex(0x10FFFD), 0u);   // a private-use code point
    EXPECT_EQ(font->glyphIndex(0x4E2D), 0u);     // 中: DejaVu has no CJK
}

// --- the atlas -------------------------------------------------------------------------------

TEST(GlyphAtlas, MissingCodePointsDrawTheNotdefBoxAndAreCounted) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout layout = layoutText(atlas, "A\xF4\x8F\xBF\xBD\xE4\xB8\xAD" "B", leftAligned());   // A U+10FFFD 中 B
    EXPECT_EQ(layout.missing, 2u);
    ASSERT_EQ(layout.quads.size(), 4u);   // .notdef is a box: it is drawn
    EXPECT_EQ(layout.quads[1].uvMin, layout.quads[2].uvMin);
    EXPECT_EQ(atlas.glyphCount(), 3u);    // A, .notdef (once), B
    EXPECT_EQ(atlas.entry(atlas.entryFor(0x4E2D)).glyph, 0u);
}

TEST(GlyphAtlas, GlyphFieldHasInkInsideItsBoxAndNothingOutsideItsPadding) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    (void)layoutText(atlas, "A\xC3\xA9\xD0\x96\xCE\xA9", leftAligned());   // A é Ж Ω
    const auto pixels = atlas.pixels();
    const int onEdge = int(std::lround(atlas.sdfOnEdge() * 255.0f)), pad = atlas.paddingPx();
    std::vector<uint8_t> covered(pixels.size(), 0);
    for (char32_t c : {U'A', char32_t(0xE9), char32_t(0x416), char32_t(0x3A9)}) {
        const AtlasRect r = atlas.entry(atlas.entryFor(c)).rect;
        ASSERT_FALSE(r.empty());
        ASSERT_TRUE(r.x >= 0 && r.y >= 0 && r.x + r.width <= atlas.width() && r.y + r.height <= atlas.height());
        int ink = 0;
        for (int y = r.y; y < r.y + r.height; ++y)
            for (int x = r.x; x < r.x + r.width; ++x) {
                const int v = pixels[size_t(y) * atlas.width() + x];
                covered[size_t(y) * atlas.width() + x] = 1;
                const int fromEdge = std::min({x - r.x, y - r.y, r.x + r.width - 1 - x, r.y + r.height - 1 - y});
                if (v >= onEdge) {
                    ++ink;
                    EXPECT_GE(fromEdge, pad - 1) << "ink in the padding of U+" << std::hex << uint32_t(c);
                }
                // The field fades to (nearly) nothing at the padding's outer edge: a texel centre
                // there is at least padding - 0.5 pixels from the outline.
                if (fromEdge == 0) {
                    EXPECT_LT(v, onEdge / 4) << "U+" << std::hex << uint32_t(c);
                }
            }
        EXPECT_GT(ink, 10) << "U+" << std::hex << uint32_t(c);
    }
    for (size_t i = 0; i < pixels.size(); ++i)
        if (!covered[i]) {
            ASSERT_EQ(pixels[i], 0) << "texel " << i << " lies outside every glyph";
        }
}

TEST(GlyphAtlas, SameTextTwiceReusesTheEntries) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const std::string text = "Z\xC3\xBCrich \xCE\xA9\xCE\xBC\xCE\xAD\xCE\xB3\xCE\xB1";   // Zürich Ωμέγα
    const TextLayout first = layoutText(atlas, text, {});
    const std::size_t glyphs = atlas.glyphCount();
    const std::vector<uint8_t> pixels(atlas.pixels().begin(), atlas.pixels().end());
    atlas.clearDirty();
    const TextLayout second = layoutText(atlas, text, {});
    EXPECT_EQ(atlas.glyphCount(), glyphs);
    EXPECT_TRUE(atlas.dirty().empty());
    EXPECT_TRUE(std::equal(pixels.begin(), pixels.end(), atlas.pixels().begin()));
    ASSERT_EQ(first.quads.size(), second.quads.size());
    for (size_t i = 0; i < first.quads.size(); ++i) EXPECT_EQ(first.quads[i].uvMin, second.quads[i].uvMin);
}

TEST(GlyphAtlas, DirtyRectangleCoversWhatChanged) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    EXPECT_EQ(atlas.dirty().width, atlas.width());   // a new atlas is uploaded whole
    (void)layoutText(atlas, "ab", {});
    atlas.clearDirty();
    (void)layoutText(atlas, "abQ", {});
    const AtlasRect q = atlas.entry(atlas.entryFor(U'Q')).rect, dirty = atlas.dirty();
    EXPECT_EQ(dirty.x, q.x);
    EXPECT_EQ(dirty.y, q.y);
    EXPECT_EQ(dirty.width, q.width);
    EXPECT_EQ(dirty.height, q.height);
}

TEST(GlyphAtlas, FillingTheAtlasReportsFullInsteadOfOverflowing) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas({.width = 128, .height = 128});
    std::string text;
    for (char32_t c = 0x410; c < 0x450; ++c) text += std::string{char(0xC0 | (c >> 6)), char(0x80 | (c & 0x3F))};   // Cyrillic А..я
    const TextLayout layout = layoutText(atlas, text, leftAligned());
    EXPECT_TRUE(atlas.full());
    EXPECT_TRUE(layout.incomplete);
    EXPECT_LT(layout.quads.size(), 64u);
    EXPECT_GT(layout.width, 0.0f);   // the box counts every glyph, drawn or not
    std::vector<AtlasRect> placed;
    for (char32_t c = 0x410; c < 0x450; ++c) {
        const GlyphEntry& e = atlas.entry(atlas.entryFor(c));
        EXPECT_EQ(e.pending, e.rect.empty());
        if (e.rect.empty()) continue;
        ASSERT_TRUE(e.rect.x >= 0 && e.rect.y >= 0 && e.rect.x + e.rect.width <= 128 && e.rect.y + e.rect.height <= 128);
        for (const AtlasRect& o : placed)
            ASSERT_FALSE(e.rect.x < o.x + o.width && o.x < e.rect.x + e.rect.width && e.rect.y < o.y + o.height &&
                         o.y < e.rect.y + e.rect.height);
        placed.push_back(e.rect);
    }
    const uint32_t generation = atlas.generation();
    atlas.clear();
    EXPECT_FALSE(atlas.full());
    EXPECT_EQ(atlas.generation(), generation + 1);
    EXPECT_EQ(atlas.glyphCount(), 0u);
    EXPECT_EQ(atlas.dirty().width * atlas.dirty().height, 128 * 128);
    const TextLayout again = layoutText(atlas, "\xD0\x96", leftAligned());
    EXPECT_FALSE(again.incomplete);
    EXPECT_EQ(again.quads.size(), 1u);
    EXPECT_EQ(again.generation, atlas.generation());
}

TEST(GlyphAtlas, FallbackFontSuppliesWhatTheMainFontLacks) {
    SKIP_WITHOUT_DEJAVU();
    if (!fs::exists(kMonoFont)) GTEST_SKIP() << kMonoFont << " is absent";
    GlyphAtlas atlas = makeAtlas({.font = kMonoFont, .fallbackFonts = {kDefaultFontPath}});
    const uint32_t dz = atlas.entryFor(0x1C4);   // Ǆ: in DejaVu Sans, not in DejaVu Sans Mono
    EXPECT_EQ(atlas.entry(dz).font, 1u);
    EXPECT_NE(atlas.entry(dz).glyph, 0u);
    EXPECT_EQ(atlas.entry(atlas.entryFor(U'A')).font, 0u);
    const TextLayout layout = layoutText(atlas, "A\xC7\x84\xE4\xB8\xAD", leftAligned());   // A Ǆ 中
    EXPECT_EQ(layout.missing, 1u);
    EXPECT_EQ(layout.quads.size(), 3u);
}

TEST(GlyphAtlas, BadOptionsAndUnreadableFallbacksAreErrors) {
    SKIP_WITHOUT_DEJAVU();
    EXPECT_FALSE(GlyphAtlas::create({.width = 10}).ok());
    EXPECT_FALSE(GlyphAtlas::create({.rasterPixelsPerEm = 0.0f}).ok());
    const auto atlas = GlyphAtlas::create({.fallbackFonts = {"/nonexistent/NotoSansCJK.ttc"}});
    ASSERT_FALSE(atlas.ok());
    EXPECT_NE(atlas.message().find("/nonexistent/NotoSansCJK.ttc"), std::string::npos) << atlas.message();
}

// --- layout ----------------------------------------------------------------------------------

TEST(GlyphLayout, KerningMakesAVNarrowerThanItsAdvances) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout layout = layoutText(atlas, "AV", leftAligned(20.0f));
    const float advances = (atlas.entry(atlas.entryFor(U'A')).advanceEm + atlas.entry(atlas.entryFor(U'V')).advanceEm) * 20.0f;
    EXPECT_LT(layout.width, advances - 0.5f);   // DejaVu Sans kerns A-V by -0.064 em: 1.3 px at 20 px
}

TEST(GlyphLayout, NarrowLettersMakeNarrowerText) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    EXPECT_LT(layoutText(atlas, "iiii", {}).width, layoutText(atlas, "MMMM", {}).width);
}

TEST(GlyphLayout, DoubleSizeDoublesTheBox) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const std::string text = "\xD0\x9C\xD0\xBE\xD1\x81\xD0\xBA\xD0\xB2\xD0\xB0 Aix";   // Москва Aix
    const TextLayout small = layoutText(atlas, text, {.pixelSize = 14.0f}), large = layoutText(atlas, text, {.pixelSize = 28.0f});
    // Metrics are em-based floats, so the scaling is exact but for rounding (1e-4 relative).
    EXPECT_NEAR(large.width / small.width, 2.0f, 2e-4f);
    EXPECT_NEAR((large.max.y - large.min.y) / (small.max.y - small.min.y), 2.0f, 2e-4f);
    EXPECT_EQ(atlas.glyphCount(), 10u);   // one entry per glyph (the space's too) serves both sizes
}

TEST(GlyphLayout, CentredTextIsSymmetricAndLeftTextStartsAtTheAnchor) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout centred = layoutText(atlas, "Wien", {.pixelSize = 16.0f, .align = TextAlign::Center});
    const TextLayout left = layoutText(atlas, "Wien", leftAligned());
    EXPECT_NEAR(centred.min.x, -centred.max.x, 1e-4f);
    EXPECT_NEAR(centred.max.x - centred.min.x, centred.width, 1e-4f);
    EXPECT_EQ(left.min.x, 0.0f);
    EXPECT_NEAR(left.max.x, left.width, 1e-4f);
    EXPECT_NEAR(left.min.y, -left.ascent, 1e-4f);
    EXPECT_NEAR(left.max.y, left.descent, 1e-4f);
    EXPECT_NEAR(left.ascent + left.descent, 16.0f * 1.164f, 0.05f);   // DejaVu Sans: ascent 0.928 em, descent 0.236 em
    ASSERT_EQ(centred.quads.size(), left.quads.size());
    EXPECT_NEAR(left.quads[0].min.x - centred.quads[0].min.x, left.width / 2.0f, 1e-3f);
}

TEST(GlyphLayout, InvalidUtf8IsDrawnAsTheReplacementCharacterAndCounted) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout layout = layoutText(atlas, "ab\xFF" "cd\xE2\x82", leftAligned());
    EXPECT_EQ(layout.invalid, 2u);
    EXPECT_EQ(layout.missing, 0u);   // DejaVu has U+FFFD
    EXPECT_EQ(layout.quads.size(), 6u);
}

TEST(GlyphLayout, WrapsAtSpacesWithinTheMaxWidth) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const std::string text = "Saint Petersburg Oblast";
    const TextLayout line = layoutText(atlas, text, leftAligned());
    const float widest = layoutText(atlas, "Petersburg", leftAligned()).width;
    TextStyle style = leftAligned();
    style.maxWidthPx = widest + 1.0f;
    const TextLayout wrapped = layoutText(atlas, text, style);
    EXPECT_EQ(line.lines, 1u);
    EXPECT_EQ(wrapped.lines, 3u);
    EXPECT_NEAR(wrapped.width, widest, 1e-3f);
    EXPECT_EQ(wrapped.quads.size(), line.quads.size());   // the spaces had no quads
    const float lineHeight = 16.0f * 1.164f;
    EXPECT_NEAR(wrapped.max.y - wrapped.min.y, 3.0f * lineHeight, 0.1f);
    // "Petersburg" starts the second line at x = its own left bearing, one line lower.
    const GlyphQuad& p = wrapped.quads[5];
    EXPECT_NEAR(p.min.y - wrapped.quads[0].min.y, lineHeight, 0.1f);
    EXPECT_LT(p.min.x, 2.0f);
    // A word longer than the width keeps a line to itself, unbroken.
    style.maxWidthPx = 10.0f;
    EXPECT_EQ(layoutText(atlas, text, style).lines, 3u);
    EXPECT_EQ(layoutText(atlas, "A\nB", leftAligned()).lines, 2u);
}

TEST(GlyphLayout, EmptyTextIsAnEmptyLayout) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout layout = layoutText(atlas, "", {});
    EXPECT_EQ(layout.lines, 0u);
    EXPECT_TRUE(layout.quads.empty());
    EXPECT_EQ(layout.min, layout.max);
}

TEST(GlyphLayout, LabelCandidateIsTheBoxAtTheAnchorGrownByTheHalo) {
    SKIP_WITHOUT_DEJAVU();
    GlyphAtlas atlas = makeAtlas();
    const TextLayout layout = layoutText(atlas, "Lyon", {});
    const LabelCandidate c = labelCandidate(layout, {400.0, 300.0}, 2.0, 42, 7.0);
    EXPECT_EQ(c.id, 42u);
    EXPECT_DOUBLE_EQ(c.min.x, 400.0 + layout.min.x - 2.0);
    EXPECT_DOUBLE_EQ(c.max.y, 300.0 + layout.max.y + 2.0);
    EXPECT_NEAR(c.max.x - c.min.x, layout.width + 4.0, 1e-4);
}
