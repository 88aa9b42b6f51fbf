#include "layers/vector/FontTables.h"

#include <algorithm>
#include <string>

namespace orbis::vector::font {
namespace {

/// A compound glyph nests at most this deep (real fonts use 2 or 3), and one outline visits at
/// most this many components: beyond, the glyph is refused rather than recursed into.
constexpr int kMaxCompoundDepth = 8;
constexpr int kMaxComponents = 4096;

constexpr uint32_t tag(const char* name) {
    return uint32_t(uint8_t(name[0])) << 24 | uint32_t(uint8_t(name[1])) << 16 | uint32_t(uint8_t(name[2])) << 8 |
           uint32_t(uint8_t(name[3]));
}

/// Big-endian reads; `has` says whether a range lies in the file (reads outside give 0, but
/// every caller asks `has` or `within` first).
class Bytes {
public:
    explicit Bytes(std::span<const uint8_t> bytes) : bytes_(bytes) {}
    uint64_t size() const { return bytes_.size(); }
    bool has(uint64_t offset, uint64_t length) const { return offset <= size() && length <= size() - offset; }
    uint8_t u8(uint64_t at) const { return has(at, 1) ? bytes_[at] : 0; }
    uint16_t u16(uint64_t at) const { return has(at, 2) ? uint16_t(bytes_[at] << 8 | bytes_[at + 1]) : 0; }
    int16_t s16(uint64_t at) const { return int16_t(u16(at)); }
    uint32_t u32(uint64_t at) const { return uint32_t(u16(at)) << 16 | u16(at + 2); }

private:
    std::span<const uint8_t> bytes_;
};

/// Whether `length` bytes at `offset` from the table's start lie within the table.
bool within(const TableRange& table, uint64_t offset, uint64_t length) {
    return offset <= table.length && length <= table.length - offset;
}

/// A table tag as text for a message (a damaged directory may hold any bytes).
std::string printable(std::string text) {
    for (char& c : text)
        if (c < 0x20 || c > 0x7E) c = '?';
    return text;
}

Error damaged(const std::string& what) { return makeError("the font is truncated or damaged: " + what); }

Result<void> findTables(const Bytes& in, FontTables& t) {
    const uint32_t face = t.faceOffset;
    if (!in.has(face, 12)) return makeError("too short to be a font (" + std::to_string(in.size()) + " bytes)");
    const uint32_t version = in.u32(face);
    if (version == tag("OTTO")) return makeError("an OpenType font with CFF outlines; only TrueType outlines (glyf) are supported");
    if (version != 0x00010000 && version != tag("true")) return makeError("not a TrueType font (no sfnt signature at its start)");
    const uint16_t count = in.u16(face + 4);
    if (!in.has(face + 12, 16ull * count))
        return damaged("its table directory (" + std::to_string(count) + " tables) runs past the end of the file (" +
                       std::to_string(in.size()) + " bytes)");

    // Every table, not only those read: a file cut anywhere is refused as a whole.
    for (uint32_t i = 0; i < count; ++i) {
        const uint64_t record = face + 12 + 16ull * i;
        const uint32_t offset = in.u32(record + 8), length = in.u32(record + 12);
        if (in.has(offset, length)) continue;
        const uint32_t name = in.u32(record);
        const std::string tagName{char(name >> 24), char(name >> 16), char(name >> 8), char(name)};
        return damaged("its '" + printable(tagName) + "' table (" + std::to_string(length) + " bytes at offset " +
                       std::to_string(offset) + ") runs past the end of the file (" + std::to_string(in.size()) + " bytes)");
    }

    struct Wanted {
        const char* name;
        TableRange* range;
        bool required;
    };
    const Wanted wanted[] = {{"cmap", &t.cmap, true}, {"head", &t.head, true}, {"hhea", &t.hhea, true},
                             {"hmtx", &t.hmtx, true}, {"maxp", &t.maxp, true}, {"loca", &t.loca, true},
                             {"glyf", &t.glyf, true}, {"kern", &t.kern, false}, {"GPOS", &t.gpos, false}};
    for (const Wanted& w : wanted) {
        bool found = false;
        const uint32_t wantedTag = tag(w.name);
        // The first record with the tag, as stb_truetype's stbtt__find_table takes it.
        for (uint32_t i = 0; i < count && !found; ++i) {
            const uint64_t record = face + 12 + 16ull * i;
            if (in.u32(record) != wantedTag) continue;
            found = true;
            *w.range = {in.u32(record + 8), in.u32(record + 12)};
        }
        if (w.required && !found) {
            const std::string extra = w.range == &t.glyf ? " (only TrueType outlines are supported)" : "";
            return makeError("not a usable TrueType font: it has no '" + std::string(w.name) + "' table" + extra);
        }
    }
    return {};
}

/// head, maxp, hhea, hmtx and loca: the sizes and counts the metrics and glyph lookups rely on.
Result<void> checkMetrics(const Bytes& in, FontTables& t) {
    // OpenType 'head': unitsPerEm at 18 (16..16384), indexToLocFormat at 50 (0 or 1), 54 bytes.
    if (!within(t.head, 0, 54)) return damaged("its 'head' table is shorter than 54 bytes");
    t.unitsPerEm = in.u16(t.head.offset + 18);
    if (t.unitsPerEm < 16 || t.unitsPerEm > 16384)
        return damaged("its unitsPerEm (" + std::to_string(t.unitsPerEm) + ") is outside 16..16384");
    const int16_t locFormat = in.s16(t.head.offset + 50);
    if (locFormat != 0 && locFormat != 1) return damaged("its indexToLocFormat is " + std::to_string(locFormat));
    t.longLoca = locFormat == 1;

    // 'maxp': numGlyphs at 4. 'hhea': numberOfHMetrics at 34, 36 bytes.
    if (!within(t.maxp, 0, 6)) return damaged("its 'maxp' table is shorter than 6 bytes");
    t.numGlyphs = in.u16(t.maxp.offset + 4);
    if (t.numGlyphs == 0) return damaged("it has no glyphs");
    if (!within(t.hhea, 0, 36)) return damaged("its 'hhea' table is shorter than 36 bytes");
    t.numHMetrics = in.u16(t.hhea.offset + 34);
    if (t.numHMetrics == 0) return damaged("its numberOfHMetrics is 0");
    // 'hmtx': a (advance, lsb) pair per long metric, then an lsb for each remaining glyph.
    const uint64_t hmtxBytes = 4ull * t.numHMetrics + 2ull * std::max(0, int(t.numGlyphs) - int(t.numHMetrics));
    if (!within(t.hmtx, 0, hmtxBytes)) return damaged("its 'hmtx' table is shorter than its glyph count needs");

    // 'loca': numGlyphs + 1 offsets into 'glyf'.
    const uint64_t entry = t.longLoca ? 4 : 2;
    if (!within(t.loca, 0, entry * (t.numGlyphs + 1ull))) return damaged("its 'loca' table is shorter than its glyph count needs");
    for (uint32_t g = 0; g <= t.numGlyphs; ++g) {
        const uint64_t at = t.loca.offset + entry * g;
        const uint64_t offset = t.longLoca ? in.u32(at) : 2ull * in.u16(at);
        if (offset > t.glyf.length)
            return damaged("its 'loca' table points past the end of 'glyf' (glyph " + std::to_string(g) + ")");
    }
    return {};
}

/// The format-4 subtable's arrays, and its search header rewritten from the segment count.
Result<void> checkCmapFormat4(std::span<uint8_t> bytes, uint64_t sub, uint64_t available) {
    const Bytes in(bytes);
    if (available < 14) return damaged("its format-4 character map is cut short");
    const uint16_t segCountX2 = in.u16(sub + 6);
    if (segCountX2 == 0 || segCountX2 % 2 != 0) return damaged("its format-4 character map has a bad segment count");
    const uint32_t segments = segCountX2 / 2u;
    // endCode[seg], reservedPad, startCode[seg], idDelta[seg], idRangeOffset[seg] (OpenType 'cmap' format 4).
    if (16ull + 8ull * segments > available) return damaged("its format-4 character map runs past the 'cmap' table");
    for (uint32_t s = 0; s < segments; ++s) {
        const uint16_t end = in.u16(sub + 14 + 2ull * s), start = in.u16(sub + 16 + 2ull * segments + 2ull * s);
        const uint64_t rangeOffsetAt = 16ull + 6ull * segments + 2ull * s;   // relative to the subtable
        const uint16_t rangeOffset = in.u16(sub + rangeOffsetAt);
        if (rangeOffset == 0 || start > end) continue;
        // glyphIdArray entries are addressed from the idRangeOffset word itself.
        if (rangeOffsetAt + rangeOffset + 2ull * (end - start) + 2 > available)
            return damaged("its format-4 character map points past the 'cmap' table");
    }
    uint32_t range = 1, selector = 0;
    while (range * 2 <= segments) range *= 2, ++selector;
    const uint16_t header[3] = {uint16_t(2 * range), uint16_t(selector), uint16_t(segCountX2 - 2 * range)};
    for (int i = 0; i < 3; ++i) {
        bytes[sub + 8 + 2 * i] = uint8_t(header[i] >> 8);
        bytes[sub + 9 + 2 * i] = uint8_t(header[i] & 0xFF);
    }
    return {};
}

/// The Unicode subtable stb_truetype picks (the last record for platform 0, or 3 with encoding
/// 1 or 10), in a format it reads and within the 'cmap' table.
Result<void> checkCmap(std::span<uint8_t> bytes, const FontTables& t) {
    const Bytes in(bytes);
    if (!within(t.cmap, 0, 4)) return damaged("its 'cmap' table is shorter than 4 bytes");
    const uint16_t records = in.u16(t.cmap.offset + 2);
    if (!within(t.cmap, 4, 8ull * records)) return damaged("its 'cmap' records run past the table");
    bool found = false;
    uint32_t chosen = 0;
    for (uint32_t i = 0; i < records; ++i) {
        const uint64_t record = t.cmap.offset + 4 + 8ull * i;
        const uint16_t platform = in.u16(record), encoding = in.u16(record + 2);
        if (platform == 0 || (platform == 3 && (encoding == 1 || encoding == 10))) found = true, chosen = in.u32(record + 4);
    }
    if (!found) return makeError("not a usable font: it has no Unicode character map");
    if (!within(t.cmap, chosen, 4)) return damaged("its Unicode character map lies outside the 'cmap' table");
    const uint64_t sub = t.cmap.offset + chosen, available = t.cmap.length - uint64_t(chosen);
    const uint16_t format = in.u16(sub);
    switch (format) {
    case 0:   // a byte per code point below `length - 6`
        if (std::max<uint64_t>(6, in.u16(sub + 2)) > available) return damaged("its format-0 character map is cut short");
        return {};
    case 4: return checkCmapFormat4(bytes, sub, available);
    case 6:   // firstCode, entryCount, then a glyph per entry
        if (available < 10 || 10ull + 2ull * in.u16(sub + 8) > available) return damaged("its format-6 character map is cut short");
        return {};
    case 12:
    case 13:   // groups of (startCharCode, endCharCode, glyph), 12 bytes each, from byte 16
        if (available < 16 || 16ull + 12ull * in.u32(sub + 12) > available)
            return damaged("its format-" + std::to_string(format) + " character map is cut short");
        return {};
    default:
        return makeError("not a usable font: its Unicode character map has format " + std::to_string(format) +
                         ", which stb_truetype does not read");
    }
}

/// 'kern' version 0, the first subtable, format 0: nPairs at 10, pairs of 6 bytes from 18.
bool kernIsSafe(const Bytes& in, const TableRange& kern) {
    if (!kern.present() || !within(kern, 0, 18)) return false;
    return within(kern, 18, 6ull * in.u16(kern.offset + 10));
}

/// The largest index a coverage table can give: -1 when it covers nothing, -2 when it is damaged.
int64_t coverageMaxIndex(const Bytes& in, const TableRange& g, uint64_t coverage) {
    if (!within(g, coverage, 4)) return -2;
    const uint16_t count = in.u16(g.offset + coverage + 2);
    switch (in.u16(g.offset + coverage)) {
    case 1: return within(g, coverage + 4, 2ull * count) ? int64_t(count) - 1 : -2;
    case 2: {
        if (!within(g, coverage + 4, 6ull * count)) return -2;
        int64_t most = -1;
        for (uint32_t r = 0; r < count; ++r) {
            const uint64_t record = g.offset + coverage + 4 + 6ull * r;
            const uint16_t start = in.u16(record), end = in.u16(record + 2), first = in.u16(record + 4);
            if (start <= end) most = std::max<int64_t>(most, int64_t(first) + end - start);
        }
        return most;
    }
    default: return -1;   // stb_truetype skips a coverage format it does not know
    }
}

bool classDefIsSafe(const Bytes& in, const TableRange& g, uint64_t def) {
    if (!within(g, def, 4)) return false;
    switch (in.u16(g.offset + def)) {
    case 1: return within(g, def, 6) && within(g, def + 6, 2ull * in.u16(g.offset + def + 4));
    case 2: return within(g, def + 4, 6ull * in.u16(g.offset + def + 2));
    default: return true;   // stb_truetype returns no class
    }
}

/// A pair-adjustment subtable, read as stb_truetype's stbtt__GetGlyphGPOSInfoAdvance reads it:
/// only value formats (4, 0) go past the header.
bool pairSubtableIsSafe(const Bytes& in, const TableRange& g, uint64_t sub) {
    const auto u16 = [&](uint64_t at) { return in.u16(g.offset + at); };
    if (!within(g, sub, 8)) return false;
    const int64_t maxIndex = coverageMaxIndex(in, g, sub + u16(sub + 2));
    if (maxIndex == -2) return false;
    if (maxIndex < 0 || u16(sub + 4) != 4 || u16(sub + 6) != 0) return true;
    switch (u16(sub)) {
    case 1: {   // pairSetCount at 8, pairSetOffsets from 10 (read for any covered index)
        if (!within(g, sub, 10) || !within(g, sub + 10, 2ull * uint64_t(maxIndex + 1))) return false;
        const uint16_t pairSets = u16(sub + 8);
        for (int64_t i = 0; i <= maxIndex; ++i) {
            const uint64_t set = sub + u16(sub + 10 + 2 * uint64_t(i));
            if (!within(g, set, 2)) return false;
            if (i < pairSets && !within(g, set + 2, 4ull * u16(set))) return false;
        }
        return true;
    }
    case 2:   // classDef1, classDef2, class1Count, class2Count, then class1Count x class2Count values
        if (!within(g, sub, 16)) return false;
        if (!classDefIsSafe(in, g, sub + u16(sub + 8)) || !classDefIsSafe(in, g, sub + u16(sub + 10))) return false;
        return within(g, sub + 16, 2ull * u16(sub + 12) * u16(sub + 14));
    default: return true;
    }
}

bool gposIsSafe(const Bytes& in, const TableRange& g) {
    const auto u16 = [&](uint64_t at) { return in.u16(g.offset + at); };
    if (!g.present() || !within(g, 0, 10)) return false;
    if (u16(0) != 1 || u16(2) != 0) return true;   // not version 1.0: stb_truetype reads no further
    const uint64_t list = u16(8);
    if (!within(g, list, 2) || !within(g, list + 2, 2ull * u16(list))) return false;
    for (uint32_t i = 0, lookups = u16(list); i < lookups; ++i) {
        const uint64_t lookup = list + u16(list + 2 + 2ull * i);
        if (!within(g, lookup, 6)) return false;
        if (u16(lookup) != 2) continue;   // only pair adjustment
        const uint16_t subtables = u16(lookup + 4);
        if (!within(g, lookup + 6, 2ull * subtables)) return false;
        for (uint32_t s = 0; s < subtables; ++s)
            if (!pairSubtableIsSafe(in, g, lookup + u16(lookup + 6 + 2ull * s))) return false;
    }
    return true;
}

bool outlineIsSafe(const Bytes& in, const FontTables& t, uint32_t glyph, int depth, int& components);

/// A simple glyph (OpenType 'glyf'): endPtsOfContours, instructions, then flags (with repeat
/// counts) and x and y coordinates whose sizes the flags give.
bool simpleOutlineIsSafe(const Bytes& in, uint64_t at, uint64_t limit, int contours) {
    if (at + 2ull * contours + 2 > limit) return false;
    for (int c = 1; c < contours; ++c)   // strictly increasing, as the spec requires
        if (in.u16(at + 2ull * c) <= in.u16(at + 2ull * (c - 1))) return false;
    const uint32_t points = in.u16(at + 2ull * (contours - 1)) + 1u;
    const uint32_t lastContourStart = contours > 1 ? in.u16(at + 2ull * (contours - 2)) + 1u : 0u;
    at += 2ull * contours;
    at += 2ull + in.u16(at);
    uint64_t coordinateBytes = 0;
    uint8_t flags = 0;
    for (uint32_t i = 0; i < points;) {
        if (at >= limit) return false;
        flags = in.u8(at++);
        uint32_t repeat = 1;
        if (flags & 8) {
            if (at >= limit) return false;
            repeat += in.u8(at++);
        }
        repeat = std::min(repeat, points - i);
        const uint32_t xBytes = (flags & 2) ? 1 : (flags & 16) ? 0 : 2, yBytes = (flags & 4) ? 1 : (flags & 32) ? 0 : 2;
        coordinateBytes += uint64_t(repeat) * (xBytes + yBytes);
        i += repeat;
    }
    if (at + coordinateBytes > limit) return false;
    // stb_truetype looks one point past the end when the last contour is one off-curve point.
    return !(points - lastContourStart == 1 && !(flags & 1));
}

/// A compound glyph: components of flags, glyph index, offsets and an optional transform.
bool compoundOutlineIsSafe(const Bytes& in, const FontTables& t, uint64_t at, uint64_t limit, int depth, int& components) {
    for (;;) {
        if (at + 4 > limit || ++components > kMaxComponents) return false;
        const uint16_t flags = in.u16(at), component = in.u16(at + 2);
        at += 4;
        if (!(flags & 2)) return false;   // point-matched placement: stb_truetype asserts
        at += (flags & 1) ? 4 : 2;
        if (flags & 8) at += 2;           // one scale
        else if (flags & 64) at += 4;     // x and y scales
        else if (flags & 128) at += 8;    // a 2 x 2 matrix
        if (at > limit) return false;
        if (!outlineIsSafe(in, t, component, depth + 1, components)) return false;
        if (!(flags & 32)) return true;   // no more components
    }
}

bool outlineIsSafe(const Bytes& in, const FontTables& t, uint32_t glyph, int depth, int& components) {
    if (depth > kMaxCompoundDepth) return false;
    if (glyph >= t.numGlyphs) return true;   // stb_truetype gives no outline for it
    const uint64_t entry = t.longLoca ? 4 : 2, at = t.loca.offset + entry * glyph;
    const uint64_t start = t.longLoca ? in.u32(at) : 2ull * in.u16(at);
    const uint64_t end = t.longLoca ? in.u32(at + entry) : 2ull * in.u16(at + entry);
    if (start == end) return true;   // no outline (a space)
    if (start > end || end > t.glyf.length || end - start < 10) return false;
    const uint64_t base = t.glyf.offset + start, limit = t.glyf.offset + end;
    const int16_t contours = in.s16(base);
    if (contours > 0) return simpleOutlineIsSafe(in, base + 10, limit, contours);
    if (contours < 0) return compoundOutlineIsSafe(in, t, base + 10, limit, depth, components);
    return true;
}

}  // namespace

Result<FontTables> checkFontTables(std::span<uint8_t> bytes, uint32_t faceOffset) {
    const Bytes in(bytes);
    FontTables t;
    t.faceOffset = faceOffset;
    if (auto ok = findTables(in, t); !ok) return ok.error();
    if (auto ok = checkMetrics(in, t); !ok) return ok.error();
    if (auto ok = checkCmap(bytes, t); !ok) return ok.error();
    // Kerning is optional: a damaged table is left unread rather than failing the font.
    t.kernUsable = kernIsSafe(in, t.kern);
    t.gposUsable = gposIsSafe(in, t.gpos);
    return t;
}

bool glyphOutlineIsSafe(std::span<const uint8_t> bytes, const FontTables& tables, uint32_t glyph) {
    int components = 0;
    return outlineIsSafe(Bytes(bytes), tables, glyph, 0, components);
}

}  // namespace orbis::vector::font
