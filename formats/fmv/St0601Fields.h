#pragma once
// The ST 0601 tags this decoder knows, as one table shared by the decoder, the encoder and the
// JSON writer: tag, name, how the value is mapped, and where it lives in St0601Packet. Internal
// to layers/fmv (tests use it to walk every mapping).

#include "formats/fmv/St0601.h"

#include <span>

namespace orbis::fmv::detail {

enum class Kind {
    Unsigned,    ///< uint of `bytes` bytes mapped linearly onto [min, max]; no error value
    Signed,      ///< int of `bytes` bytes mapped onto [-max, max] by ±(2^(8n-1) - 1); INT_MIN is the error value
    Imapb,       ///< ST 1201 IMAPB(min, max), 1..`bytes` bytes; values with the top bit set are special
    Text,        ///< ISO 646 text
    Timestamp,   ///< uint64 µs since 1970 (tag 2)
    Integer,     ///< uint of `bytes` bytes taken as is (tag 65)
};

using Number = std::optional<double> St0601Packet::*;
using Corners = std::array<std::optional<double>, 4> St0601Packet::*;
using Text = std::optional<std::string> St0601Packet::*;

struct Field {
    uint32_t tag = 0;
    const char* name = "";
    Kind kind = Kind::Unsigned;
    int bytes = 0;            ///< exact value size (Unsigned, Signed, Timestamp, Integer); the most for Imapb
    double min = 0.0, max = 0.0;
    Number number = nullptr;  ///< where a decoded number goes ...
    Corners corners = nullptr;   ///< ... or this array at `index`
    int index = 0;
    Text text = nullptr;      ///< Kind::Text

    /// The packet's value for this field (Unsigned, Signed, Imapb).
    template <typename P>
    auto& numberIn(P& p) const { return number ? p.*number : (p.*corners)[std::size_t(index)]; }
    /// Value of one step of the integer (the decode's resolution), for `n` value bytes.
    double lsb(std::size_t n) const;
    /// Whether the mapping has an error value that the encoder can write.
    bool hasErrorValue() const { return kind == Kind::Signed || kind == Kind::Imapb; }
};

/// Every tag decoded, in tag order.
std::span<const Field> st0601Fields();
/// The field of `tag`, or nullptr.
const Field* findField(uint32_t tag);

/// A mapped number as decoded: the value, or none with `error` set (sentinel, special value,
/// out of range).
struct Mapped {
    std::optional<double> value;
    bool error = false;
};
/// Decodes `value` (already checked to have the right size) through `field`'s mapping.
Mapped decodeNumber(const Field& field, Bytes value);
/// Appends `field`'s encoding of `value`: nullopt, NaN or (Signed) out of range gives the error
/// value, Unsigned clamps to its range (it has no error value: callers leave such a tag out).
/// Imapb uses `imapbBytes` bytes.
void encodeNumber(const Field& field, std::optional<double> value, std::vector<uint8_t>& out, int imapbBytes);

/// ST 1201 IMAPB(a, b) of `n` bytes (1..8): decode of an integer, and encode (floor, clamped).
Mapped imapbDecode(double a, double b, uint64_t y, std::size_t n);
uint64_t imapbEncode(double a, double b, double x, std::size_t n);

}  // namespace orbis::fmv::detail
