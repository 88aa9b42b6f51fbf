#include "layers/points/LasReader.h"

#include <ogr_spatialref.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace orbis::points {
namespace {

// Standard record sizes of point data formats 0..10 (LAS 1.4 R15).
constexpr uint16_t kRecordSize[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

template <typename T>
T get(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

std::string fixedString(const uint8_t* p, size_t n) {
    size_t len = 0;
    while (len < n && p[len] != 0) ++len;
    std::string s(reinterpret_cast<const char*>(p), len);
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

Error fail(const std::string& path, const std::string& what) { return makeError(std::string(path).append(": ").append(what)); }

std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// GeoTIFF keys (34735: u16 directory; 34736 doubles; 34737 ASCII) to a CRS, for the keys that
/// name EPSG codes; user-defined projections are reported, not guessed.
LasCrs crsFromGeoKeys(const uint8_t* keys, uint64_t length) {
    LasCrs crs;
    if (length < 8) {
        crs.source = "GeoTIFF keys (empty directory)";
        return crs;
    }
    const uint16_t count = get<uint16_t>(keys + 6);
    int projected = 0, geographic = 0, vertical = 0;
    for (uint16_t k = 0; k < count && 8u + 8u * (k + 1u) <= length; ++k) {
        const uint8_t* e = keys + 8 + 8 * k;
        const uint16_t id = get<uint16_t>(e), location = get<uint16_t>(e + 2), value = get<uint16_t>(e + 6);
        if (location != 0) continue;   // values stored elsewhere: not a code
        if (id == 3072) projected = value;
        else if (id == 2048) geographic = value;
        else if (id == 4096) vertical = value;
    }
    const int code = projected ? projected : geographic;
    if (code == 0 || code == 32767) {
        crs.source = "GeoTIFF keys (user-defined projection: give a sidecar .wkt or the scene's \"crs\")";
        return crs;
    }
    OGRSpatialReference horizontal;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = horizontal.importFromEPSG(code) == OGRERR_NONE;
    std::string source = "GeoTIFF keys (EPSG:" + std::to_string(code);
    if (ok && vertical > 0 && vertical != 32767) {
        OGRSpatialReference v;
        if (v.importFromEPSG(vertical) == OGRERR_NONE) {
            OGRSpatialReference compound;
            if (compound.SetCompoundCS("", &horizontal, &v) == OGRERR_NONE) {
                horizontal = compound;
                source += " + EPSG:" + std::to_string(vertical);
            }
        }
    }
    CPLPopErrorHandler();
    crs.source = source + ")";
    if (!ok) {
        crs.source = "GeoTIFF keys (EPSG:" + std::to_string(code) + " is unknown to PROJ)";
        return crs;
    }
    char* wkt = nullptr;
    const char* options[] = {"FORMAT=WKT2_2019", nullptr};
    if (horizontal.exportToWkt(&wkt, options) == OGRERR_NONE && wkt) crs.wkt = wkt;
    CPLFree(wkt);
    return crs;
}

}  // namespace

bool LasHeader::hasGpsTime() const { return pointFormat == 1 || pointFormat >= 3; }
bool LasHeader::hasRgb() const { return pointFormat == 2 || pointFormat == 3 || pointFormat == 5 || pointFormat == 7 || pointFormat == 8 || pointFormat == 10; }
bool LasHeader::hasNir() const { return pointFormat == 8 || pointFormat == 10; }

LasFile::~LasFile() {
    if (data_) munmap(const_cast<uint8_t*>(data_), bytes_);
    if (fd_ >= 0) close(fd_);
}

Result<std::unique_ptr<LasFile>> LasFile::open(const std::string& path) {
    std::unique_ptr<LasFile> f(new LasFile());
    f->path_ = path;
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".laz" || ext == ".LAZ") return fail(path, "LAZ (LASzip-compressed) files are not supported yet");
    f->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (f->fd_ < 0) return fail(path, std::string("cannot open: ").append(std::strerror(errno)));
    struct stat st {};
    if (fstat(f->fd_, &st) != 0 || !S_ISREG(st.st_mode)) return fail(path, "not a regular file");
    f->bytes_ = uint64_t(st.st_size);
    if (f->bytes_ < 227) return fail(path, "not a LAS file (shorter than a LAS header, " + std::to_string(f->bytes_) + " bytes)");
    void* map = mmap(nullptr, f->bytes_, PROT_READ, MAP_PRIVATE, f->fd_, 0);
    if (map == MAP_FAILED) return fail(path, std::string("cannot map: ").append(std::strerror(errno)));
    f->data_ = static_cast<const uint8_t*>(map);
    const uint8_t* d = f->data_;
    if (std::memcmp(d, "LASF", 4) != 0) return fail(path, "not a LAS file (no \"LASF\" signature)");

    LasHeader& h = f->header_;
    h.globalEncoding = get<uint16_t>(d + 6);
    h.versionMajor = d[24];
    h.versionMinor = d[25];
    if (h.versionMajor != 1 || h.versionMinor > 4)
        return fail(path, "LAS version " + std::to_string(h.versionMajor) + "." + std::to_string(h.versionMinor) +
                              " is not supported (1.0 to 1.4)");
    h.systemId = fixedString(d + 26, 32);
    h.software = fixedString(d + 58, 32);
    h.creationDay = get<uint16_t>(d + 90);
    h.creationYear = get<uint16_t>(d + 92);
    const uint16_t headerSize = get<uint16_t>(d + 94);
    const uint16_t minHeader = h.versionMinor >= 4 ? 375 : h.versionMinor == 3 ? 235 : 227;
    if (headerSize < minHeader || headerSize > f->bytes_)
        return fail(path, "header size " + std::to_string(headerSize) + " is wrong for LAS 1." +
                              std::to_string(h.versionMinor) + " (at least " + std::to_string(minHeader) + ")");
    h.pointOffset = get<uint32_t>(d + 96);
    const uint32_t vlrCount = get<uint32_t>(d + 100);
    const uint8_t format = d[104];
    if (format & 0xC0) return fail(path, "LAZ (LASzip-compressed) files are not supported yet");
    if (format > 10) return fail(path, "unknown point data format " + std::to_string(format) + " (0 to 10)");
    h.pointFormat = format;
    h.recordLength = get<uint16_t>(d + 105);
    if (h.recordLength < kRecordSize[format])
        return fail(path, "point record length " + std::to_string(h.recordLength) + " is shorter than format " +
                              std::to_string(format) + "'s " + std::to_string(kRecordSize[format]) + " bytes");
    h.extraBytes = uint16_t(h.recordLength - kRecordSize[format]);
    h.pointCount = get<uint32_t>(d + 107);
    for (int i = 0; i < 5; ++i) h.pointsByReturn[size_t(i)] = get<uint32_t>(d + 111 + 4 * i);
    h.scale = {get<double>(d + 131), get<double>(d + 139), get<double>(d + 147)};
    h.offset = {get<double>(d + 155), get<double>(d + 163), get<double>(d + 171)};
    h.max = {get<double>(d + 179), get<double>(d + 195), get<double>(d + 211)};
    h.min = {get<double>(d + 187), get<double>(d + 203), get<double>(d + 219)};
    for (int a = 0; a < 3; ++a)
        if (!(std::abs(h.scale[a]) > 0.0) || !std::isfinite(h.scale[a]) || !std::isfinite(h.offset[a]))
            return fail(path, "scale factor or offset of axis " + std::string(1, "xyz"[a]) + " is zero or not finite");
    uint64_t evlrStart = 0;
    uint32_t evlrCount = 0;
    if (h.versionMinor >= 4) {
        evlrStart = get<uint64_t>(d + 235);
        evlrCount = get<uint32_t>(d + 243);
        const uint64_t count64 = get<uint64_t>(d + 247);
        if (h.pointCount == 0 || format >= 6) h.pointCount = count64;
        for (int i = 0; i < 15; ++i) {
            const uint64_t v = get<uint64_t>(d + 255 + 8 * i);
            if (format >= 6 || i >= 5 || h.pointsByReturn[size_t(i)] == 0) h.pointsByReturn[size_t(i)] = v;
        }
    }

    // VLRs between the header and the points.
    uint64_t at = headerSize;
    for (uint32_t i = 0; i < vlrCount; ++i) {
        if (at + 54 > h.pointOffset || at + 54 > f->bytes_)
            return fail(path, "variable-length record " + std::to_string(i) + " runs past the start of the point data");
        LasVlr v;
        v.userId = fixedString(d + at + 2, 16);
        v.recordId = get<uint16_t>(d + at + 18);
        v.length = get<uint16_t>(d + at + 20);
        v.description = fixedString(d + at + 22, 32);
        if (at + 54 + v.length > h.pointOffset)
            return fail(path, "variable-length record " + std::to_string(i) + " (" + v.userId + " " +
                                  std::to_string(v.recordId) + ") runs past the start of the point data");
        if (v.userId == "laszip encoded") return fail(path, "LAZ (LASzip-compressed) files are not supported yet");
        h.vlrs.push_back(v);
        at += 54 + v.length;
    }
    if (h.pointOffset < headerSize) return fail(path, "the point data starts inside the header");
    // Points: offset + count * record length within the file (no overflow: checked by division).
    if (h.pointOffset > f->bytes_) return fail(path, "the point data offset is past the end of the file");
    const uint64_t room = f->bytes_ - h.pointOffset;
    if (h.pointCount > room / h.recordLength)
        return fail(path, "the header declares " + std::to_string(h.pointCount) + " points of " +
                              std::to_string(h.recordLength) + " bytes but the file holds " +
                              std::to_string(room / h.recordLength) + " (truncated or a corrupt header)");
    // EVLRs after the points (LAS 1.4).
    if (evlrCount > 0) {
        at = evlrStart;
        for (uint32_t i = 0; i < evlrCount; ++i) {
            if (at < h.pointOffset + h.pointCount * h.recordLength || at + 60 > f->bytes_)
                return fail(path, "extended variable-length record " + std::to_string(i) + " lies outside the file");
            LasVlr v;
            v.userId = fixedString(d + at + 2, 16);
            v.recordId = get<uint16_t>(d + at + 18);
            v.length = get<uint64_t>(d + at + 20);
            v.description = fixedString(d + at + 28, 32);
            v.extended = true;
            if (v.length > f->bytes_ - (at + 60))
                return fail(path, "extended variable-length record " + std::to_string(i) + " runs past the end of the file");
            h.vlrs.push_back(v);
            at += 60 + v.length;
        }
    }

    // The CRS: WKT VLR, then GeoTIFF keys, then a sidecar.
    const auto payload = [&](const LasVlr& want) -> const uint8_t* {
        uint64_t pos = headerSize;
        for (const LasVlr& v : h.vlrs) {
            if (v.extended) break;
            if (&v == &want) return d + pos + 54;
            pos += 54 + v.length;
        }
        if (!want.extended) return nullptr;
        pos = evlrStart;
        for (const LasVlr& v : h.vlrs) {
            if (!v.extended) continue;
            if (&v == &want) return d + pos + 60;
            pos += 60 + v.length;
        }
        return nullptr;
    };
    for (const LasVlr& v : h.vlrs)
        if (v.userId == "LASF_Projection" && v.recordId == 2112 && v.length > 0) {
            const uint8_t* p = payload(v);
            if (p) f->crs_ = {fixedString(p, v.length), "WKT VLR"};
            break;
        }
    if (f->crs_.wkt.empty())
        for (const LasVlr& v : h.vlrs)
            if (v.userId == "LASF_Projection" && v.recordId == 34735) {
                if (const uint8_t* p = payload(v)) f->crs_ = crsFromGeoKeys(p, v.length);
                break;
            }
    if (f->crs_.wkt.empty()) {
        const std::filesystem::path p(path);
        const std::filesystem::path candidates[] = {std::filesystem::path(path + ".wkt"),
                                                     std::filesystem::path(p).replace_extension(".wkt"),
                                                     std::filesystem::path(p).replace_extension(".prj")};
        for (const auto& c : candidates) {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(c, ec) || std::filesystem::file_size(c, ec) > (1u << 20)) continue;
            std::string text = readText(c);
            while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
            if (text.empty()) continue;
            f->crs_ = {text, "sidecar " + std::filesystem::weakly_canonical(c, ec).string()};
            break;
        }
    }
    if (f->crs_.wkt.empty() && f->crs_.source.empty()) f->crs_.source = "none";
    return f;
}

void LasFile::read(uint64_t first, uint64_t count, std::vector<LasPoint>& out) const {
    const LasHeader& h = header_;
    first = std::min(first, h.pointCount);
    count = std::min(count, h.pointCount - first);
    out.resize(count);
    const bool modern = h.pointFormat >= 6;
    const uint8_t f = h.pointFormat;
    for (uint64_t i = 0; i < count; ++i) {
        const uint8_t* r = data_ + h.pointOffset + (first + i) * h.recordLength;
        LasPoint& p = out[i];
        p.position = glm::dvec3(get<int32_t>(r), get<int32_t>(r + 4), get<int32_t>(r + 8)) * h.scale + h.offset;
        p.intensity = get<uint16_t>(r + 12);
        size_t rgbAt = 0;
        if (modern) {
            p.returnNumber = r[14] & 15;
            p.numberOfReturns = r[14] >> 4;
            p.flags = r[15] & 15;
            p.classification = r[16];
            p.userData = r[17];
            p.scanAngleDeg = float(get<int16_t>(r + 18)) * 0.006f;
            p.pointSourceId = get<uint16_t>(r + 20);
            p.gpsTime = get<double>(r + 22);
            rgbAt = 30;
        } else {
            p.returnNumber = r[14] & 7;
            p.numberOfReturns = (r[14] >> 3) & 7;
            p.classification = r[15] & 31;
            p.flags = (r[15] >> 5) & 7;
            p.scanAngleDeg = float(get<int8_t>(r + 16));
            p.userData = r[17];
            p.pointSourceId = get<uint16_t>(r + 18);
            if (f == 1 || f >= 3) p.gpsTime = get<double>(r + 20);
            rgbAt = f == 2 ? 20 : 28;
        }
        if (h.hasRgb()) {
            p.red = get<uint16_t>(r + rgbAt);
            p.green = get<uint16_t>(r + rgbAt + 2);
            p.blue = get<uint16_t>(r + rgbAt + 4);
            if (h.hasNir()) p.nir = get<uint16_t>(r + rgbAt + 6);
        }
    }
}

void LasFile::readPositions(uint64_t first, uint64_t count, std::vector<glm::dvec3>& out) const {
    const LasHeader& h = header_;
    first = std::min(first, h.pointCount);
    count = std::min(count, h.pointCount - first);
    out.resize(count);
    for (uint64_t i = 0; i < count; ++i) {
        const uint8_t* r = data_ + h.pointOffset + (first + i) * h.recordLength;
        out[i] = glm::dvec3(get<int32_t>(r), get<int32_t>(r + 4), get<int32_t>(r + 8)) * h.scale + h.offset;
    }
}

}  // namespace orbis::points
