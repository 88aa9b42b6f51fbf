#include "layers/points/LazChunks.h"
#include "layers/points/LasBytes.h"

#include "layers/points/LazCoder.h"

#include <cstring>

namespace orbis::points::laz {
namespace {

std::string num(uint64_t v) { return std::to_string(v); }

const char* itemName(ItemType t) {
    switch (t) {
    case ItemType::Byte: return "BYTE";
    case ItemType::Point10: return "POINT10";
    case ItemType::GpsTime11: return "GPSTIME11";
    case ItemType::Rgb12: return "RGB12";
    case ItemType::WavePacket13: return "WAVEPACKET13";
    case ItemType::Point14: return "POINT14";
    case ItemType::Rgb14: return "RGB14";
    case ItemType::RgbNir14: return "RGBNIR14";
    case ItemType::WavePacket14: return "WAVEPACKET14";
    case ItemType::Byte14: return "BYTE14";
    }
    return "unknown";
}

/// The fixed size of an item type (0: any, the extra bytes).
uint16_t itemSize(ItemType t) {
    switch (t) {
    case ItemType::Point10: return 20;
    case ItemType::GpsTime11: return 8;
    case ItemType::Rgb12: return 6;
    case ItemType::WavePacket13: return 29;
    case ItemType::Point14: return 30;
    case ItemType::Rgb14: return 6;
    case ItemType::RgbNir14: return 8;
    case ItemType::WavePacket14: return 29;
    default: return 0;
    }
}

/// The items a point format's standard part is made of, in record order.
std::vector<ItemType> formatItems(uint8_t format) {
    using enum ItemType;
    switch (format) {
    case 0: return {Point10};
    case 1: return {Point10, GpsTime11};
    case 2: return {Point10, Rgb12};
    case 3: return {Point10, GpsTime11, Rgb12};
    case 4: return {Point10, GpsTime11, WavePacket13};
    case 5: return {Point10, GpsTime11, Rgb12, WavePacket13};
    case 6: return {Point14};
    case 7: return {Point14, Rgb14};
    case 8: return {Point14, RgbNir14};
    case 9: return {Point14, WavePacket14};
    case 10: return {Point14, RgbNir14, WavePacket14};
    default: return {};
    }
}

}  // namespace

uint32_t LaszipVlr::recordLength() const {
    uint32_t n = 0;
    for (const Item& i : items) n += i.size;
    return n;
}

Result<LaszipVlr> parseLaszipVlr(std::span<const uint8_t> payload) {
    if (payload.size() < 34)
        return makeError(std::string("the laszip VLR is ").append(num(payload.size())).append(" bytes, shorter than its 34-byte header"));
    const uint8_t* d = payload.data();
    LaszipVlr v;
    v.compressor = bytes::get<uint16_t>(d);
    v.coder = bytes::get<uint16_t>(d + 2);
    v.versionMajor = d[4];
    v.versionMinor = d[5];
    v.versionRevision = bytes::get<uint16_t>(d + 6);
    v.options = bytes::get<uint32_t>(d + 8);
    v.chunkSize = bytes::get<uint32_t>(d + 12);
    const uint16_t n = bytes::get<uint16_t>(d + 32);
    if (payload.size() < 34 + 6 * size_t(n))
        return makeError(std::string("the laszip VLR lists ").append(num(n)).append(" items but holds ")
                             .append(num((payload.size() - 34) / 6)));
    for (uint16_t i = 0; i < n; ++i) {
        const uint8_t* e = d + 34 + 6 * size_t(i);
        v.items.push_back({ItemType(bytes::get<uint16_t>(e)), bytes::get<uint16_t>(e + 2), bytes::get<uint16_t>(e + 4)});
    }
    if (v.compressor < 1 || v.compressor > 3)
        return makeError(std::string("unknown LAZ compressor ").append(num(v.compressor)).append(" (1 point-wise, 2 point-wise chunked, 3 layered chunked)"));
    if (v.coder != 0) return makeError(std::string("unknown LAZ coder ").append(num(v.coder)).append(" (0 arithmetic)"));
    if (v.chunkSize == 0 && v.compressor != 1) return makeError("the laszip VLR's chunk size is 0");
    return v;
}

Result<void> checkItems(const LaszipVlr& vlr, uint8_t pointFormat, uint16_t recordLength) {
    const std::vector<ItemType> standard = formatItems(pointFormat);
    if (standard.empty()) return makeError(std::string("point format ").append(num(pointFormat)).append(" cannot be LAZ-compressed"));
    const bool modern = pointFormat >= 6;
    for (size_t i = 0; i < vlr.items.size(); ++i) {
        const Item& item = vlr.items[i];
        const std::string what = std::string("LAZ item ").append(num(i)).append(" (").append(itemName(item.type)).append(" version ")
                                     .append(num(item.version)).append(")");
        const bool extra = item.type == (modern ? ItemType::Byte14 : ItemType::Byte);
        if (i < standard.size() ? item.type != standard[i] : !extra)
            return makeError(std::string(what).append(" does not belong to point format ").append(num(pointFormat)));
        if (const uint16_t size = itemSize(item.type); size != 0 && item.size != size)
            return makeError(std::string(what).append(" is ").append(num(item.size)).append(" bytes, not ").append(num(size)));
        if (extra && item.size == 0) return makeError(std::string(what).append(" holds no bytes"));
        const bool versionOk = modern ? item.version == 3 : (item.version == 1 || item.version == 2);
        if (!versionOk)
            return makeError(std::string(what).append(modern ? ": only version 3 is supported for formats 6-10"
                                                             : ": only versions 1 and 2 are supported for formats 0-5"));
    }
    if (vlr.items.size() < standard.size())
        return makeError(std::string("the LAZ items lack ").append(itemName(standard[vlr.items.size()])).append(" for point format ").append(num(pointFormat)));
    if (vlr.recordLength() != recordLength)
        return makeError(std::string("the LAZ items make ").append(num(vlr.recordLength())).append("-byte records, the header says ").append(num(recordLength)));
    if (modern != (vlr.compressor == 3))
        return makeError(std::string("LAZ compressor ").append(num(vlr.compressor)).append(modern ? " cannot hold point formats 6-10 (layered, 3, expected)"
                                                                                              : " cannot hold point formats 0-5 (1 or 2 expected)"));
    return {};
}

Result<std::vector<Chunk>> decodeChunkTable(const LaszipVlr& vlr, std::span<const uint8_t> table, uint64_t firstChunk,
                                            uint64_t pointDataEnd, uint64_t totalPoints) {
    if (table.size() < 8) return makeError("the chunk table is cut short (fewer than 8 bytes)");
    const uint32_t version = bytes::get<uint32_t>(table.data());
    const uint32_t n = bytes::get<uint32_t>(table.data() + 4);
    if (version != 0) return makeError(std::string("unknown chunk table version ").append(num(version)));
    if (pointDataEnd < firstChunk) return makeError("the chunk table lies before the first chunk");
    // Every chunk holds at least one point and one byte: a count above either is corrupt (and
    // would make a huge allocation).
    if (n > totalPoints || n > pointDataEnd - firstChunk)
        return makeError(std::string("the chunk table lists ").append(num(n)).append(" chunks for ").append(num(totalPoints))
                             .append(" points in ").append(num(pointDataEnd - firstChunk)).append(" bytes"));
    std::vector<Chunk> chunks(n);
    if (n > 0) {
        ArithmeticDecoder dec;
        dec.init(table.data() + 8, table.size() - 8);
        IntegerCodec ic(32, 2);
        int32_t lastCount = 0, lastBytes = 0;
        for (uint32_t i = 0; i < n; ++i) {
            if (vlr.variableChunks()) chunks[i].points = uint32_t(lastCount = ic.decompress(dec, lastCount, 0));
            chunks[i].bytes = uint32_t(lastBytes = ic.decompress(dec, lastBytes, 1));
        }
        if (dec.overrun() > 4) return makeError("the chunk table is cut short");
    }
    uint64_t at = firstChunk, first = 0;
    for (uint32_t i = 0; i < n; ++i) {
        Chunk& c = chunks[i];
        if (!vlr.variableChunks()) c.points = std::min<uint64_t>(vlr.chunkSize, totalPoints - std::min(totalPoints, first));
        c.offset = at;
        c.firstPoint = first;
        if (c.bytes > pointDataEnd - at)
            return makeError(std::string("chunk ").append(num(i)).append(" (").append(num(c.bytes)).append(" bytes at ").append(num(at))
                                 .append(") runs past the point data's end at byte ").append(num(pointDataEnd)));
        if (c.points == 0 || c.points > totalPoints - first)
            return makeError(std::string("chunk ").append(num(i)).append(" claims ").append(num(c.points)).append(" points, but ")
                                 .append(num(totalPoints - first)).append(" of the header's ").append(num(totalPoints)).append(" are left"));
        at += c.bytes;
        first += c.points;
    }
    if (first != totalPoints)
        return makeError(std::string("the chunks hold ").append(num(first)).append(" points, the header says ").append(num(totalPoints)));
    return chunks;
}

Result<void> decodeChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint32_t fields, uint8_t* out) {
    if (count == 0) return {};
    if (vlr.compressor == 3) return detail::decodeLayeredChunk(vlr, data, count, fields, out);
    return detail::decodePointwiseChunk(vlr, data, count, out);
}

Result<void> encodeChunk(const LaszipVlr& vlr, const uint8_t* records, uint64_t count, std::vector<uint8_t>& out) {
    if (vlr.compressor != 3) return makeError(std::string("Orbis writes layered LAZ chunks (compressor 3), not compressor ").append(num(vlr.compressor)));
    return detail::encodeLayeredChunk(vlr, records, count, out);
}

void encodeChunkTable(const LaszipVlr& vlr, std::span<const Chunk> chunks, std::vector<uint8_t>& out) {
    const uint32_t header[2] = {0, uint32_t(chunks.size())};
    const auto* h = reinterpret_cast<const uint8_t*>(header);
    out.insert(out.end(), h, h + 8);
    ArithmeticEncoder enc(out);
    IntegerCodec ic(32, 2);
    int32_t lastCount = 0, lastBytes = 0;
    for (const Chunk& c : chunks) {
        if (vlr.variableChunks()) {
            ic.compress(enc, lastCount, int32_t(c.points), 0);
            lastCount = int32_t(c.points);
        }
        ic.compress(enc, lastBytes, int32_t(c.bytes), 1);
        lastBytes = int32_t(c.bytes);
    }
    enc.done();
}

}  // namespace orbis::points::laz
