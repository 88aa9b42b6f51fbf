// The bytes of a COPC file around its chunks (CopcLayout.h).
#include "layers/points/CopcLayout.h"

#include "layers/points/LasBytes.h"

#include <cpl_error.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cstring>
#include <ctime>
#include <tuple>

namespace orbis::points {
namespace {

constexpr uint16_t kHeaderSize = 375;   // LAS 1.4
constexpr uint32_t kInfoBytes = 160;    // the copc info VLR's payload
constexpr uint32_t kEntryBytes = 32;    // a hierarchy entry

void putString(uint8_t* b, size_t at, const std::string& s, size_t n) { std::memcpy(b + at, s.data(), std::min(n, s.size())); }

/// A VLR (LAS 1.4 R15 Table 13): 54-byte header then the payload.
void vlr(std::vector<uint8_t>& out, const std::string& user, uint16_t id, const std::vector<uint8_t>& payload, const std::string& description) {
    uint8_t h[54] = {};
    putString(h, 2, user, 16);
    bytes::put<uint16_t>(h + 18, id);
    bytes::put<uint16_t>(h + 20, uint16_t(payload.size()));
    putString(h, 22, description, 32);
    out.insert(out.end(), h, h + 54);
    out.insert(out.end(), payload.begin(), payload.end());
}

}  // namespace

bool levelOrder(const copc::Key& p, const copc::Key& q) { return std::tie(p.d, p.z, p.y, p.x) < std::tie(q.d, q.z, q.y, q.x); }

std::string wkt1(const std::string& crs) {
    const size_t start = crs.find_first_not_of(" \t\r\n");
    if (start == std::string::npos) return {};
    for (const char* keyword : {"PROJCS[", "GEOGCS[", "GEOCCS[", "COMPD_CS[", "VERT_CS[", "LOCAL_CS["})
        if (crs.compare(start, std::strlen(keyword), keyword) == 0) return crs.substr(start);
    OGRSpatialReference srs;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::string out = crs.substr(start);
    if (srs.SetFromUserInput(crs.c_str()) == OGRERR_NONE) {
        char* text = nullptr;
        const char* options[] = {"FORMAT=WKT1_GDAL", nullptr};
        if (srs.exportToWkt(&text, options) == OGRERR_NONE && text && *text) out = text;
        CPLFree(text);
    }
    CPLPopErrorHandler();
    return out;
}

laz::LaszipVlr copcLaszip(uint8_t format) {
    laz::LaszipVlr z;
    z.compressor = 3;
    z.versionMajor = 3, z.versionMinor = 4, z.versionRevision = 3;
    z.chunkSize = 0xFFFFFFFFu;   // variable: each node's chunk holds its points
    z.items.push_back({laz::ItemType::Point14, 30, 3});
    if (format == 7) z.items.push_back({laz::ItemType::Rgb14, 6, 3});
    if (format == 8) z.items.push_back({laz::ItemType::RgbNir14, 8, 3});
    return z;
}

std::vector<uint8_t> copcHead(const laz::LaszipVlr& z, const std::string& wkt) {
    std::vector<uint8_t> laszip(34 + 6 * z.items.size(), 0);
    uint8_t* l = laszip.data();
    bytes::put<uint16_t>(l, z.compressor);
    l[4] = z.versionMajor, l[5] = z.versionMinor;
    bytes::put<uint16_t>(l + 6, z.versionRevision);
    bytes::put<uint32_t>(l + 12, z.chunkSize);
    bytes::put<int64_t>(l + 16, -1);   // no special EVLRs
    bytes::put<int64_t>(l + 24, -1);
    bytes::put<uint16_t>(l + 32, uint16_t(z.items.size()));
    for (size_t i = 0; i < z.items.size(); ++i) {
        bytes::put<uint16_t>(l + 34 + 6 * i, uint16_t(z.items[i].type));
        bytes::put<uint16_t>(l + 36 + 6 * i, z.items[i].size);
        bytes::put<uint16_t>(l + 38 + 6 * i, z.items[i].version);
    }
    std::vector<uint8_t> head(kHeaderSize, 0);
    // The copc info first (filled in once the hierarchy's place is known), laszip, WKT.
    vlr(head, "copc", 1, std::vector<uint8_t>(kInfoBytes, 0), "COPC info VLR");
    vlr(head, "laszip encoded", 22204, laszip, "Orbis LAZ (LASzip format)");
    std::vector<uint8_t> text(wkt.begin(), wkt.end());
    text.push_back(0);
    vlr(head, "LASF_Projection", 2112, text, "OGC WKT");
    head.resize(head.size() + 8);   // the offset of the chunk table
    return head;
}

std::vector<uint8_t> hierarchyEvlr(std::vector<copc::Node> entries) {
    std::sort(entries.begin(), entries.end(), [](const copc::Node& a, const copc::Node& b) { return levelOrder(a.key, b.key); });
    const uint64_t pageBytes = uint64_t(kEntryBytes) * std::max<size_t>(entries.size(), 1);
    std::vector<uint8_t> evlr(60 + pageBytes, 0);
    putString(evlr.data(), 2, "copc", 16);
    bytes::put<uint16_t>(evlr.data() + 18, 1000);
    bytes::put<uint64_t>(evlr.data() + 20, pageBytes);
    putString(evlr.data(), 28, "EPT hierarchy", 32);
    for (size_t i = 0; i < entries.size(); ++i) {
        const copc::Node& nd = entries[i];
        uint8_t* e = evlr.data() + 60 + kEntryBytes * i;
        bytes::put<int32_t>(e, nd.key.d);
        bytes::put<int32_t>(e + 4, nd.key.x);
        bytes::put<int32_t>(e + 8, nd.key.y);
        bytes::put<int32_t>(e + 12, nd.key.z);
        bytes::put<uint64_t>(e + 16, nd.offset);
        bytes::put<int32_t>(e + 24, int32_t(nd.bytes));
        bytes::put<int32_t>(e + 28, int32_t(nd.points));
    }
    return evlr;
}

void fillCopcHead(std::vector<uint8_t>& head, const CopcHeadFields& f, const copc::Info& info) {
    uint8_t* h = head.data();
    const uint64_t pointOffset = head.size() - 8;
    putString(h, 0, "LASF", 4);
    bytes::put<uint16_t>(h + 6, uint16_t(16 | (f.globalEncoding & 1)));   // WKT; the GPS time's kind as the input's
    h[24] = 1;
    h[25] = 4;
    putString(h, 26, "Orbis", 32);
    putString(h, 58, "Orbis CopcWriter", 32);
    {
        const std::time_t now = std::time(nullptr);
        std::tm utc{};
        gmtime_r(&now, &utc);
        bytes::put<uint16_t>(h + 90, uint16_t(utc.tm_yday + 1));
        bytes::put<uint16_t>(h + 92, uint16_t(utc.tm_year + 1900));
    }
    bytes::put<uint16_t>(h + 94, kHeaderSize);
    bytes::put<uint32_t>(h + 96, uint32_t(pointOffset));
    bytes::put<uint32_t>(h + 100, 3);            // VLRs
    h[104] = uint8_t(f.format | 0x80);           // LASzip's mark of compressed points
    bytes::put<uint16_t>(h + 105, f.recordLength);
    // 107..130: the legacy counts, 0 for formats 6-10.
    for (int a = 0; a < 3; ++a) {
        bytes::put<double>(h + 131 + 8 * a, f.scale[a]);
        bytes::put<double>(h + 155 + 8 * a, f.offset[a]);
        bytes::put<double>(h + 179 + 16 * a, f.hi[a]);
        bytes::put<double>(h + 187 + 16 * a, f.lo[a]);
    }
    bytes::put<uint64_t>(h + 227, 0);   // no waveform data
    bytes::put<uint64_t>(h + 235, f.evlrAt);
    bytes::put<uint32_t>(h + 243, 1);
    bytes::put<uint64_t>(h + 247, f.points);
    for (int i = 0; i < 15; ++i) bytes::put<uint64_t>(h + 255 + 8 * i, f.byReturn[size_t(i)]);
    uint8_t* c = h + kHeaderSize + 54;
    for (int a = 0; a < 3; ++a) bytes::put<double>(c + 8 * a, info.centre[a]);
    bytes::put<double>(c + 24, info.halfSize);
    bytes::put<double>(c + 32, info.spacing);
    bytes::put<uint64_t>(c + 40, info.rootPageOffset);
    bytes::put<uint64_t>(c + 48, info.rootPageBytes);
    bytes::put<double>(c + 56, info.gpsTimeMin);
    bytes::put<double>(c + 64, info.gpsTimeMax);
    bytes::put<int64_t>(h + pointOffset, int64_t(f.chunkTableAt));
}

}  // namespace orbis::points
