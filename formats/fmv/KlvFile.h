#pragma once
// Raw KLV streams: files of concatenated MISB ST 0601 packets (`.bin`, `.klv`, the data stream
// of an MPEG-TS dumped as is). Garbage between packets is skipped by searching for the next
// ST 0601 key; a packet that does not decode is reported with its offset and the reason, and
// reading goes on after its key.

#include "base/Result.h"
#include "formats/fmv/St0601.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace orbis::fmv {

/// Largest KLV file read. It is read whole and its packets decoded at ~900 bytes each (several
/// times a packet's size), so this bounds memory at about 1 GB; it holds over 4 hours of 30 Hz
/// packets of 1 kB. Larger files are refused with a clear error, never swallowed.
inline constexpr uint64_t kMaxKlvFileBytes = uint64_t(128) << 20;

/// One packet of a stream: decoded, or the reason it could not be.
struct KlvRecord {
    uint64_t offset = 0;                  ///< of the packet's first key byte in the stream
    std::optional<St0601Packet> packet;   ///< absent when the packet could not be decoded
    std::string error;                    ///< why not (empty when `packet` is there)
};

/// Bytes skipped between packets (not the start of an ST 0601 packet, or the rest of a packet
/// that did not decode).
struct KlvGap {
    uint64_t offset = 0;
    uint64_t bytes = 0;
};

struct KlvStream {
    std::vector<KlvRecord> records;   ///< in stream order
    std::vector<KlvGap> gaps;
    std::size_t decodedCount() const;     ///< records with a packet
    std::size_t checksumErrors() const;   ///< decoded records whose checksum does not match
};

/// Every ST 0601 packet in `bytes`, with resynchronisation on the key after garbage or a bad
/// packet. Never fails: a buffer with no key is one gap. Any thread.
KlvStream decodeKlvStream(Bytes bytes);

/// Reads `path` whole and decodes it. Errors name the file: unreadable, empty, over
/// kMaxKlvFileBytes, or no ST 0601 key anywhere in it. Per-packet problems are in the records.
Result<KlvStream> readKlvFile(const std::string& path);

/// By extension (.bin, .klv, any case) or by the ST 0601 key in the first 16 bytes.
bool looksLikeKlv(const std::string& path);

}  // namespace orbis::fmv
