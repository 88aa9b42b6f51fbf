#pragma once
// UTF-8 to code points (label text; names of values that are not UTF-8 in orbis info). Bad input is data, not an error: every ill-formed
// sequence becomes U+FFFD, one per maximal subpart (Unicode 15, §3.9 "U+FFFD Substitution of
// Maximal Subparts", the same rule as the WHATWG Encoding standard), so a truncated name costs
// one replacement glyph, not the rest of the string. No Vulkan, no fonts.

#include <cstddef>
#include <string>
#include <string_view>

namespace orbis {

inline constexpr char32_t kReplacementCharacter = 0xFFFD;

/// The code point that starts at `pos` in `text` (`pos < text.size()`), and `pos` moved past
/// it. An ill-formed sequence (a stray continuation byte, a lead byte without its continuation
/// bytes, an overlong form, a surrogate, a value past U+10FFFF) gives U+FFFD with `valid` false.
/// Never reads at or past `text.size()`. Any thread.
char32_t decodeUtf8(std::string_view text, std::size_t& pos, bool& valid);

/// Every code point of `text` (ill-formed sequences as U+FFFD). Any thread.
std::u32string decodeUtf8(std::string_view text);

}  // namespace orbis
