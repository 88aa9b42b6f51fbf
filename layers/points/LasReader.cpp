#include "layers/points/LasReader.h"
#include "layers/points/LasReaderDetail.h"
#include "layers/points/LasBytes.h"

#include "base/FileText.h"
#include "layers/points/LazChunks.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <ogr_spatialref.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace orbis::points {
namespace {

using namespace las_detail;

// Standard record sizes of point data formats 0..10 (LAS 1.4 R15).
constexpr uint16_t kRecordSize[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

std::string fixedString(const uint8_t* p, size_t n) {
    size_t len = 0;
    while (len < n && p[len] != 0) ++len;
    std::string s(reinterpret_cast<const char*>(p), len);
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}


struct Unit {
    double metres = 0.0;   ///< 0: a code we do not know
    const char* name = "";
};

/// The EPSG unit codes GeoTIFF keys use (GeoTIFF 1.1 §7.1.6 and the EPSG units table).
Unit unitFromCode(uint16_t code) {
    switch (code) {
    case 9001: return {1.0, "metre"};
    case 9002: return {0.3048, "foot"};
    case 9003: return {1200.0 / 3937.0, "US survey foot"};
    case 9005: return {0.3047972654, "Clarke's foot"};
    case 9036: return {1000.0, "kilometre"};
    default: return {};
    }
}

/// The GeoKeyDirectoryTag (34735): GeoTIFF 1.1 §2.4, a header of 4 uint16 (version 1, revision
/// 1, minor, key count), then 4 uint16 per key (id, tag location, count, value or index). The
/// keys read here are inline codes (location 0) and citations in the ASCII VLR (34737); none of
/// them needs the doubles (34736).
struct GeoKeys {
    std::map<uint16_t, uint16_t> shorts;          // keys whose value is stored inline (location 0)
    std::map<uint16_t, std::string> ascii;        // keys stored in 34737

    GeoKeys(const uint8_t* dir, uint64_t length, const uint8_t* text, uint64_t textLength) {
        if (!dir || length < 8) return;
        const uint16_t count = bytes::get<uint16_t>(dir + 6);
        for (uint64_t k = 0; k < count && 8 + 8 * (k + 1) <= length; ++k) {
            const uint8_t* e = dir + 8 + 8 * k;
            const uint16_t id = bytes::get<uint16_t>(e), location = bytes::get<uint16_t>(e + 2);
            const uint16_t n = bytes::get<uint16_t>(e + 4), value = bytes::get<uint16_t>(e + 6);
            if (location == 0) shorts[id] = value;
            else if (location == 34737 && text && uint64_t(value) + n <= textLength) {
                std::string s(reinterpret_cast<const char*>(text) + value, n);
                while (!s.empty() && (s.back() == '|' || s.back() == 0 || s.back() == ' ')) s.pop_back();
                ascii[id] = s;
            }
        }
    }
    uint16_t code(uint16_t id) const {
        const auto it = shorts.find(id);
        return it == shorts.end() ? 0 : it->second;
    }
};

std::string exportWkt(const OGRSpatialReference& srs) {
    char* wkt = nullptr;
    const char* options[] = {"FORMAT=WKT2_2019", nullptr};
    std::string out;
    if (srs.exportToWkt(&wkt, options) == OGRERR_NONE && wkt) out = wkt;
    CPLFree(wkt);
    return out;
}

/// GeoTIFF keys to a CRS, for the keys that name EPSG codes: ProjectedCSTypeGeoKey (3072) or
/// GeographicTypeGeoKey (2048), VerticalCSTypeGeoKey (4096) as a compound CRS, and the unit keys
/// ProjLinearUnitsGeoKey (3076) and VerticalUnitsGeoKey (4099) where they differ from the
/// codes' own units. User-defined projections (32767) are reported, not guessed.
LasCrs crsFromGeoKeys(const GeoKeys& keys) {
    constexpr uint16_t kUserDefined = 32767;   // GeoTIFF 1.1 §7.1.4
    LasCrs crs;
    const uint16_t projected = keys.code(3072), geographic = keys.code(2048), vertical = keys.code(4096);
    const bool isProjected = projected != 0 || keys.code(1024) == 1;   // GTModelTypeGeoKey 1 = projected
    const uint16_t code = isProjected ? projected : geographic;
    if (code == 0 || code == kUserDefined) {
        std::string citation;
        for (uint16_t id : {3073, 2049, 1026})   // PCSCitationGeoKey, GeogCitationGeoKey, GTCitationGeoKey
            if (keys.ascii.count(id) && !keys.ascii.at(id).empty()) {
                citation = std::string(" \"").append(keys.ascii.at(id)).append("\"");
                break;
            }
        crs.source = std::string("GeoTIFF keys (")
                         .append(code == 0 ? "no EPSG code" : "user-defined projection")
                         .append(citation)
                         .append(": give a sidecar .wkt or the scene's \"crs\")");
        return crs;
    }
    std::ostringstream source;
    source << "GeoTIFF keys (EPSG:" << code;
    OGRSpatialReference srs;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = srs.importFromEPSG(code) == OGRERR_NONE;
    // A projected CRS whose coordinates the file states in another unit (common in US surveys:
    // a metre-based code with coordinates in feet).
    const Unit linear = unitFromCode(keys.code(3076));
    if (ok && isProjected && linear.metres > 0.0 && std::abs(srs.GetLinearUnits() - linear.metres) > 1e-12 &&
        srs.SetLinearUnitsAndUpdateParameters(linear.name, linear.metres) == OGRERR_NONE)
        source << " in " << linear.name;
    const Unit up = unitFromCode(keys.code(4099));
    OGRSpatialReference heights;
    bool haveHeights = false;
    if (ok && vertical != 0 && vertical != kUserDefined && heights.importFromEPSG(vertical) == OGRERR_NONE) {
        haveHeights = true;
        source << " + EPSG:" << vertical;
        if (up.metres > 0.0 && std::abs(heights.GetTargetLinearUnits("VERT_CS") - up.metres) > 1e-12 &&
            heights.SetTargetLinearUnits("VERT_CS", up.name, up.metres) == OGRERR_NONE)
            source << " in " << up.name;
    } else if (ok && vertical != 0 && vertical != kUserDefined) {
        source << ", vertical EPSG:" << vertical << " unknown to PROJ, heights taken as ellipsoidal";
    } else if (ok && up.metres > 0.0) {
        // Heights in a stated unit but no vertical CRS: LasGeoreference would take them in the
        // horizontal unit (metres for degrees), so only a different unit needs a vertical part.
        const double assumed = isProjected ? srs.GetLinearUnits() : 1.0;
        if (std::abs(assumed - up.metres) > 1e-12) {
            std::ostringstream wkt;
            wkt.precision(17);
            wkt << "VERT_CS[\"heights in " << up.name << "\",VERT_DATUM[\"unknown\",2005],UNIT[\"" << up.name << "\","
                << up.metres << "],AXIS[\"Up\",UP]]";
            haveHeights = heights.SetFromUserInput(wkt.str().c_str()) == OGRERR_NONE;
            if (haveHeights) source << ", heights in " << up.name;
        }
    }
    if (haveHeights) {
        OGRSpatialReference compound;
        const std::string name = std::string(srs.GetName() ? srs.GetName() : "").append(" + ").append(heights.GetName() ? heights.GetName() : "");
        if (compound.SetCompoundCS(name.c_str(), &srs, &heights) == OGRERR_NONE) srs = compound;
    }
    CPLPopErrorHandler();
    if (!ok) {
        crs.source = std::string("GeoTIFF keys (EPSG:").append(std::to_string(code)).append(" is unknown to PROJ)");
        return crs;
    }
    source << ")";
    crs.source = source.str();
    crs.wkt = exportWkt(srs);
    return crs;
}


/// The public header block (LAS 1.4 R15 Table 3; 1.0-1.3 are its prefix up to byte 227/235).
/// `evlrStart`/`evlrCount` come from the 1.4 part.
Result<uint16_t> parseHeader(const std::string& path, const uint8_t* d, uint64_t bytes, LasHeader& h,
                             uint64_t& evlrStart, uint32_t& evlrCount, bool& compressedFlag) {
    h.globalEncoding = bytes::get<uint16_t>(d + 6);
    h.versionMajor = d[24];
    h.versionMinor = d[25];
    if (h.versionMajor != 1 || h.versionMinor > 4)
        return fail(path, std::string("LAS version ").append(num(h.versionMajor)).append(".").append(num(h.versionMinor)).append(" is not supported (1.0 to 1.4)"));
    h.systemId = fixedString(d + 26, 32);
    h.software = fixedString(d + 58, 32);
    h.creationDay = bytes::get<uint16_t>(d + 90);
    h.creationYear = bytes::get<uint16_t>(d + 92);
    const uint16_t headerSize = bytes::get<uint16_t>(d + 94);
    const uint16_t minHeader = h.versionMinor >= 4 ? 375 : h.versionMinor == 3 ? 235 : 227;
    if (headerSize < minHeader || headerSize > bytes)
        return fail(path, std::string("header size ").append(num(headerSize)).append(" is wrong for LAS 1.")
                              .append(num(h.versionMinor)).append(" (at least ").append(num(minHeader))
                              .append(" bytes, within the file's ").append(num(bytes)).append(")"));
    h.pointOffset = bytes::get<uint32_t>(d + 96);
    // LASzip sets bit 7 (and older writers bit 6) of the format byte in compressed files, so that
    // readers that do not know LAZ refuse them.
    compressedFlag = (d[104] & 0xC0) != 0;
    const uint8_t format = d[104] & 0x3F;
    if (format > 10) return fail(path, std::string("unknown point data format ").append(num(format)).append(" (0 to 10)"));
    h.pointFormat = format;
    h.recordLength = bytes::get<uint16_t>(d + 105);
    if (h.recordLength < kRecordSize[format])
        return fail(path, std::string("point record length ").append(num(h.recordLength)).append(" is shorter than format ")
                              .append(num(format)).append("'s ").append(num(kRecordSize[format])).append(" bytes"));
    h.extraBytes = uint16_t(h.recordLength - kRecordSize[format]);
    h.pointCount = bytes::get<uint32_t>(d + 107);
    for (int i = 0; i < 5; ++i) h.pointsByReturn[size_t(i)] = bytes::get<uint32_t>(d + 111 + 4 * i);
    h.scale = {bytes::get<double>(d + 131), bytes::get<double>(d + 139), bytes::get<double>(d + 147)};
    h.offset = {bytes::get<double>(d + 155), bytes::get<double>(d + 163), bytes::get<double>(d + 171)};
    h.max = {bytes::get<double>(d + 179), bytes::get<double>(d + 195), bytes::get<double>(d + 211)};
    h.min = {bytes::get<double>(d + 187), bytes::get<double>(d + 203), bytes::get<double>(d + 219)};
    for (int a = 0; a < 3; ++a)
        if (!(std::abs(h.scale[a]) > 0.0) || !std::isfinite(h.scale[a]) || !std::isfinite(h.offset[a]))
            return fail(path, std::string("the scale factor or offset of axis ").append(1, "xyz"[a]).append(" is zero or not finite"));
    if (h.versionMinor >= 4) {
        // 1.4: 64-bit counts; the legacy 32-bit ones are 0 for formats 6..10 or above 2^32 points.
        evlrStart = bytes::get<uint64_t>(d + 235);
        evlrCount = bytes::get<uint32_t>(d + 243);
        const uint64_t count64 = bytes::get<uint64_t>(d + 247);
        if (h.pointCount == 0 || format >= 6) h.pointCount = count64;
        for (int i = 0; i < 15; ++i) {
            const uint64_t v = bytes::get<uint64_t>(d + 255 + 8 * i);
            if (format >= 6 || i >= 5 || h.pointsByReturn[size_t(i)] == 0) h.pointsByReturn[size_t(i)] = v;
        }
    }
    return headerSize;
}

/// The VLRs between the header and the points (54-byte headers, 16-bit lengths) and the 1.4
/// EVLRs after them (60-byte headers, 64-bit lengths); `payloads` gets each one's data offset.
Result<void> readVlrs(const std::string& path, const uint8_t* d, uint64_t bytes, uint16_t headerSize, uint32_t vlrCount,
                      uint64_t evlrStart, uint32_t evlrCount, uint64_t pointsEnd, LasHeader& h, std::vector<uint64_t>& payloads) {
    uint64_t at = headerSize;
    for (uint32_t i = 0; i < vlrCount; ++i) {
        if (at + 54 > h.pointOffset)
            return fail(path, std::string("variable-length record ").append(num(i)).append(" of ").append(num(vlrCount))
                                  .append(" runs past the start of the point data (byte ").append(num(h.pointOffset)).append(")"));
        LasVlr v;
        v.userId = fixedString(d + at + 2, 16);
        v.recordId = bytes::get<uint16_t>(d + at + 18);
        v.length = bytes::get<uint16_t>(d + at + 20);
        v.description = fixedString(d + at + 22, 32);
        if (at + 54 + v.length > h.pointOffset)
            return fail(path, std::string("variable-length record ").append(num(i)).append(" (").append(v.userId).append(" ")
                                  .append(num(v.recordId)).append(", ").append(num(v.length))
                                  .append(" bytes) runs past the start of the point data"));
        payloads.push_back(at + 54);
        h.vlrs.push_back(std::move(v));
        at += 54 + h.vlrs.back().length;
    }
    at = evlrStart;
    for (uint32_t i = 0; i < evlrCount; ++i) {
        if (at < pointsEnd || at > bytes || bytes - at < 60)
            return fail(path, std::string("extended variable-length record ").append(num(i)).append(" at byte ").append(num(at))
                                  .append(" lies outside the file or inside the point data"));
        LasVlr v;
        v.userId = fixedString(d + at + 2, 16);
        v.recordId = bytes::get<uint16_t>(d + at + 18);
        v.length = bytes::get<uint64_t>(d + at + 20);
        v.description = fixedString(d + at + 28, 32);
        v.extended = true;
        if (v.length > bytes - (at + 60))
            return fail(path, std::string("extended variable-length record ").append(num(i)).append(" (").append(v.userId)
                                  .append(" ").append(num(v.recordId)).append(") runs past the end of the file"));
        payloads.push_back(at + 60);
        h.vlrs.push_back(std::move(v));
        at += 60 + h.vlrs.back().length;
    }
    return {};
}

constexpr std::uintmax_t kMaxSidecarBytes = 1u << 20;

/// The first sidecar that exists and holds text: `cloud.las.wkt`, `cloud.wkt`, `cloud.prj`.
LasCrs sidecarCrs(const std::string& path) {
    const std::filesystem::path p(path);
    const std::filesystem::path candidates[] = {std::filesystem::path(std::string(path).append(".wkt")),
                                                std::filesystem::path(p).replace_extension(".wkt"),
                                                std::filesystem::path(p).replace_extension(".prj")};
    for (const auto& c : candidates) {
        auto read = readTextFile(c, kMaxSidecarBytes, "CRS sidecar");
        if (!read) continue;   // absent (the usual case), a folder, or too large for a CRS: the next one
        std::string text = std::move(read).value();
        while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
        if (text.empty()) continue;
        std::error_code ec;
        return {text, std::string("sidecar ").append(std::filesystem::weakly_canonical(c, ec).string())};
    }
    return {};
}

}  // namespace

bool LasHeader::hasGpsTime() const { return pointFormat == 1 || pointFormat >= 3; }
bool LasHeader::hasRgb() const { return pointFormat == 2 || pointFormat == 3 || pointFormat == 5 || pointFormat == 7 || pointFormat == 8 || pointFormat == 10; }
bool LasHeader::hasNir() const { return pointFormat == 8 || pointFormat == 10; }

// ---------------------------------------------------------------------------------------------
// LAZ

namespace {

/// A chunk holding more points than this is refused: its decoding buffer would be unbounded (LASzip
/// writes 50 000 per chunk, COPC writers a few hundred thousand per node).
constexpr uint64_t kMaxChunkPoints = 8u << 20;

const char* compressorName(uint16_t c) {
    return c == 1 ? "point-wise" : c == 2 ? "point-wise chunked" : "layered chunked";
}

}  // namespace

struct LasFile::Laz {
    laz::LaszipVlr vlr;
    std::vector<laz::Chunk> chunks;
    std::atomic<unsigned> threads{std::max(1u, std::thread::hardware_concurrency())};
    std::atomic<bool> skipDamaged{false};
    // The last chunk decoded (sequential reads rarely end on a chunk's edge) and the damage seen.
    mutable std::mutex mutex;
    mutable size_t cachedChunk = SIZE_MAX;
    mutable uint32_t cachedFields = 0;
    mutable std::shared_ptr<const std::vector<uint8_t>> cached;
    mutable uint64_t skipped = 0;
    mutable std::set<size_t> damaged;
    mutable std::vector<std::string> damageMessages;
};

Result<void> LasFile::openLaz(const uint8_t* d, uint64_t evlrStart, const std::vector<uint64_t>& payloads) {
    LasHeader& h = header_;
    size_t index = 0;
    while (!(h.vlrs[index].userId == "laszip encoded" && h.vlrs[index].recordId == 22204)) ++index;
    auto vlr = laz::parseLaszipVlr({d + payloads[index], size_t(h.vlrs[index].length)});
    if (!vlr) return fail(path_, vlr.message());
    if (auto items = laz::checkItems(*vlr, h.pointFormat, h.recordLength); !items) return fail(path_, items.message());
    auto state = std::make_unique<Laz>();
    state->vlr = std::move(vlr).value();
    const uint64_t end = evlrStart > h.pointOffset && evlrStart <= bytes_ ? evlrStart : bytes_;
    if (state->vlr.compressor == 1) {
        // Not chunked: one stream from the point data to the end.
        if (h.pointCount > kMaxChunkPoints)
            return fail(path_, std::string("a LAZ file that is not chunked (compressor 1) with ").append(num(h.pointCount))
                                   .append(" points: Orbis decodes at most ").append(num(kMaxChunkPoints))
                                   .append(" points at once; re-compress it chunked (laszip, or orbis convert)"));
        if (h.pointCount > 0) state->chunks.push_back({h.pointOffset, end - h.pointOffset, h.pointCount, 0});
    } else {
        if (h.pointOffset + 8 > end) return fail(path_, "the LAZ point data is cut short before its chunk table offset");
        int64_t tableAt = bytes::get<int64_t>(d + h.pointOffset);
        if (tableAt == -1 && bytes_ >= 8) tableAt = bytes::get<int64_t>(d + bytes_ - 8);   // written last by a streaming writer
        if (tableAt < int64_t(h.pointOffset + 8) || uint64_t(tableAt) > end - 8)
            return fail(path_, std::string("the LAZ chunk table offset ").append(std::to_string(tableAt)).append(" lies outside the point data (bytes ")
                                   .append(num(h.pointOffset + 8)).append(" to ").append(num(end)).append(")"));
        const uint64_t table = uint64_t(tableAt);
        auto chunks = laz::decodeChunkTable(state->vlr, {d + table, size_t(end - table)}, h.pointOffset + 8, table, h.pointCount);
        if (!chunks) return fail(path_, chunks.message());
        state->chunks = std::move(chunks).value();
        for (size_t i = 0; i < state->chunks.size(); ++i)
            if (state->chunks[i].points > kMaxChunkPoints)
                return fail(path_, std::string("LAZ chunk ").append(num(i)).append(" claims ").append(num(state->chunks[i].points))
                                       .append(" points, more than the ").append(num(kMaxChunkPoints)).append(" Orbis decodes at once"));
    }
    char text[160];
    std::snprintf(text, sizeof text, "LAZ (LASzip %u.%ur%u, %s, %zu chunk%s)", unsigned(state->vlr.versionMajor), unsigned(state->vlr.versionMinor),
                  unsigned(state->vlr.versionRevision), compressorName(state->vlr.compressor), state->chunks.size(),
                  state->chunks.size() == 1 ? "" : "s");
    h.compression = text;
    laz_ = std::move(state);
    return {};
}

Result<void> LasFile::readLaz(uint64_t first, uint64_t count, std::vector<uint8_t>& raw, uint32_t fields) const {
    const Laz& z = *laz_;
    const LasHeader& h = header_;
    const uint64_t record = h.recordLength;
    raw.clear();
    if (count == 0 || z.chunks.empty()) return {};
    const uint64_t last = first + count - 1;
    const auto byFirst = [](uint64_t p, const laz::Chunk& c) { return p < c.firstPoint; };
    const size_t lo = size_t(std::upper_bound(z.chunks.begin(), z.chunks.end(), first, byFirst) - z.chunks.begin()) - 1;
    const size_t hi = size_t(std::upper_bound(z.chunks.begin(), z.chunks.end(), last, byFirst) - z.chunks.begin()) - 1;
    const size_t n = hi - lo + 1;
    std::vector<std::shared_ptr<const std::vector<uint8_t>>> decoded(n);
    std::vector<std::string> errors(n);
    {
        std::lock_guard lock(z.mutex);
        if (z.cachedChunk >= lo && z.cachedChunk <= hi && (z.cachedFields & fields) == fields) decoded[z.cachedChunk - lo] = z.cached;
    }
    const auto decodeOne = [&](size_t i) {
        const laz::Chunk& c = z.chunks[lo + i];
        std::vector<uint8_t> bytes(c.bytes);
        auto out = std::make_shared<std::vector<uint8_t>>(c.points * record);
        if (std::string why; !readAt(bytes.data(), c.bytes, c.offset, why)) {
            errors[i] = std::string("cannot be read: ").append(why);
            return;
        }
        if (auto r = laz::decodeChunk(z.vlr, bytes, c.points, fields, out->data()); !r) {
            errors[i] = r.message();
            return;
        }
        decoded[i] = std::move(out);
    };
    std::vector<size_t> pending;   // chunks not in the cache
    for (size_t i = 0; i < n; ++i)
        if (!decoded[i]) pending.push_back(i);
    const unsigned threads = unsigned(std::min<size_t>(z.threads.load(), pending.size()));
    if (threads <= 1) {
        for (size_t i : pending) decodeOne(i);
    } else {
        std::atomic<size_t> next{0};
        std::vector<std::thread> workers;
        for (unsigned t = 0; t < threads; ++t)
            workers.emplace_back([&] {
                for (size_t k; (k = next.fetch_add(1)) < pending.size();) decodeOne(pending[k]);
            });
        for (std::thread& w : workers) w.join();
    }
    std::lock_guard lock(z.mutex);
    if (decoded[n - 1]) {
        z.cachedChunk = hi;
        z.cachedFields = fields;
        z.cached = decoded[n - 1];
    }
    raw.reserve(count * record);
    for (size_t i = 0; i < n; ++i) {
        const laz::Chunk& c = z.chunks[lo + i];
        const uint64_t from = std::max(first, c.firstPoint), to = std::min(last + 1, c.firstPoint + c.points);
        if (!decoded[i]) {
            const std::string message = std::string("LAZ chunk ").append(num(lo + i)).append(" of ").append(num(z.chunks.size()))
                                            .append(" (points ").append(num(c.firstPoint)).append(" to ").append(num(c.firstPoint + c.points - 1))
                                            .append(", ").append(num(c.bytes)).append(" bytes at ").append(num(c.offset)).append("): ").append(errors[i]);
            if (!z.skipDamaged) {
                raw.clear();
                return fail(path_, message);
            }
            if (z.damaged.insert(lo + i).second) {
                z.damageMessages.push_back(std::string(path_).append(": ").append(message).append("; its points are left out"));
                z.skipped += c.points;
            }
            continue;
        }
        const uint8_t* src = decoded[i]->data() + (from - c.firstPoint) * record;
        raw.insert(raw.end(), src, src + (to - from) * record);
    }
    return {};
}

Result<void> LasFile::readBytes(uint64_t offset, uint64_t bytes, std::vector<uint8_t>& out) const {
    out.clear();
    if (offset > bytes_ || bytes > bytes_ - offset)
        return fail(path_, std::string("bytes ").append(num(offset)).append(" to ").append(num(offset + bytes)).append(" lie outside the file (")
                               .append(num(bytes_)).append(" bytes)"));
    out.resize(bytes);
    if (std::string why; !readAt(out.data(), bytes, offset, why)) {
        out.clear();
        return fail(path_, std::string("cannot read bytes ").append(num(offset)).append(" to ").append(num(offset + bytes)).append(": ").append(why));
    }
    return {};
}

Result<void> LasFile::readChunk(uint64_t offset, uint64_t bytes, uint64_t count, std::vector<LasPoint>& out) const {
    out.clear();
    const std::string which = std::string("the LAZ chunk of ").append(num(count)).append(" points at byte ").append(num(offset));
    if (!laz_) return fail(path_, which.substr(4).append(": the file is not LAZ"));
    if (count > kMaxChunkPoints)
        return fail(path_, std::string(which).append(": more than the ").append(num(kMaxChunkPoints)).append(" points Orbis decodes at once"));
    std::vector<uint8_t> data, raw(count * header_.recordLength);
    if (auto r = readBytes(offset, bytes, data); !r) return r;
    if (auto r = laz::decodeChunk(laz_->vlr, data, count, laz::kFieldsAll, raw.data()); !r) return fail(path_, std::string(which).append(": ").append(r.message()));
    decodeRecords(raw.data(), count, out);
    return {};
}

void LasFile::setDecodeThreads(unsigned threads) {
    if (laz_) laz_->threads = std::max(1u, threads);
}
void LasFile::setSkipDamagedChunks(bool skip) {
    if (laz_) laz_->skipDamaged = skip;
}
uint64_t LasFile::skippedPoints() const {
    if (!laz_) return 0;
    std::lock_guard lock(laz_->mutex);
    return laz_->skipped;
}
std::vector<std::string> LasFile::damagedChunks() const {
    if (!laz_) return {};
    std::lock_guard lock(laz_->mutex);
    return laz_->damageMessages;
}

LasFile::LasFile() = default;

LasFile::~LasFile() {
    if (fd_ >= 0) close(fd_);
}

Result<std::unique_ptr<LasFile>> LasFile::open(const std::string& path) {
    if (path.rfind("http://", 0) == 0 || path.rfind("https://", 0) == 0) return openRemote(path);
    std::unique_ptr<LasFile> f(new LasFile());
    f->path_ = path;
    f->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (f->fd_ < 0) return fail(path, std::string("cannot open: ").append(std::strerror(errno)));
    struct stat st {};
    if (fstat(f->fd_, &st) != 0 || !S_ISREG(st.st_mode)) return fail(path, "not a regular file");
    f->bytes_ = uint64_t(st.st_size);
    if (f->bytes_ < 227) return fail(path, std::string("not a LAS file (").append(num(f->bytes_)).append(" bytes, shorter than a LAS header)"));
    void* map = mmap(nullptr, f->bytes_, PROT_READ, MAP_PRIVATE, f->fd_, 0);
    if (map == MAP_FAILED) return fail(path, std::string("cannot map: ").append(std::strerror(errno)));
    const Mapping mapping{static_cast<const uint8_t*>(map), f->bytes_};
    if (auto parsed = parse(*f, mapping.data); !parsed) return parsed.error();
    return f;
}

Result<void> LasFile::parse(LasFile& file, const uint8_t* d) {
    LasFile* f = &file;
    const std::string& path = f->path_;
    if (std::memcmp(d, "LASF", 4) != 0) return fail(path, "not a LAS file (no \"LASF\" signature)");

    LasHeader& h = f->header_;
    uint64_t evlrStart = 0;
    uint32_t evlrCount = 0;
    bool compressedFlag = false;
    auto headerSize = parseHeader(path, d, f->bytes_, h, evlrStart, evlrCount, compressedFlag);
    if (!headerSize) return headerSize.error();
    if (h.pointOffset < *headerSize)
        return fail(path, std::string("the point data offset ").append(num(h.pointOffset)).append(" lies inside the ")
                              .append(num(*headerSize)).append("-byte header"));
    if (h.pointOffset > f->bytes_)
        return fail(path, std::string("the point data offset ").append(num(h.pointOffset)).append(" is past the end of the file (")
                              .append(num(f->bytes_)).append(" bytes)"));
    // offset + count * record length within the file, compared by division: no overflow. (A LAZ
    // file's chunks are checked against the file when its chunk table is read.)
    const uint64_t room = f->bytes_ - h.pointOffset;
    if (!compressedFlag && h.pointCount > room / h.recordLength)
        return fail(path, std::string("the header declares ").append(num(h.pointCount)).append(" points of ")
                              .append(num(h.recordLength)).append(" bytes but the file holds ")
                              .append(num(room / h.recordLength)).append(" (truncated or a corrupt header)"));
    const uint64_t pointsEnd = compressedFlag ? h.pointOffset : h.pointOffset + h.pointCount * h.recordLength;
    std::vector<uint64_t> payloads;
    if (auto vlrs = readVlrs(path, d, f->bytes_, *headerSize, bytes::get<uint32_t>(d + 100), evlrStart, evlrCount, pointsEnd, h, payloads); !vlrs)
        return vlrs.error();
    const bool lazVlr = std::any_of(h.vlrs.begin(), h.vlrs.end(), [](const LasVlr& v) { return v.userId == "laszip encoded" && v.recordId == 22204; });
    if (compressedFlag && !lazVlr)
        return fail(path, "the point format marks the file compressed (LAZ) but it has no \"laszip encoded\" VLR");
    if (lazVlr) {
        if (auto laz = f->openLaz(d, evlrCount > 0 ? evlrStart : 0, payloads); !laz) return laz.error();
    }
    // COPC: its info VLR comes first (COPC 1.0 §3.1), in a LAZ 1.4 file of layered chunks.
    if (!h.vlrs.empty() && h.vlrs[0].userId == "copc" && h.vlrs[0].recordId == 1) {
        if (!f->laz_ || f->laz_->vlr.compressor != 3 || h.versionMinor != 4)
            return fail(path, "a COPC info VLR in a file that is not LAZ 1.4 with layered chunks");
        auto info = copc::parseInfo({d + payloads[0], size_t(h.vlrs[0].length)});
        if (!info) return fail(path, info.message());
        f->copc_ = *info;
    }

    // The CRS: WKT VLR, then GeoTIFF keys, then a sidecar (a sidecar also stands in for GeoTIFF
    // keys that name no EPSG code).
    const auto find = [&](uint16_t id) -> size_t {
        for (size_t i = 0; i < h.vlrs.size(); ++i)
            if (h.vlrs[i].userId == "LASF_Projection" && h.vlrs[i].recordId == id && h.vlrs[i].length > 0) return i;
        return h.vlrs.size();
    };
    if (const size_t w = find(2112); w < h.vlrs.size()) f->crs_ = {fixedString(d + payloads[w], h.vlrs[w].length), "WKT VLR"};
    if (const size_t k = find(34735); f->crs_.wkt.empty() && k < h.vlrs.size()) {
        const size_t t = find(34737);
        const bool text = t < h.vlrs.size();
        f->crs_ = crsFromGeoKeys(GeoKeys(d + payloads[k], h.vlrs[k].length, text ? d + payloads[t] : nullptr,
                                         text ? h.vlrs[t].length : 0));
    }
    if (f->crs_.wkt.empty())
        if (LasCrs side = f->remote_ ? remoteSidecarCrs(path) : sidecarCrs(path); !side.wkt.empty()) f->crs_ = std::move(side);
    if (f->crs_.wkt.empty() && f->crs_.source.empty()) f->crs_.source = "none";
    return {};
}

Result<void> LasFile::readRaw(uint64_t first, uint64_t count, std::vector<uint8_t>& raw, uint32_t fields) const {
    if (laz_) return readLaz(first, count, raw, fields);
    const LasHeader& h = header_;
    raw.resize(count * h.recordLength);
    uint64_t offset = h.pointOffset + first * h.recordLength, left = raw.size();
    if (remote_) {
        std::string why;
        if (readAt(raw.data(), left, offset, why)) return {};
        raw.clear();
        return fail(path_, std::string("cannot read points ").append(num(first)).append(" to ").append(num(first + count)).append(": ").append(why));
    }
    uint8_t* p = raw.data();
    while (left > 0) {
        const ssize_t r = ::pread(fd_, p, left, off_t(offset));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) {
            struct stat st {};
            const uint64_t now = fstat(fd_, &st) == 0 ? uint64_t(st.st_size) : 0;
            return fail(path_, std::string("cannot read points ").append(num(first)).append(" to ").append(num(first + count))
                                   .append(r < 0 ? std::string(": ").append(std::strerror(errno)) : std::string())
                                   .append(": the file is now ").append(num(now)).append(" bytes, ").append(num(bytes_))
                                   .append(" when opened (changed while loading?)"));
        }
        p += r, left -= uint64_t(r), offset += uint64_t(r);
    }
    return {};
}

Result<void> LasFile::read(uint64_t first, uint64_t count, std::vector<LasPoint>& out) const {
    const LasHeader& h = header_;
    first = std::min(first, h.pointCount);
    count = std::min(count, h.pointCount - first);
    std::vector<uint8_t> raw;
    if (auto r = readRaw(first, count, raw, laz::kFieldsAll); !r) {
        out.clear();
        return r;
    }
    count = raw.size() / h.recordLength;   // fewer when damaged LAZ chunks were skipped
    decodeRecords(raw.data(), count, out);
    return {};
}

void LasFile::decodeRecords(const uint8_t* raw, uint64_t count, std::vector<LasPoint>& out) const {
    const LasHeader& h = header_;
    out.resize(count);
    const bool modern = h.pointFormat >= 6;
    const uint8_t f = h.pointFormat;
    for (uint64_t i = 0; i < count; ++i) {
        const uint8_t* r = raw + i * h.recordLength;
        LasPoint& p = out[i];
        p.position = glm::dvec3(bytes::get<int32_t>(r), bytes::get<int32_t>(r + 4), bytes::get<int32_t>(r + 8)) * h.scale + h.offset;
        p.intensity = bytes::get<uint16_t>(r + 12);
        size_t rgbAt = 0;
        if (modern) {
            p.returnNumber = r[14] & 15;
            p.numberOfReturns = r[14] >> 4;
            p.flags = uint8_t((r[15] & 15) | ((r[15] >> 6) & 3) << 4);
            p.scannerChannel = (r[15] >> 4) & 3;
            p.classification = r[16];
            p.userData = r[17];
            p.scanAngleDeg = float(bytes::get<int16_t>(r + 18)) * 0.006f;
            p.pointSourceId = bytes::get<uint16_t>(r + 20);
            p.gpsTime = bytes::get<double>(r + 22);
            rgbAt = 30;
        } else {
            p.returnNumber = r[14] & 7;
            p.numberOfReturns = (r[14] >> 3) & 7;
            p.classification = r[15] & 31;
            p.flags = uint8_t(((r[15] >> 5) & 7) | ((r[14] >> 6) & 3) << 4);
            p.scanAngleDeg = float(bytes::get<int8_t>(r + 16));
            p.userData = r[17];
            p.pointSourceId = bytes::get<uint16_t>(r + 18);
            if (f == 1 || f >= 3) p.gpsTime = bytes::get<double>(r + 20);
            rgbAt = f == 2 ? 20 : 28;
        }
        if (h.hasRgb()) {
            p.red = bytes::get<uint16_t>(r + rgbAt);
            p.green = bytes::get<uint16_t>(r + rgbAt + 2);
            p.blue = bytes::get<uint16_t>(r + rgbAt + 4);
            if (h.hasNir()) p.nir = bytes::get<uint16_t>(r + rgbAt + 6);
        }
    }
}

Result<void> LasFile::readPositions(uint64_t first, uint64_t count, std::vector<glm::dvec3>& out) const {
    const LasHeader& h = header_;
    first = std::min(first, h.pointCount);
    count = std::min(count, h.pointCount - first);
    std::vector<uint8_t> raw;
    if (auto r = readRaw(first, count, raw, laz::kFieldPositions); !r) {
        out.clear();
        return r;
    }
    count = raw.size() / h.recordLength;
    out.resize(count);
    for (uint64_t i = 0; i < count; ++i) {
        const uint8_t* r = raw.data() + i * h.recordLength;
        out[i] = glm::dvec3(bytes::get<int32_t>(r), bytes::get<int32_t>(r + 4), bytes::get<int32_t>(r + 8)) * h.scale + h.offset;
    }
    return {};
}

}  // namespace orbis::points
