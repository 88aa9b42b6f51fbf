#pragma once
// LAS 1.0–1.4 point clouds (point data formats 0–10), CPU only (no Vulkan).
//
// The header and VLRs are read when the file opens (mapped for that moment); the points are read
// with pread in ranges, so clouds larger than RAM stream through a bounded buffer, and a file cut
// short or replaced in place while it loads gives an error naming it, never a SIGBUS. The header
// is validated against the file's size before anything is read: counts, offsets and record
// lengths that disagree give a clear error naming the file, never a huge allocation.
//
// LAZ (LASzip-compressed) files read through the same API: the chunk table is read when the file
// opens, and a read decodes the chunks that hold the points asked for (several chunks on several
// threads), keeping the last one decoded for the next read. A chunk that is corrupt or cut short
// is an error naming the file and the chunk; with `setSkipDamagedChunks(true)` its points are
// left out instead (counted in `skippedPoints()`) and the other chunks still load.
//
// The coordinate reference system comes, in this order, from the scene (an override), the OGC
// WKT VLR (LASF_Projection 2112), the GeoTIFF key VLRs (LASF_Projection 34735/34736/34737),
// or a sidecar next to the file (`cloud.las.wkt`, `cloud.wkt`, `cloud.prj`). LasGeoreference
// turns coordinates in that CRS into ECEF (WGS84, metres, double) through GDAL/OGR, with the
// CRS's units (feet, US survey feet) and datum shifts honoured.

#include "base/Result.h"
#include "layers/points/Copc.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orbis::points {

/// One variable-length record (VLR) or extended VLR, as listed by `orbis info`.
struct LasVlr {
    std::string userId;
    uint16_t recordId = 0;
    uint64_t length = 0;   ///< payload bytes
    std::string description;
    bool extended = false;   ///< an EVLR (after the points, LAS 1.4)
};

struct LasHeader {
    uint8_t versionMajor = 1, versionMinor = 2;
    uint8_t pointFormat = 0;      ///< 0..10
    uint16_t recordLength = 0;    ///< bytes per point record, extra bytes included
    uint16_t extraBytes = 0;      ///< recordLength minus the format's standard size
    uint64_t pointCount = 0;
    uint64_t pointOffset = 0;     ///< offset to the first point record
    uint16_t globalEncoding = 0;
    glm::dvec3 scale{1.0}, offset{0.0};
    glm::dvec3 min{0.0}, max{0.0};   ///< header bounds, CRS units
    std::array<uint64_t, 15> pointsByReturn{};
    std::string systemId, software;
    uint16_t creationDay = 0, creationYear = 0;
    std::vector<LasVlr> vlrs;
    /// "" for LAS; for LAZ what LASzip wrote, e.g. "LAZ (LASzip 3.4r3, layered chunked, 65 chunks)".
    std::string compression;

    bool hasGpsTime() const;   ///< formats 1, 3..10
    bool hasRgb() const;       ///< formats 2, 3, 5, 7, 8, 10
    bool hasNir() const;       ///< formats 8, 10
};

/// One decoded point: coordinates scaled and offset (CRS units), attributes as stored.
struct LasPoint {
    glm::dvec3 position{0.0};
    double gpsTime = 0.0;
    uint16_t intensity = 0;
    uint16_t red = 0, green = 0, blue = 0, nir = 0;   ///< 16-bit as LAS stores them
    uint16_t pointSourceId = 0;
    uint8_t returnNumber = 0, numberOfReturns = 0;   ///< 1..15 (formats 6..10), 1..7 before
    uint8_t classification = 0;   ///< ASPRS class (0..255 in formats 6..10, 0..31 before)
    /// bit 0 synthetic, 1 key-point, 2 withheld, 3 overlap (formats 6..10), 4 scan direction,
    /// 5 edge of flight line
    uint8_t flags = 0;
    uint8_t scannerChannel = 0;   ///< 0..3 (formats 6..10)
    uint8_t userData = 0;
    float scanAngleDeg = 0.0f;
};

/// Where a cloud's CRS came from, and the CRS as WKT (empty when the file names none).
struct LasCrs {
    std::string wkt;
    std::string source;   ///< "scene", "WKT VLR", "GeoTIFF keys (EPSG:2992)", "sidecar /path/x.wkt", "none"
};

class LasFile {
public:
    /// Opens and validates `path`: a file, or an http(s):// URL read with range requests (through
    /// GDAL's /vsicurl/: the header, VLRs and the tables at the file's end when it opens, then
    /// the points or nodes asked for). Errors name the file and the problem (not a LAS file,
    /// unknown point format, record length too short for the format, point count or offsets past
    /// the end of the file, a server that answers 404 or does not honour ranges, ...).
    static Result<std::unique_ptr<LasFile>> open(const std::string& path);
    ~LasFile();
    LasFile(const LasFile&) = delete;
    LasFile& operator=(const LasFile&) = delete;

    const std::string& path() const { return path_; }
    const LasHeader& header() const { return header_; }
    uint64_t size() const { return points(); }
    uint64_t points() const { return header_.pointCount; }
    /// The CRS found in the file or next to it (see the top of this file).
    const LasCrs& crs() const { return crs_; }

    /// Decodes points [first, first + count), clamped to the header's count, into `out`
    /// (replaced). Any thread. An error (naming the file, the points and its size now) when the
    /// file no longer holds them: cut short or rewritten while loaded.
    Result<void> read(uint64_t first, uint64_t count, std::vector<LasPoint>& out) const;
    /// Only the scaled positions of points [first, first + count) (the fast path for loading; in
    /// LAZ files of formats 6-10 the other fields' layers are not decoded).
    Result<void> readPositions(uint64_t first, uint64_t count, std::vector<glm::dvec3>& out) const;

    bool compressed() const { return laz_ != nullptr; }
    /// COPC: the info VLR when the file is a COPC file (its octree: copc::readHierarchy).
    const std::optional<copc::Info>& copc() const { return copc_; }
    /// The file's size when opened.
    uint64_t fileBytes() const { return bytes_; }
    /// Read from a server (an http(s):// URL), and the bytes asked of it so far.
    bool remote() const { return remote_ != nullptr; }
    uint64_t bytesFetched() const;
    /// A remote file: from now on, ranges read from the server are kept in a folder of `folder`
    /// named after the URL, the file's size and its date (a file changed on the server is a new
    /// folder), and read from there again: a COPC node once fetched is not fetched again, in this
    /// run or the next. Each range is one file, written under a temporary name with a CRC-32
    /// trailer; a damaged one counts as absent; a folder that cannot be written leaves reads as
    /// they are. When `folder` holds more than `maxBytes`, the least recently written ranges of
    /// every file are removed first. A local file: nothing.
    void cacheRemoteReads(const std::string& folder, uint64_t maxBytes = uint64_t(2) << 30) const;
    /// Bytes read from that cache instead of the server, so far.
    uint64_t bytesFromCache() const;
    /// `bytes` bytes at `offset` into `out` (hierarchy pages); an error when outside the file.
    Result<void> readBytes(uint64_t offset, uint64_t bytes, std::vector<uint8_t>& out) const;
    /// Decodes the LAZ chunk of `count` points at [offset, offset + bytes) (a COPC node's) into
    /// `out`; `fields` (laz::Fields) as for reads. Errors name the file and the chunk.
    Result<void> readChunk(uint64_t offset, uint64_t bytes, uint64_t count, std::vector<LasPoint>& out) const;
    /// LAZ: threads decoding the chunks of one read (default: the hardware's cores).
    void setDecodeThreads(unsigned threads);
    /// LAZ: leave out the points of damaged chunks (warned once each) instead of failing the read.
    void setSkipDamagedChunks(bool skip);
    /// Points left out so far by setSkipDamagedChunks, and the messages naming their chunks.
    uint64_t skippedPoints() const;
    std::vector<std::string> damagedChunks() const;

private:
    LasFile();   // out of line: Laz is complete only in LasReader.cpp
    struct Laz;
    struct Remote;
    /// Exactly `n` bytes at `offset` from the file or the server; false with the reason.
    bool readAt(uint8_t* out, uint64_t n, uint64_t offset, std::string& why) const;
    static Result<std::unique_ptr<LasFile>> openRemote(const std::string& url);
    /// Parses the header and VLRs from `d` (the whole file, or a view with its head and tail).
    static Result<void> parse(LasFile& f, const uint8_t* d);
    /// The raw records of points [first, first + count) into `raw`; `fields` (laz::Fields) says
    /// which a LAZ read must decode.
    Result<void> readRaw(uint64_t first, uint64_t count, std::vector<uint8_t>& raw, uint32_t fields) const;
    Result<void> readLaz(uint64_t first, uint64_t count, std::vector<uint8_t>& raw, uint32_t fields) const;
    Result<void> openLaz(const uint8_t* map, uint64_t evlrStart, const std::vector<uint64_t>& payloads);
    /// Raw records to points.
    void decodeRecords(const uint8_t* raw, uint64_t count, std::vector<LasPoint>& out) const;
    std::string path_;
    LasHeader header_;
    LasCrs crs_;
    uint64_t bytes_ = 0;   // the file's size when opened
    int fd_ = -1;
    std::unique_ptr<Laz> laz_;
    std::shared_ptr<Remote> remote_;
    std::optional<copc::Info> copc_;
};

/// A CRS to ECEF (WGS84, metres) through GDAL/OGR.
class LasGeoreference {
public:
    /// `crs`: WKT, "EPSG:n", or a PROJ string; `what` names where it came from, for messages.
    static Result<LasGeoreference> create(const std::string& crs, const std::string& what);
    LasGeoreference(LasGeoreference&&) noexcept;
    LasGeoreference& operator=(LasGeoreference&&) noexcept;
    ~LasGeoreference();

    /// In place: CRS coordinates to ECEF. A horizontal-only CRS in feet gets its heights in the
    /// same unit. Points the transformation cannot place become NaN; the count of those returns.
    /// Any thread: calls on one georeference are serialised (GDAL's transformations are not
    /// thread-safe).
    size_t toEcef(std::span<glm::dvec3> xyz) const;
    std::string name() const;           ///< the CRS's name
    double linearUnitMetres() const;    ///< horizontal unit (0.3048 for feet)
    double verticalUnitMetres() const;  ///< unit of the heights as read

private:
    LasGeoreference() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Writes LAS files (tests, the synthetic generator in tools/): any version 1.0–1.4 and point
/// format 0–10, with an optional WKT VLR or GeoTIFF EPSG keys, and extra bytes per record.
struct LasWriteOptions {
    uint8_t versionMinor = 2;
    uint8_t pointFormat = 3;
    uint16_t extraBytes = 0;
    glm::dvec3 scale{0.001}, offset{0.0};
    std::string wkt;     ///< written as the WKT VLR (and the WKT bit of the global encoding)
    int epsg = 0;        ///< written as GeoTIFF keys (ProjectedCSTypeGeoKey or GeographicTypeGeoKey)
    int verticalEpsg = 0;          ///< with `epsg`: VerticalCSTypeGeoKey (4096)
    uint16_t linearUnits = 0;      ///< with `epsg`: ProjLinearUnitsGeoKey (3076), an EPSG unit code (9002 ft, 9003 US ft)
    uint16_t verticalUnits = 0;    ///< with `epsg`: VerticalUnitsGeoKey (4099), an EPSG unit code
    /// LAZ: layered chunks (compressor 3, LASzip's format for LAS 1.4) of `lazChunkPoints` points;
    /// point formats 6, 7 and 8 (the ones with a version 3 coder Orbis writes).
    bool laz = false;
    uint32_t lazChunkPoints = 50000;
};
/// Streams points to a file: the header's counts and bounds (and a LAZ file's chunk table) are
/// written when closed.
class LasWriter {
public:
    static Result<std::unique_ptr<LasWriter>> create(const std::string& path, const LasWriteOptions& options);
    ~LasWriter();
    void write(std::span<const LasPoint> points);
    Result<void> close();

private:
    LasWriter() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace orbis::points
