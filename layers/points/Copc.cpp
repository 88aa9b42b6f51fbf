#include "layers/points/Copc.h"
#include "layers/points/LasBytes.h"

#include "layers/points/LasReader.h"

#include <cmath>
#include <cstring>
#include <set>
#include <string>

namespace orbis::points::copc {
namespace {

std::string num(uint64_t v) { return std::to_string(v); }

/// The deepest level a key may have: 2^d cells per axis must fit an int32.
constexpr int32_t kMaxLevel = 30;

}  // namespace

Result<Info> parseInfo(std::span<const uint8_t> payload) {
    if (payload.size() < 160) return makeError(std::string("the copc info VLR is ").append(num(payload.size())).append(" bytes, not 160"));
    const uint8_t* d = payload.data();
    Info i;
    i.centre = {bytes::get<double>(d), bytes::get<double>(d + 8), bytes::get<double>(d + 16)};
    i.halfSize = bytes::get<double>(d + 24);
    i.spacing = bytes::get<double>(d + 32);
    i.rootPageOffset = bytes::get<uint64_t>(d + 40);
    i.rootPageBytes = bytes::get<uint64_t>(d + 48);
    i.gpsTimeMin = bytes::get<double>(d + 56);
    i.gpsTimeMax = bytes::get<double>(d + 64);
    if (!std::isfinite(i.centre.x) || !std::isfinite(i.centre.y) || !std::isfinite(i.centre.z) || !(i.halfSize > 0.0) ||
        !std::isfinite(i.halfSize))
        return makeError("the copc info VLR's root cube is not finite or has no size");
    return i;
}

Result<std::vector<Node>> readHierarchy(const LasFile& file, const Info& info) {
    const uint64_t size = file.fileBytes(), pointsStart = file.header().pointOffset;
    // Each entry takes 32 bytes of a page: more entries than the file could hold is corrupt.
    const uint64_t maxEntries = size / 32;
    std::vector<Node> nodes;
    std::set<uint64_t> seen;   // pages read (by offset)
    std::set<std::tuple<int32_t, int32_t, int32_t, int32_t>> keys;
    std::vector<std::pair<uint64_t, uint64_t>> pages{{info.rootPageOffset, info.rootPageBytes}};
    uint64_t entries = 0, points = 0;
    std::vector<uint8_t> page;
    while (!pages.empty()) {
        const auto [offset, bytes] = pages.back();
        pages.pop_back();
        const std::string which = std::string("COPC hierarchy page at byte ").append(num(offset)).append(" (").append(num(bytes)).append(" bytes)");
        if (offset > size || bytes > size - offset || bytes % 32 != 0)
            return makeError(std::string(which).append(bytes % 32 != 0 ? " is not a whole number of 32-byte entries" : " lies outside the file (")
                                 .append(bytes % 32 != 0 ? "" : num(size).append(" bytes)")));
        if (!seen.insert(offset).second) return makeError(std::string(which).append(" is referred to twice (a loop in the hierarchy)"));
        if (auto r = file.readBytes(offset, bytes, page); !r) return r.error();
        for (uint64_t e = 0; e < bytes / 32; ++e) {
            const uint8_t* p = page.data() + 32 * e;
            const Key k{bytes::get<int32_t>(p), bytes::get<int32_t>(p + 4), bytes::get<int32_t>(p + 8), bytes::get<int32_t>(p + 12)};
            const uint64_t at = bytes::get<uint64_t>(p + 16);
            const int32_t byteSize = bytes::get<int32_t>(p + 24), count = bytes::get<int32_t>(p + 28);
            const std::string entry = std::string(which).append(", entry ").append(num(e)).append(" (node ").append(std::to_string(k.d)).append("-")
                                          .append(std::to_string(k.x)).append("-").append(std::to_string(k.y)).append("-").append(std::to_string(k.z)).append(")");
            if (++entries > maxEntries) return makeError(std::string(entry).append(": more entries than the file can hold"));
            if (k.d < 0 || k.d > kMaxLevel || k.x < 0 || k.y < 0 || k.z < 0 || k.x >= (1 << k.d) || k.y >= (1 << k.d) || k.z >= (1 << k.d))
                return makeError(std::string(entry).append(": the key lies outside its level"));
            if (count == -1) {   // another page
                if (byteSize < 0) return makeError(std::string(entry).append(": a page of negative size"));
                pages.emplace_back(at, uint64_t(byteSize));
                continue;
            }
            if (count < -1 || byteSize < 0) return makeError(std::string(entry).append(": a negative point count or size"));
            if (!keys.insert({k.d, k.x, k.y, k.z}).second) return makeError(std::string(entry).append(": the node is listed twice"));
            if (count == 0) continue;
            if (at < pointsStart || at > size || uint64_t(byteSize) > size - at || byteSize == 0)
                return makeError(std::string(entry).append(": its chunk (").append(num(uint64_t(byteSize))).append(" bytes at ").append(num(at))
                                     .append(") lies outside the point data"));
            nodes.push_back({k, at, uint32_t(byteSize), uint32_t(count)});
            points += uint64_t(count);
        }
    }
    if (points != file.header().pointCount)
        return makeError(std::string("the COPC hierarchy's nodes hold ").append(num(points)).append(" points, the header says ")
                             .append(num(file.header().pointCount)));
    return nodes;
}

}  // namespace orbis::points::copc
