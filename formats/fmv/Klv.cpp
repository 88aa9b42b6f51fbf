#include "formats/fmv/Klv.h"

#include <algorithm>
#include <cstring>

namespace orbis::fmv {
namespace {

std::string at(std::size_t offset) { return std::string("byte ").append(std::to_string(offset)); }

}  // namespace

bool sameKey(const uint8_t* bytes, const UniversalKey& key) {
    // Bytes 0..6 and 8..15; byte 7 is the registry version (SMPTE ST 336).
    return std::memcmp(bytes, key.data(), 7) == 0 && std::memcmp(bytes + 8, key.data() + 8, 8) == 0;
}

std::size_t findKey(Bytes bytes, const UniversalKey& key, std::size_t from) {
    const std::size_t n = bytes.size();
    if (n < key.size()) return n;
    const std::size_t last = n - key.size();   // the last offset a whole key fits at
    while (from <= last) {
        const void* hit = std::memchr(bytes.data() + from, key[0], last - from + 1);
        if (!hit) return n;
        const std::size_t i = std::size_t(static_cast<const uint8_t*>(hit) - bytes.data());
        if (sameKey(bytes.data() + i, key)) return i;
        from = i + 1;
    }
    return n;
}

Result<BerValue> readBerLength(Bytes bytes, std::size_t offset) {
    if (offset >= bytes.size()) return makeError(std::string("BER length: past the end of the data"));
    const uint8_t first = bytes[offset];
    if (first < 0x80) return BerValue{first, 1};
    // X.690 §8.1.3.6: 0x80 is the indefinite form, which KLV does not allow.
    if (first == 0x80)
        return makeError(std::string("BER length: indefinite form (0x80) is not allowed in KLV"));
    const std::size_t count = first & 0x7F;
    if (count > 8)
        return makeError(std::string("BER length: long form of ").append(std::to_string(count))
                             .append(" bytes (at most 8)"));
    if (bytes.size() - offset - 1 < count)
        return makeError(std::string("BER length: long form of ").append(std::to_string(count))
                             .append(" bytes cut by the end of the data"));
    return BerValue{bigEndian(bytes.subspan(offset + 1, count)), 1 + count};
}

Result<BerValue> readBerOid(Bytes bytes, std::size_t offset) {
    uint64_t value = 0;
    for (std::size_t i = 0; i < kMaxBerOidBytes; ++i) {
        if (offset + i >= bytes.size())
            return makeError(std::string("BER-OID tag cut by the end of the data"));
        const uint8_t b = bytes[offset + i];
        value = (value << 7) | (b & 0x7F);
        if (!(b & 0x80)) return BerValue{value, i + 1};
    }
    return makeError(std::string("BER-OID tag longer than ")
                         .append(std::to_string(kMaxBerOidBytes)).append(" bytes"));
}

void appendBerLength(std::vector<uint8_t>& out, uint64_t length) {
    if (length < 0x80) {
        out.push_back(uint8_t(length));
        return;
    }
    int n = 1;
    while (n < 8 && (length >> (8 * n)) != 0) ++n;
    appendBerLengthLong(out, length, n);
}

void appendBerLengthLong(std::vector<uint8_t>& out, uint64_t length, int lengthBytes) {
    lengthBytes = std::clamp(lengthBytes, 1, 8);
    if (lengthBytes < 8) length = std::min<uint64_t>(length, (uint64_t(1) << (8 * lengthBytes)) - 1);
    out.push_back(uint8_t(0x80 | lengthBytes));
    appendBigEndian(out, length, lengthBytes);
}

void appendBerOid(std::vector<uint8_t>& out, uint32_t tag) {
    uint8_t groups[5];
    int n = 0;
    do {
        groups[n++] = uint8_t(tag & 0x7F);
        tag >>= 7;
    } while (tag != 0);
    while (n > 1) out.push_back(uint8_t(groups[--n] | 0x80));
    out.push_back(groups[0]);
}

uint64_t bigEndian(Bytes bytes) {
    uint64_t v = 0;
    for (std::size_t i = 0; i < bytes.size() && i < 8; ++i) v = (v << 8) | bytes[i];
    return v;
}

void appendBigEndian(std::vector<uint8_t>& out, uint64_t value, int bytes) {
    bytes = std::clamp(bytes, 1, 8);
    for (int i = bytes - 1; i >= 0; --i) out.push_back(uint8_t(value >> (8 * i)));
}

bool ByteReader::take(std::size_t n, Bytes& out) {
    if (n > remaining()) return false;
    out = bytes_.subspan(pos_, n);
    pos_ += n;
    return true;
}

bool ByteReader::skip(std::size_t n) {
    if (n > remaining()) return false;
    pos_ += n;
    return true;
}

bool ByteReader::u8(uint8_t& out) {
    if (atEnd()) return false;
    out = bytes_[pos_++];
    return true;
}

bool ByteReader::uintBE(std::size_t n, uint64_t& out) {
    if (n == 0 || n > 8 || n > remaining()) return false;
    out = bigEndian(bytes_.subspan(pos_, n));
    pos_ += n;
    return true;
}

Result<std::vector<LocalSetItem>> splitLocalSet(Bytes set, std::size_t base) {
    std::vector<LocalSetItem> items;
    items.reserve(48);   // a full ST 0601 packet has ~30-60 items: one allocation in the usual case
    std::size_t pos = 0;
    while (pos < set.size()) {
        auto tag = readBerOid(set, pos);
        if (!tag) return makeError(std::string("local set item at ").append(at(base + pos)).append(": ").append(tag.message()));
        auto length = readBerLength(set, pos + tag->bytes);
        if (!length)
            return makeError(std::string("tag ").append(std::to_string(tag->value)).append(" at ").append(at(base + pos))
                                 .append(": ").append(length.message()));
        const std::size_t header = tag->bytes + length->bytes;
        const std::size_t left = set.size() - pos - header;
        if (length->value > left)
            return makeError(std::string("tag ").append(std::to_string(tag->value)).append(" at ").append(at(base + pos))
                                 .append(": length ").append(std::to_string(length->value)).append(" runs past the end of the set (")
                                 .append(std::to_string(left)).append(" bytes left)"));
        items.push_back({uint32_t(tag->value), base + pos, header, set.subspan(pos + header, std::size_t(length->value))});
        pos += header + std::size_t(length->value);
    }
    return items;
}

Result<KlvTriplet> readTriplet(Bytes bytes, std::size_t offset, std::size_t maxLength, std::size_t base) {
    if (offset > bytes.size() || bytes.size() - offset < 16)
        return makeError(std::string("key at ").append(at(base + offset)).append(": cut by the end of the data (")
                             .append(std::to_string(offset > bytes.size() ? 0 : bytes.size() - offset)).append(" bytes left, a key is 16)"));
    auto length = readBerLength(bytes, offset + 16);
    if (!length) return makeError(std::string("packet at ").append(at(base + offset)).append(": ").append(length.message()));
    KlvTriplet t;
    t.keyOffset = offset;
    t.valueOffset = offset + 16 + length->bytes;
    const std::size_t left = bytes.size() - t.valueOffset;
    if (length->value > maxLength)
        return makeError(std::string("packet at ").append(at(base + offset)).append(": length ").append(std::to_string(length->value))
                             .append(" is over the ").append(std::to_string(maxLength)).append(" bytes a packet may have"));
    if (length->value > left)
        return makeError(std::string("packet at ").append(at(base + offset)).append(": length ").append(std::to_string(length->value))
                             .append(" runs past the end of the data (").append(std::to_string(left)).append(" bytes left): truncated"));
    t.length = std::size_t(length->value);
    return t;
}

std::string toHex(Bytes bytes) {
    static const char* const kDigits = "0123456789abcdef";
    std::string s;
    s.reserve(bytes.size() * 2);
    for (uint8_t b : bytes) {
        s.push_back(kDigits[b >> 4]);
        s.push_back(kDigits[b & 15]);
    }
    return s;
}

}  // namespace orbis::fmv
