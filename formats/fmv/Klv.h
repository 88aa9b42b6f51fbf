#pragma once
// SMPTE ST 336 KLV (key-length-value), CPU only: the byte-level pieces every MISB set is made of.
//
//  - 16-byte Universal Keys, found in a byte stream (to resynchronise after garbage);
//  - BER lengths: short form (one byte, 0..127) and long form (0x81..0x88, then that many bytes,
//    big-endian); the indefinite form 0x80 and forms longer than 8 bytes are refused;
//  - BER-OID tag numbers of local sets (7 bits a byte, high bit = more bytes follow), at most
//    4 bytes;
//  - a bounds-checked big-endian cursor, and a splitter of a local set into its items.
//
// Nothing here reads outside the span it is given or allocates from a length read in the data:
// every length is checked against the bytes that are there before it is used. Errors are
// Result values that say what is wrong (and, above the BER readers, at which byte offset);
// callers add the file.

#include "base/Result.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace orbis::fmv {

using Bytes = std::span<const uint8_t>;
using UniversalKey = std::array<uint8_t, 16>;

/// MISB ST 0601 UAS Datalink Local Set key (ST 0601: 06 0E 2B 34 02 0B 01 01 0E 01 03 01 01 00 00 00).
inline constexpr UniversalKey kSt0601Key = {0x06, 0x0E, 0x2B, 0x34, 0x02, 0x0B, 0x01, 0x01,
                                            0x0E, 0x01, 0x03, 0x01, 0x01, 0x00, 0x00, 0x00};

/// True when the 16 bytes at `bytes` are `key`. Byte 8 (index 7) is the registry's version
/// number, which SMPTE ST 336 excludes from a key's identity (decoders ignore it).
/// `bytes` must hold at least 16 bytes.
bool sameKey(const uint8_t* bytes, const UniversalKey& key);

/// Offset of the first occurrence of `key` in `bytes` at or after `from`; `bytes.size()` when
/// there is none.
std::size_t findKey(Bytes bytes, const UniversalKey& key, std::size_t from = 0);

/// A BER length or BER-OID number as read: its value and how many bytes it took.
struct BerValue {
    uint64_t value = 0;
    std::size_t bytes = 0;
};

/// The BER length at `bytes[at]` (SMPTE ST 336, ITU-T X.690 §8.1.3): short form (one byte,
/// 0..127) or long form (0x81..0x88, then 1..8 big-endian bytes, non-minimal forms accepted:
/// ST 0601 writers use 0x81 0x05). Refused: 0x80 (the indefinite form, not allowed in KLV),
/// 0x89..0xFF (more than 8 bytes), and a length field cut by the end of `bytes`. The value is
/// NOT checked against the buffer: the caller knows what follows.
Result<BerValue> readBerLength(Bytes bytes, std::size_t at);

/// Longest BER-OID tag read: 4 bytes hold 28 bits, far beyond any MISB tag (ST 0601 uses < 2^8).
inline constexpr std::size_t kMaxBerOidBytes = 4;

/// The BER-OID number at `bytes[at]` (SMPTE ST 336 local-set tags, ITU-T X.690 §8.19): 7 bits a byte, most significant
/// first, the high bit set on every byte but the last. Refused: more than kMaxBerOidBytes bytes,
/// and a number cut by the end of `bytes`.
Result<BerValue> readBerOid(Bytes bytes, std::size_t at);

/// Appends `length` as a BER length in the shortest form (short form up to 127).
void appendBerLength(std::vector<uint8_t>& out, uint64_t length);
/// Appends `length` in the long form with exactly `lengthBytes` (1..8) bytes after the first
/// (0x81 0x05 for 5 with 1). Lengths that do not fit are clamped to the largest that does.
void appendBerLengthLong(std::vector<uint8_t>& out, uint64_t length, int lengthBytes);
/// Appends `tag` as a BER-OID number.
void appendBerOid(std::vector<uint8_t>& out, uint32_t tag);

/// Big-endian unsigned integer of 1..8 bytes (0 for an empty span; callers check sizes).
uint64_t bigEndian(Bytes bytes);
/// Appends the low `bytes` (1..8) bytes of `value`, big-endian.
void appendBigEndian(std::vector<uint8_t>& out, uint64_t value, int bytes);

/// A forward cursor over a byte span that never reads past its end: a read that does not fit
/// returns false (or an empty optional) and leaves the cursor where it was.
class ByteReader {
public:
    explicit ByteReader(Bytes bytes) : bytes_(bytes) {}

    std::size_t position() const { return pos_; }
    std::size_t remaining() const { return bytes_.size() - pos_; }
    bool atEnd() const { return pos_ == bytes_.size(); }

    /// The next `n` bytes, advancing past them; false when fewer remain.
    bool take(std::size_t n, Bytes& out);
    /// Skips `n` bytes; false (and no move) when fewer remain.
    bool skip(std::size_t n);
    /// The next byte.
    bool u8(uint8_t& out);
    /// A big-endian unsigned integer of `n` (1..8) bytes.
    bool uintBE(std::size_t n, uint64_t& out);

private:
    Bytes bytes_;
    std::size_t pos_ = 0;
};

/// One item of a local set: its tag, where its tag starts in the set, and its value.
struct LocalSetItem {
    uint32_t tag = 0;
    std::size_t offset = 0;   ///< of the tag's first byte, relative to the set's value + `base`
    std::size_t headerBytes = 0;   ///< tag + length bytes
    Bytes value;
};

/// Splits the value of a local set (the bytes after its key and length) into items, in order.
/// `base` is added to every offset, in items and in messages (the set's position in its file or
/// packet). An item whose tag or length is malformed, or whose value runs past the end of the
/// set, is an error naming the byte offset: nothing after it can be trusted.
Result<std::vector<LocalSetItem>> splitLocalSet(Bytes set, std::size_t base = 0);

/// A key-length-value triplet with a universal key, located in a buffer.
struct KlvTriplet {
    std::size_t keyOffset = 0;     ///< first key byte
    std::size_t valueOffset = 0;   ///< first value byte
    std::size_t length = 0;        ///< value bytes
    std::size_t end() const { return valueOffset + length; }
};

/// The triplet whose 16-byte key starts at `bytes[at]`: its BER length is read and checked
/// against the bytes left and against `maxLength`. The key itself is not compared. Offsets in
/// the triplet are relative to `bytes`; `base` is added to offsets in messages.
Result<KlvTriplet> readTriplet(Bytes bytes, std::size_t at, std::size_t maxLength, std::size_t base = 0);

/// Lower-case hex of `bytes`, two digits a byte, no separators ("060e2b34").
std::string toHex(Bytes bytes);

}  // namespace orbis::fmv
