#pragma once
// Inside the point store: the cache file's header and the node data's encoding (see
// PointStore.h for the layout; shaders/points/PointData.glsl decodes it).

#include "layers/points/PointStore.h"

#include <cstring>
#include <string>
#include <span>
#include <vector>

namespace orbis::points::store {

inline constexpr char kMagic[8] = {'O', 'R', 'B', 'I', 'S', 'P', 'T', 'S'};
inline constexpr uint32_t kVersion = 2;   // 2: checksums (the header's tableCrc, each node's crc)
inline constexpr uint64_t kMaxKeyBytes = 1u << 16;
inline constexpr uint32_t kQuantisedBits = 21;
inline constexpr uint32_t kQuantisedCentre = 1u << 20;   // q = round(offset / step) + this

struct FileHeader {
    char magic[8];
    uint32_t version;
    uint32_t headerBytes;   // sizeof(FileHeader)
    uint64_t keyBytes;      // the key text follows the header
    uint64_t dataOffset;    // = headerBytes + keyBytes
    uint64_t dataBytes;
    uint64_t nodeTableOffset;   // = dataOffset + dataBytes; nodeCount StoredNodes to the end
    uint64_t nodeCount;
    CloudInfo info;
    uint32_t tableCrc;   // CRC-32 of this header (with tableCrc 0), the key and the node table
    uint32_t reserved0;
    uint8_t reserved[256 - 64 - sizeof(CloudInfo)];
};
static_assert(sizeof(FileHeader) == 256);

/// The step a node's positions get quantised to: its edge over 2^21 - 2 (so that offsets of
/// +-halfSize land on 1 .. 2^21 - 1).
inline double quantisationStep(double halfSize) { return 2.0 * halfSize / double((1u << kQuantisedBits) - 2); }

inline void packPosition(glm::uvec3 q, uint32_t& w0, uint32_t& w1) {
    w0 = q.x | (q.y << 21);
    w1 = (q.y >> 11) | (q.z << 10);
}
inline glm::uvec3 unpackPosition(uint32_t w0, uint32_t w1) {
    return {w0 & 0x1FFFFFu, (w0 >> 21) | ((w1 & 0x3FFu) << 11), w1 >> 10};
}

/// CRC-32 (zlib's) of `bytes` bytes, continuing from `crc` (0 to start).
uint32_t checksum(const void* data, uint64_t bytes, uint32_t crc = 0);

/// The header's tableCrc for `header` (its tableCrc ignored), `key` and the node table.
uint32_t tableChecksum(const FileHeader& header, const std::string& key, std::span<const StoredNode> nodes);

/// pread until `bytes` are read; false on an error or the end of the file.
bool preadAll(int fd, void* out, uint64_t bytes, uint64_t offset);

/// How a cloud's attributes are packed: heights over [heightMin, heightMax] to 16 bits.
struct Packing {
    double heightMin = 0.0, heightSpan = 1.0;
    double tolerance = 0.001;   // a node is quantised when its step is at most this (m)
    bool morton = true;         // points in Z order of their grid cells (else as given)
};

/// Appends the data of a node with the given cube, holding points[indices[k]], to `out`, and
/// returns the node's step (0: floats).
/// The Z-order (Morton) code of a 21-bit grid cell: x, y, z bits interleaved, x lowest.
uint64_t mortonCode(glm::uvec3 q);
double encodeNode(std::span<const PointRecord> points, std::span<const uint32_t> indices, const Cube& cube,
                  const Packing& packing, std::vector<uint8_t>& out);

}  // namespace orbis::points::store
