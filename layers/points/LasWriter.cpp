// LAS writing for tests, the synthetic generator and `orbis convert`: any version 1.0-1.4, point
// formats 0-10, an optional WKT VLR or GeoTIFF EPSG keys, extra bytes, and LAZ (layered chunks);
// counts and bounds written on close.
#include "layers/points/LasBytes.h"
#include "layers/points/LasReader.h"
#include "layers/points/LazChunks.h"

#include <cpl_error.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>

namespace orbis::points {
namespace {

constexpr uint16_t kRecordSize[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

template <typename T>
void put(uint8_t* r, size_t at, T v) {
    std::memcpy(r + at, &v, sizeof(T));
}

/// Into a buffer already large enough (headers are allocated at their full size).
template <typename T>
void put(std::vector<uint8_t>& b, size_t at, T v) {
    put<T>(b.data(), at, v);
}

void putString(std::vector<uint8_t>& b, size_t at, const std::string& s, size_t n) {
    std::memcpy(b.data() + at, s.data(), std::min(n, s.size()));
}

/// A VLR (LAS 1.4 R15 Table 13): 54-byte header then the payload. LAS 1.0 calls the first two
/// bytes the record signature, 0xAABB; later versions reserve them (0).
void vlr(std::vector<uint8_t>& out, uint8_t versionMinor, const std::string& user, uint16_t id,
         const std::vector<uint8_t>& payload, const std::string& description) {
    std::vector<uint8_t> h(54, 0);
    put<uint16_t>(h, 0, versionMinor == 0 ? 0xAABB : 0);
    putString(h, 2, user, 16);
    put<uint16_t>(h, 18, id);
    put<uint16_t>(h, 20, uint16_t(payload.size()));
    putString(h, 22, description, 32);
    out.insert(out.end(), h.begin(), h.end());
    out.insert(out.end(), payload.begin(), payload.end());
}

bool isGeographic(int epsg) {
    OGRSpatialReference srs;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool known = srs.importFromEPSG(epsg) == OGRERR_NONE;
    CPLPopErrorHandler();
    return known && srs.IsGeographic();
}

/// The GeoKeyDirectoryTag (GeoTIFF 1.1 §2.4): version 1.1.0 and the keys, sorted by id, all
/// inline shorts: GTModelTypeGeoKey (1024: 1 projected, 2 geographic), the CRS code
/// (3072 projected or 2048 geographic), then the optional unit and vertical keys.
std::vector<uint8_t> geoKeys(const LasWriteOptions& o) {
    const bool geographic = isGeographic(o.epsg);
    std::vector<std::array<uint16_t, 2>> keys{{1024, uint16_t(geographic ? 2 : 1)},
                                              {uint16_t(geographic ? 2048 : 3072), uint16_t(o.epsg)}};
    if (o.linearUnits && !geographic) keys.push_back({3076, o.linearUnits});
    if (o.verticalEpsg) keys.push_back({4096, uint16_t(o.verticalEpsg)});
    if (o.verticalUnits) keys.push_back({4099, o.verticalUnits});
    std::vector<uint16_t> words{1, 1, 0, uint16_t(keys.size())};
    for (const auto& k : keys) words.insert(words.end(), {k[0], 0, 1, k[1]});
    std::vector<uint8_t> payload(words.size() * 2);
    std::memcpy(payload.data(), words.data(), payload.size());
    return payload;
}

}  // namespace

void packLasRecord(const LasPoint& p, const int32_t q[3], uint8_t f, uint8_t* r) {
    put<int32_t>(r, 0, q[0]);
    put<int32_t>(r, 4, q[1]);
    put<int32_t>(r, 8, q[2]);
    put<uint16_t>(r, 12, p.intensity);
    size_t rgbAt;
    if (f >= 6) {
        r[14] = uint8_t((p.returnNumber & 15) | (p.numberOfReturns & 15) << 4);
        r[15] = uint8_t((p.flags & 15) | (p.scannerChannel & 3) << 4 | ((p.flags >> 4) & 3) << 6);
        r[16] = p.classification;
        r[17] = p.userData;
        put<int16_t>(r, 18, int16_t(std::clamp(std::lround(p.scanAngleDeg / 0.006f), -32768l, 32767l)));   // 0.006 deg steps
        put<uint16_t>(r, 20, p.pointSourceId);
        put<double>(r, 22, p.gpsTime);
        rgbAt = 30;
    } else {
        r[14] = uint8_t((p.returnNumber & 7) | (p.numberOfReturns & 7) << 3 | ((p.flags >> 4) & 3) << 6);
        r[15] = uint8_t((p.classification & 31) | (p.flags & 7) << 5);
        r[16] = uint8_t(int8_t(std::clamp(std::lround(p.scanAngleDeg), -128l, 127l)));   // whole degrees
        r[17] = p.userData;
        put<uint16_t>(r, 18, p.pointSourceId);
        if (f == 1 || f >= 3) put<double>(r, 20, p.gpsTime);
        rgbAt = f == 2 ? 20 : 28;
    }
    if (f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10) {
        put<uint16_t>(r, rgbAt, p.red);
        put<uint16_t>(r, rgbAt + 2, p.green);
        put<uint16_t>(r, rgbAt + 4, p.blue);
        if (f == 8 || f == 10) put<uint16_t>(r, rgbAt + 6, p.nir);
    }
}

struct LasWriter::Impl {
    std::FILE* file = nullptr;
    std::string path;
    LasWriteOptions o;
    uint16_t headerSize = 227, recordLength = 0;
    uint32_t pointOffset = 0;
    uint64_t count = 0;
    std::array<uint64_t, 15> byReturn{};
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
    std::vector<uint8_t> vlrs, buffer;
    uint32_t vlrCount = 0;
    bool failed = false;
    bool outOfRange = false;
    // LAZ: the records of the chunk being filled, the chunks written, where the data goes next.
    std::optional<laz::LaszipVlr> laz;
    std::vector<uint8_t> pending, encoded;
    std::vector<laz::Chunk> chunks;
    uint64_t written = 0;
    std::string lazError;

    /// Compresses the pending records as one chunk and writes it.
    void flushChunk() {
        const uint64_t n = pending.size() / recordLength;
        if (n == 0) return;
        encoded.clear();
        if (auto r = laz::encodeChunk(*laz, pending.data(), n, encoded); !r) {
            if (lazError.empty()) lazError = r.message();
            failed = true;
        }
        if (std::fwrite(encoded.data(), 1, encoded.size(), file) != encoded.size()) failed = true;
        chunks.push_back({written, encoded.size(), n, 0});
        written += encoded.size();
        pending.clear();
    }
};

LasWriter::~LasWriter() {
    if (impl_ && impl_->file) std::fclose(impl_->file);
}

Result<std::unique_ptr<LasWriter>> LasWriter::create(const std::string& path, const LasWriteOptions& options) {
    if (options.pointFormat > 10) return makeError(path + ": point format must be 0 to 10");
    if (options.versionMinor > 4) return makeError(path + ": LAS version must be 1.0 to 1.4");
    std::unique_ptr<LasWriter> w(new LasWriter());
    w->impl_ = std::make_unique<Impl>();
    Impl& m = *w->impl_;
    m.path = path;
    m.o = options;
    m.headerSize = options.versionMinor >= 4 ? 375 : options.versionMinor == 3 ? 235 : 227;
    m.recordLength = uint16_t(kRecordSize[options.pointFormat] + options.extraBytes);
    if (!options.wkt.empty()) {
        if (options.wkt.size() >= 65535) return makeError(path + ": the WKT is too long for a VLR (65 535 bytes at most)");
        std::vector<uint8_t> text(options.wkt.begin(), options.wkt.end());
        text.push_back(0);
        vlr(m.vlrs, options.versionMinor, "LASF_Projection", 2112, text, "OGC WKT");
    } else if (options.epsg > 0) {
        if (options.epsg > 65535 || options.verticalEpsg < 0 || options.verticalEpsg > 65535)
            return makeError(path + ": GeoTIFF keys hold EPSG codes up to 65535");
        vlr(m.vlrs, options.versionMinor, "LASF_Projection", 34735, geoKeys(options), "GeoTIFF GeoKeyDirectoryTag");
    }
    m.vlrCount = m.vlrs.empty() ? 0 : 1;
    if (options.laz) {
        if (options.pointFormat < 6 || options.pointFormat > 8)
            return makeError(path + ": Orbis writes LAZ for point formats 6, 7 and 8 (LAS 1.4, layered chunks)");
        if (options.versionMinor < 4) return makeError(path + ": LAZ of point formats 6-8 needs LAS 1.4");
        if (options.lazChunkPoints == 0) return makeError(path + ": a LAZ chunk must hold at least one point");
        laz::LaszipVlr z;
        z.compressor = 3;
        z.versionMajor = 3, z.versionMinor = 4, z.versionRevision = 3;   // the format LASzip 3.4 reads
        z.chunkSize = options.lazChunkPoints;
        z.items.push_back({laz::ItemType::Point14, 30, 3});
        if (options.pointFormat == 7) z.items.push_back({laz::ItemType::Rgb14, 6, 3});
        if (options.pointFormat == 8) z.items.push_back({laz::ItemType::RgbNir14, 8, 3});
        if (options.extraBytes > 0) z.items.push_back({laz::ItemType::Byte14, options.extraBytes, 3});
        std::vector<uint8_t> payload(34 + 6 * z.items.size(), 0);
        put<uint16_t>(payload, 0, z.compressor);
        payload[4] = z.versionMajor, payload[5] = z.versionMinor;
        put<uint16_t>(payload, 6, z.versionRevision);
        put<uint32_t>(payload, 12, z.chunkSize);
        put<int64_t>(payload, 16, -1);   // no special EVLRs
        put<int64_t>(payload, 24, -1);
        put<uint16_t>(payload, 32, uint16_t(z.items.size()));
        for (size_t i = 0; i < z.items.size(); ++i) {
            put<uint16_t>(payload, 34 + 6 * i, uint16_t(z.items[i].type));
            put<uint16_t>(payload, 36 + 6 * i, z.items[i].size);
            put<uint16_t>(payload, 38 + 6 * i, z.items[i].version);
        }
        vlr(m.vlrs, options.versionMinor, "laszip encoded", 22204, payload, "Orbis LAZ (LASzip format)");
        ++m.vlrCount;
        m.laz = std::move(z);
    }
    m.pointOffset = uint32_t(m.headerSize + m.vlrs.size());
    m.file = std::fopen(path.c_str(), "wb");
    if (!m.file) return makeError(path + ": cannot create the file");
    // Room for the header and VLRs, written by close() once the counts and bounds are known.
    std::vector<uint8_t> headerSpace(m.pointOffset + (m.laz ? 8 : 0), 0);   // LAZ: the chunk table's offset
    if (std::fwrite(headerSpace.data(), 1, headerSpace.size(), m.file) != headerSpace.size())
        return makeError(path + ": write failed");
    return w;
}

void LasWriter::write(std::span<const LasPoint> points) {
    Impl& m = *impl_;
    if (!m.file) {
        m.failed = true;   // written after close(): nothing to write to
        return;
    }
    if (points.empty()) return;   // (fwrite of an empty buffer would pass it a null pointer)
    const uint8_t f = m.o.pointFormat;
    m.buffer.assign(points.size() * m.recordLength, 0);
    for (size_t i = 0; i < points.size(); ++i) {
        const LasPoint& p = points[i];
        uint8_t* r = m.buffer.data() + i * m.recordLength;
        const glm::dvec3 q = glm::round((p.position - m.o.offset) / m.o.scale);
        if (!(glm::all(glm::lessThanEqual(glm::abs(q), glm::dvec3(2147483647.0)))))
            m.outOfRange = true;   // the scale and offset cannot hold the point: close() reports it
        const int32_t xyz[3] = {int32_t(q.x), int32_t(q.y), int32_t(q.z)};
        packLasRecord(p, xyz, f, r);
        for (size_t k = kRecordSize[f]; k < m.recordLength; ++k) r[k] = uint8_t(0xA5 ^ k);   // extra bytes
        const glm::dvec3 stored = q * m.o.scale + m.o.offset;
        m.lo = glm::min(m.lo, stored);
        m.hi = glm::max(m.hi, stored);
        if (p.returnNumber >= 1 && p.returnNumber <= 15) ++m.byReturn[size_t(p.returnNumber - 1)];
    }
    m.count += points.size();
    if (!m.laz) {
        if (std::fwrite(m.buffer.data(), 1, m.buffer.size(), m.file) != m.buffer.size()) m.failed = true;
        return;
    }
    const uint64_t chunkBytes = uint64_t(m.laz->chunkSize) * m.recordLength;
    for (size_t at = 0; at < m.buffer.size();) {
        const size_t take = size_t(std::min<uint64_t>(chunkBytes - m.pending.size(), m.buffer.size() - at));
        m.pending.insert(m.pending.end(), m.buffer.begin() + ptrdiff_t(at), m.buffer.begin() + ptrdiff_t(at + take));
        at += take;
        if (m.pending.size() == chunkBytes) m.flushChunk();
    }
}

Result<void> LasWriter::close() {
    Impl& m = *impl_;
    if (!m.file) return makeError(m.path + ": already closed");
    if (m.count == 0) m.lo = m.hi = glm::dvec3(0.0);
    uint64_t tableAt = 0;
    if (m.laz) {
        m.flushChunk();
        tableAt = m.pointOffset + 8 + m.written;
        std::vector<uint8_t> table;
        laz::encodeChunkTable(*m.laz, m.chunks, table);
        if (std::fwrite(table.data(), 1, table.size(), m.file) != table.size()) m.failed = true;
    }
    std::vector<uint8_t> h(m.headerSize, 0);
    putString(h, 0, "LASF", 4);
    const bool wkt = !m.o.wkt.empty();
    put<uint16_t>(h, 6, uint16_t(wkt && m.o.versionMinor >= 4 ? 16 : 0));
    h[24] = 1;
    h[25] = m.o.versionMinor;
    putString(h, 26, "Orbis", 32);
    putString(h, 58, "Orbis LasWriter", 32);
    put<uint16_t>(h, 90, 1);
    put<uint16_t>(h, 92, 2026);
    put<uint16_t>(h, 94, m.headerSize);
    put<uint32_t>(h, 96, m.pointOffset);
    put<uint32_t>(h, 100, m.vlrCount);
    h[104] = uint8_t(m.o.pointFormat | (m.laz ? 0x80 : 0));   // LASzip's mark of compressed points
    put<uint16_t>(h, 105, m.recordLength);
    const bool legacy = m.o.pointFormat < 6 && m.count <= 0xFFFFFFFFull;
    put<uint32_t>(h, 107, legacy ? uint32_t(m.count) : 0u);
    for (int i = 0; i < 5; ++i) put<uint32_t>(h, 111 + 4 * i, legacy ? uint32_t(m.byReturn[size_t(i)]) : 0u);
    for (int a = 0; a < 3; ++a) {
        put<double>(h, 131 + 8 * a, m.o.scale[a]);
        put<double>(h, 155 + 8 * a, m.o.offset[a]);
        put<double>(h, 179 + 16 * a, m.hi[a]);
        put<double>(h, 187 + 16 * a, m.lo[a]);
    }
    if (m.o.versionMinor >= 4) {
        put<uint64_t>(h, 235, 0);
        put<uint32_t>(h, 243, 0);
        put<uint64_t>(h, 247, m.count);
        for (int i = 0; i < 15; ++i) put<uint64_t>(h, 255 + 8 * i, m.byReturn[size_t(i)]);
    }
    h.insert(h.end(), m.vlrs.begin(), m.vlrs.end());
    if (m.laz) {
        h.resize(h.size() + 8);
        put<int64_t>(h, m.pointOffset, int64_t(tableAt));
    }
    const bool ok = std::fseek(m.file, 0, SEEK_SET) == 0 && std::fwrite(h.data(), 1, h.size(), m.file) == h.size() && !m.failed;
    const bool closed = std::fclose(m.file) == 0;
    m.file = nullptr;
    if (!m.lazError.empty()) return makeError(m.path + ": " + m.lazError);
    if (!ok || !closed) return makeError(m.path + ": write failed");
    if (m.count > 0xFFFFFFFFull && m.o.versionMinor < 4)
        return makeError(m.path + ": " + std::to_string(m.count) + " points need LAS 1.4 (64-bit counts)");
    if (m.outOfRange) return makeError(m.path + ": a coordinate does not fit in 32 bits with this scale and offset");
    return {};
}

}  // namespace orbis::points
