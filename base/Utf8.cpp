#include "base/Utf8.h"

namespace orbis {
namespace {

bool isContinuation(unsigned char byte) { return (byte & 0xC0) == 0x80; }

}  // namespace

char32_t decodeUtf8(std::string_view text, std::size_t& pos, bool& valid) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(pos++);
    valid = true;
    if (lead < 0x80) return lead;

    // Unicode 15, table 3-7 (well-formed byte sequences): the lead byte sets the length and the
    // range of the first continuation byte, which is what excludes overlong forms (E0, F0),
    // surrogates (ED) and values past U+10FFFF (F4). C0, C1 and F5..FF never start a sequence.
    int length = 0;
    unsigned char low = 0x80, high = 0xBF;
    char32_t value = 0;
    if (lead >= 0xC2 && lead <= 0xDF) { length = 2; value = lead & 0x1F; }
    else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3; value = lead & 0x0F;
        if (lead == 0xE0) low = 0xA0;
        if (lead == 0xED) high = 0x9F;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4; value = lead & 0x07;
        if (lead == 0xF0) low = 0x90;
        if (lead == 0xF4) high = 0x8F;
    } else {
        valid = false;
        return kReplacementCharacter;
    }
    for (int i = 1; i < length; ++i) {
        // The maximal subpart ends at the first byte that cannot continue the sequence; that
        // byte is not consumed, so it starts the next code point.
        if (pos >= text.size()) { valid = false; return kReplacementCharacter; }
        const unsigned char next = byte(pos);
        const bool inRange = i == 1 ? (next >= low && next <= high) : isContinuation(next);
        if (!inRange) { valid = false; return kReplacementCharacter; }
        value = (value << 6) | (next & 0x3F);
        ++pos;
    }
    return value;
}

std::u32string decodeUtf8(std::string_view text) {
    std::u32string out;
    out.reserve(text.size());
    bool valid = true;
    for (std::size_t pos = 0; pos < text.size();) out.push_back(decodeUtf8(text, pos, valid));
    return out;
}

}  // namespace orbis
