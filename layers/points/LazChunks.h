#pragma once
// LAZ (LASzip) point data: the `laszip encoded` VLR, the chunk table, and the decoding of one
// chunk into raw LAS point records. CPU only; no file access here (LasFile reads the bytes).
//
// Layout (as LASzip writes it): the point data starts with an int64, the offset of the chunk
// table (or -1, then the offset is in the file's last 8 bytes); the chunks follow; the chunk table
// (version, count, then per chunk its byte size and, for variable chunks, its point count, both
// coded as differences by an IntegerCodec) closes the point data. Compressor 1 (point-wise, not
// chunked) has neither: one stream from the point data offset to the end.
//
// Point-wise chunks (compressor 1 and 2, item versions 1 and 2): the first point raw, then every
// item coded by one arithmetic stream, point after point. Layered chunks (compressor 3, item
// version 3, LAS 1.4 formats 6-10): the first point raw, the chunk's point count, the byte size
// of each layer of each item, then the layers: one arithmetic stream per field group, so fields a
// caller does not need are skipped without decoding.

#include "base/Result.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace orbis::points::laz {

enum class ItemType : uint16_t {
    Byte = 0,
    Point10 = 6,
    GpsTime11 = 7,
    Rgb12 = 8,
    WavePacket13 = 9,
    Point14 = 10,
    Rgb14 = 11,
    RgbNir14 = 12,
    WavePacket14 = 13,
    Byte14 = 14,
};

struct Item {
    ItemType type = ItemType::Byte;
    uint16_t size = 0;      ///< bytes of the record this item holds
    uint16_t version = 0;   ///< coder version (1, 2 or 3)
};

/// The `laszip encoded` VLR (user "laszip encoded", record 22204).
struct LaszipVlr {
    uint16_t compressor = 0;   ///< 0 none, 1 point-wise, 2 point-wise chunked, 3 layered chunked
    uint16_t coder = 0;        ///< 0 arithmetic
    uint8_t versionMajor = 0, versionMinor = 0;
    uint16_t versionRevision = 0;
    uint32_t options = 0;
    uint32_t chunkSize = 0;    ///< points per chunk; 0xFFFFFFFF: variable (from the chunk table)
    std::vector<Item> items;

    bool variableChunks() const { return chunkSize == 0xFFFFFFFFu; }
    uint32_t recordLength() const;   ///< the sum of the items' sizes
};

/// Parses the VLR's payload. Errors say what is wrong (the caller names the file).
Result<LaszipVlr> parseLaszipVlr(std::span<const uint8_t> payload);
/// Checks that the items describe records of `pointFormat` (0..10) with `recordLength` bytes and
/// that every item's type and version is one this decoder knows; the error names the item.
Result<void> checkItems(const LaszipVlr& vlr, uint8_t pointFormat, uint16_t recordLength);

/// What a caller needs from the records. Positions are always decoded; in layered chunks the
/// layers of the fields left out are skipped (their bytes in the output hold the chunk's first
/// point's values). Point-wise chunks decode everything whatever is asked.
enum Fields : uint32_t {
    kFieldPositions = 0,
    kFieldRgb = 1u << 0,
    kFieldNir = 1u << 1,
    kFieldAttributes = 1u << 2,   ///< intensity, returns, classification, flags, scan angle, user data, source, GPS time
    kFieldExtraBytes = 1u << 3,
    kFieldWaveform = 1u << 4,
    kFieldsAll = 0x1Fu,
};

/// One chunk: where its bytes are and how many points it holds.
struct Chunk {
    uint64_t offset = 0;   ///< in the file
    uint64_t bytes = 0;
    uint64_t points = 0;
    uint64_t firstPoint = 0;   ///< index of its first point in the file
};

/// Decodes the chunk table. `table` is the file's bytes from the table's offset (to the end of
/// the file or at most what the table can need); `firstChunk` the offset of the first chunk;
/// `totalPoints` the header's count; `pointDataEnd` the offset where chunks must end (the table).
/// Fixed-size chunks get their counts from `chunkSize`; every chunk is checked to lie inside
/// [firstChunk, pointDataEnd) and the counts to sum to `totalPoints`.
Result<std::vector<Chunk>> decodeChunkTable(const LaszipVlr& vlr, std::span<const uint8_t> table, uint64_t firstChunk,
                                            uint64_t pointDataEnd, uint64_t totalPoints);

/// Decodes `count` points of one chunk (its bytes in `data`) into `out` (count * recordLength
/// bytes, records of the VLR's items in order). Errors (the caller names the file and the chunk):
/// the data ends before the points do, a layered chunk's own count or layer sizes disagree with
/// its size, an unknown item.
Result<void> decodeChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint32_t fields, uint8_t* out);

/// Encodes `count` records (`recordLength` bytes each, items of `vlr` in order) as one chunk,
/// appended to `out`. What Orbis writes (COPC): layered chunks (compressor 3) of POINT14, RGB14,
/// RGBNIR14 and BYTE14; any other compressor is an error.
Result<void> encodeChunk(const LaszipVlr& vlr, const uint8_t* records, uint64_t count, std::vector<uint8_t>& out);
/// The chunk table as LASzip writes it (version 0, count, sizes and counts coded), appended.
void encodeChunkTable(const LaszipVlr& vlr, std::span<const Chunk> chunks, std::vector<uint8_t>& out);

namespace detail {
// The two chunk kinds (LazPointwise.cpp, LazLayered.cpp).
Result<void> decodePointwiseChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint8_t* out);
Result<void> decodeLayeredChunk(const LaszipVlr& vlr, std::span<const uint8_t> data, uint64_t count, uint32_t fields, uint8_t* out);
Result<void> encodeLayeredChunk(const LaszipVlr& vlr, const uint8_t* records, uint64_t count, std::vector<uint8_t>& out);
}  // namespace detail

}  // namespace orbis::points::laz
