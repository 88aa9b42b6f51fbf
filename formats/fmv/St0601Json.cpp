// `orbis info` on KLV: one packet as one line of JSON.
#include "formats/fmv/St0601.h"

#include "base/TimeFormat.h"
#include "formats/fmv/St0601Fields.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <limits>

namespace orbis::fmv {
namespace {

std::string hex16(uint16_t v) {
    char s[8];
    std::snprintf(s, sizeof s, "%04x", unsigned(v));
    return s;
}

}  // namespace

std::string st0601JsonLine(const St0601Packet& p, uint64_t offset) {
    using detail::Kind;
    nlohmann::ordered_json j;
    j["offset"] = offset;
    j["size"] = p.size;
    j["checksum"] = {{"verdict", toString(p.checksum)}, {"stored", hex16(p.storedChecksum)}, {"computed", hex16(p.computedChecksum)}};
    for (const detail::Field& f : detail::st0601Fields()) {
        switch (f.kind) {
        case Kind::Timestamp:
            if (p.precisionTimeUs) {
                j[f.name] = *p.precisionTimeUs;
                // An int64 of ns reaches 2262: later stamps are printed only as µs.
                if (*p.precisionTimeUs <= uint64_t(std::numeric_limits<int64_t>::max() / 1000))
                    j["precisionTime"] = formatIso8601(TimeNs(*p.precisionTimeUs) * 1000, 6);
            }
            break;
        case Kind::Text:
            if (p.*f.text) j[f.name] = *(p.*f.text);
            break;
        case Kind::Integer:
            if (p.uasLsVersion) j[f.name] = *p.uasLsVersion;
            break;
        default:
            if (const auto& v = f.numberIn(p)) j[f.name] = *v;
            else if (p.hasError(f.tag)) j[f.name] = nullptr;   // present, but an error value
        }
    }
    if (!p.errorTags.empty()) j["errorTags"] = p.errorTags;
    if (!p.warnings.empty()) j["warnings"] = p.warnings;
    if (!p.otherTags.empty()) {
        auto& other = j["otherTags"] = nlohmann::ordered_json::array();
        for (const RawTag& t : p.otherTags) other.push_back({{"tag", t.tag}, {"hex", toHex(t.bytes)}});
    }
    // Text fields come from the stream: bytes that are not UTF-8 are replaced, never thrown on.
    return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace orbis::fmv
