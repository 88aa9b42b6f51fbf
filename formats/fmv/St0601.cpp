#include "formats/fmv/St0601.h"

#include "formats/fmv/St0601Fields.h"

#include <algorithm>
#include <bitset>

namespace orbis::fmv {
namespace {

using detail::Field;
using detail::Kind;

constexpr uint32_t kChecksumTag = 1;   // ST 0601 tag 1: uint16 checksum, the set's last item

std::string tagText(uint32_t tag) { return std::string("tag ").append(std::to_string(tag)); }

/// ISO 646 text as stored, less the NUL padding some encoders add.
std::string textOf(Bytes value) {
    std::size_t n = value.size();
    while (n > 0 && value[n - 1] == 0) --n;
    return std::string(reinterpret_cast<const char*>(value.data()), n);
}

void keepRaw(St0601Packet& p, const LocalSetItem& item) { p.otherTags.push_back({item.tag, {item.value.begin(), item.value.end()}}); }

void flagError(St0601Packet& p, uint32_t tag) {
    if (std::find(p.errorTags.begin(), p.errorTags.end(), tag) == p.errorTags.end()) p.errorTags.push_back(tag);
}

/// A value whose size is not the one ST 0601 gives the tag: kept raw, flagged, warned about.
bool sizeIsRight(St0601Packet& p, const Field& f, const LocalSetItem& item) {
    const std::size_t n = item.value.size();
    const bool ok = f.kind == Kind::Imapb ? (n >= 1 && n <= std::size_t(f.bytes)) : n == std::size_t(f.bytes);
    if (ok) return true;
    p.warnings.push_back(tagText(item.tag).append(" (").append(f.name).append(") at byte ").append(std::to_string(item.offset))
                             .append(": ").append(std::to_string(n)).append(" bytes, ST 0601 gives it ")
                             .append(f.kind == Kind::Imapb ? std::string("1..").append(std::to_string(f.bytes)) : std::to_string(f.bytes))
                             .append("; value ignored"));
    flagError(p, item.tag);
    keepRaw(p, item);
    return false;
}

void decodeItem(St0601Packet& p, const Field& f, const LocalSetItem& item) {
    if (f.kind == Kind::Text) {
        p.*f.text = textOf(item.value);
        return;
    }
    if (!sizeIsRight(p, f, item)) return;
    switch (f.kind) {
    case Kind::Timestamp: p.precisionTimeUs = bigEndian(item.value); return;
    case Kind::Integer: p.uasLsVersion = int(bigEndian(item.value)); return;
    default: {
        const detail::Mapped m = detail::decodeNumber(f, item.value);
        f.numberIn(p) = m.value;
        if (m.error) flagError(p, item.tag);
    }
    }
}

/// Tag 1: checks it against the running sum of the packet up to its own length byte.
void verifyChecksum(St0601Packet& p, Bytes packet, const LocalSetItem& item, std::size_t base, bool last) {
    const std::size_t upTo = item.offset - base + item.headerBytes;   // key .. checksum length byte
    p.computedChecksum = st0601Checksum(packet.first(upTo));
    if (!last) p.warnings.push_back(std::string("checksum (tag 1) at byte ").append(std::to_string(item.offset)).append(" is not the last item"));
    if (item.value.size() != 2) {
        p.warnings.push_back(std::string("checksum (tag 1) at byte ").append(std::to_string(item.offset)).append(": ")
                                 .append(std::to_string(item.value.size())).append(" bytes, ST 0601 gives it 2"));
        flagError(p, kChecksumTag);
        p.checksum = ChecksumVerdict::Mismatch;
        return;
    }
    p.storedChecksum = uint16_t(bigEndian(item.value));
    p.checksum = p.storedChecksum == p.computedChecksum ? ChecksumVerdict::Valid : ChecksumVerdict::Mismatch;
}

}  // namespace

const char* toString(ChecksumVerdict verdict) {
    switch (verdict) {
    case ChecksumVerdict::Valid: return "valid";
    case ChecksumVerdict::Mismatch: return "mismatch";
    case ChecksumVerdict::Missing: return "missing";
    }
    return "?";
}

std::optional<LatLonDeg> St0601Packet::corner(int i) const {
    if (i < 0 || i > 3) return std::nullopt;
    const auto k = std::size_t(i);
    if (cornerLatitudeDeg[k] && cornerLongitudeDeg[k]) return LatLonDeg{*cornerLatitudeDeg[k], *cornerLongitudeDeg[k]};
    if (frameCenterLatitudeDeg && frameCenterLongitudeDeg && offsetCornerLatitudeDeg[k] && offsetCornerLongitudeDeg[k]) {
        double lon = *frameCenterLongitudeDeg + *offsetCornerLongitudeDeg[k];
        if (lon > 180.0) lon -= 360.0;   // a footprint across the antimeridian
        if (lon < -180.0) lon += 360.0;
        return LatLonDeg{*frameCenterLatitudeDeg + *offsetCornerLatitudeDeg[k], lon};
    }
    return std::nullopt;
}

bool St0601Packet::hasError(uint32_t tag) const { return std::find(errorTags.begin(), errorTags.end(), tag) != errorTags.end(); }

uint16_t st0601Checksum(Bytes bytes) {
    // ST 0601 tag 1: bcc += byte << (8 * ((i + 1) % 2)), i.e. big-endian 16-bit words.
    uint32_t sum = 0;
    const std::size_t n = bytes.size();
    std::size_t i = 0;
    for (; i + 1 < n; i += 2) sum += (uint32_t(bytes[i]) << 8) | bytes[i + 1];
    if (i < n) sum += uint32_t(bytes[i]) << 8;
    return uint16_t(sum);
}

Result<St0601Packet> decodeSt0601(Bytes bytes, std::size_t base) {
    if (bytes.size() < kSt0601Key.size() || !sameKey(bytes.data(), kSt0601Key))
        return makeError(std::string("byte ").append(std::to_string(base)).append(": not an ST 0601 packet (no UAS Datalink Local Set key)"));
    auto triplet = readTriplet(bytes, 0, kMaxSt0601PacketBytes, base);
    if (!triplet) return triplet.error();
    const Bytes packet = bytes.first(triplet->end());
    auto items = splitLocalSet(packet.subspan(triplet->valueOffset), base + triplet->valueOffset);
    if (!items) return items.error();

    St0601Packet p;
    p.size = packet.size();
    std::bitset<256> seen;
    bool seenChecksum = false;
    for (std::size_t i = 0; i < items->size(); ++i) {
        const LocalSetItem& item = (*items)[i];
        const bool small = item.tag < seen.size();
        if (small && seen[item.tag]) {
            p.warnings.push_back(tagText(item.tag).append(" at byte ").append(std::to_string(item.offset))
                                     .append(" appears again; the first value is kept"));
            continue;
        }
        if (small) seen[item.tag] = true;
        if (item.tag == kChecksumTag) {
            seenChecksum = true;
            verifyChecksum(p, packet, item, base, i + 1 == items->size());
            continue;
        }
        if (const Field* f = detail::findField(item.tag)) decodeItem(p, *f, item);
        else keepRaw(p, item);
    }
    if (!seenChecksum) {
        p.computedChecksum = 0;
        p.warnings.push_back("no checksum (tag 1): ST 0601 requires one as the last item");
    }
    if (!p.precisionTimeUs && !p.hasError(2)) p.warnings.push_back("no precision time stamp (tag 2): ST 0601 requires one");
    return p;
}

const char* st0601TagName(uint32_t tag) {
    if (tag == kChecksumTag) return "checksum";
    const Field* f = detail::findField(tag);
    return f ? f->name : "";
}

}  // namespace orbis::fmv
