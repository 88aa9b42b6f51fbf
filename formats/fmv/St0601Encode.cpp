#include "formats/fmv/St0601Encode.h"

#include "formats/fmv/St0601Fields.h"

#include <cmath>

namespace orbis::fmv {
namespace {

using detail::Field;
using detail::Kind;

void appendItem(std::vector<uint8_t>& set, uint32_t tag, const std::vector<uint8_t>& value) {
    appendBerOid(set, tag);
    appendBerLength(set, value.size());
    set.insert(set.end(), value.begin(), value.end());
}

/// The value bytes of `f` in `p`, or false when the packet has nothing to write for it.
bool valueOf(const St0601Packet& p, const Field& f, const St0601EncodeOptions& o, std::vector<uint8_t>& v) {
    switch (f.kind) {
    case Kind::Timestamp:
        if (!p.precisionTimeUs) return false;
        appendBigEndian(v, *p.precisionTimeUs, 8);
        return true;
    case Kind::Integer: {
        if (!p.uasLsVersion && !o.writeVersion) return false;
        appendBigEndian(v, uint64_t(p.uasLsVersion.value_or(17)), 1);   // 17: ST 0601.17
        return true;
    }
    case Kind::Text: {
        const auto& s = p.*f.text;
        if (!s) return false;
        v.assign(s->begin(), s->end());
        return true;
    }
    default: {
        const std::optional<double>& x = f.numberIn(p);
        const bool number = x && !std::isnan(*x);
        // NaN, or no value for a tag the packet flags as an error: the error value, where the
        // mapping has one.
        const bool errorValue = f.hasErrorValue() && (x || p.hasError(f.tag));
        if (!number && !errorValue) return false;
        detail::encodeNumber(f, x, v, o.imapbBytes);
        return true;
    }
    }
}

}  // namespace

std::vector<uint8_t> encodeSt0601(const St0601Packet& packet, const St0601EncodeOptions& options) {
    std::vector<uint8_t> set, value;
    set.reserve(256);
    auto add = [&](const Field& f) {
        value.clear();
        if (valueOf(packet, f, options, value)) appendItem(set, f.tag, value);
    };
    add(*detail::findField(2));   // ST 0601: the precision time stamp comes first
    for (const Field& f : detail::st0601Fields())
        if (f.tag != 2) add(f);
    for (const RawTag& t : packet.otherTags) appendItem(set, t.tag, t.bytes);
    set.push_back(1);   // tag 1, checksum: 2 bytes, computed below
    set.push_back(2);

    std::vector<uint8_t> out(kSt0601Key.begin(), kSt0601Key.end());
    const std::size_t length = set.size() + 2;
    if (options.packetLengthBytes > 0) appendBerLengthLong(out, length, options.packetLengthBytes);
    else appendBerLength(out, length);
    out.insert(out.end(), set.begin(), set.end());
    appendBigEndian(out, st0601Checksum(out), 2);
    return out;
}

}  // namespace orbis::fmv
