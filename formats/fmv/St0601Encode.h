#pragma once
// Writes MISB ST 0601 packets: the inverse of decodeSt0601, for tests and fixture tools (the
// synthetic-flight MPEG-TS writer). Every mapping is the standard's, so what is written here
// decodes in any ST 0601 reader to within one step of the integer.

#include "formats/fmv/St0601.h"

#include <cstdint>
#include <vector>

namespace orbis::fmv {

struct St0601EncodeOptions {
    /// Bytes after 0x8n of the packet's BER length: 0 writes the shortest form; 1..8 force the
    /// long form (real encoders often write 0x81 nn even for short packets).
    int packetLengthBytes = 0;
    /// Bytes of IMAPB values (tag 104): 1..8. 4 gives 2^-15 m steps.
    int imapbBytes = 4;
    /// Write tag 65 (UAS LS version) when the packet has none.
    bool writeVersion = false;
};

/// One packet: key, BER length, tag 2 first (as ST 0601 asks), then the other fields present in
/// tag order, then `otherTags` verbatim in their order, then the checksum (tag 1) computed over
/// everything before its value. Values are written through the tag's mapping: out-of-range
/// values of signed tags, NaN, and absent values of tags listed in `errorTags` are written as
/// the tag's error value (INT_MIN, or ST 1201's NaN for IMAPB); unsigned tags clamp to their
/// range. `checksum`, `size`, `warnings` and the stored checksums of `packet` are ignored.
std::vector<uint8_t> encodeSt0601(const St0601Packet& packet, const St0601EncodeOptions& options = {});

}  // namespace orbis::fmv
