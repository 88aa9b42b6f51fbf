// LAZ reading: the real files in ../shared/data/lidar written by LASzip (1.2, 2.0, 3.4), libLAS and
// a COPC writer decode to exactly the points of their LAS twins; damaged files (a chunk cut short
// or corrupt, a chunk table outside the file or lying about counts, unknown compressors and item
// versions) give errors naming the file and the chunk, and the other chunks still load.
#include "layers/points/LasReader.h"
#include "layers/points/LazChunks.h"
#include "layers/points/LazCoder.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <tuple>

namespace orbis::points {
namespace {

namespace fs = std::filesystem;

fs::path lidar(const char* name) { return fs::path(ORBIS_SHARED_DATA_DIR) / "lidar" / name; }
fs::path tempDir() { return test::processTempDir("orbis-laz"); }

std::vector<char> bytesOf(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
std::string writeBytes(const std::string& name, const std::vector<char>& b) {
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(b.size()));
    return p.string();
}
template <typename T>
T peek(const std::vector<char>& b, size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}
template <typename T>
void poke(std::vector<char>& b, size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof v);
}

std::vector<LasPoint> readAll(const std::string& path) {
    auto f = LasFile::open(path);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.message());
    std::vector<LasPoint> pts;
    if (f) {
        auto r = (*f)->read(0, UINT64_MAX, pts);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.message());
    }
    return pts;
}

/// Field-by-field equality (LAS 1.2 fields; the 1.4 scan angle is compared in degrees).
/// `tolerance`: positions in files of different scales and offsets differ by rounding.
void expectSamePoint(const LasPoint& a, const LasPoint& b, const std::string& where, double tolerance = 0.0) {
    if (tolerance == 0.0) EXPECT_EQ(a.position, b.position) << where;
    else EXPECT_LE(glm::length(a.position - b.position), tolerance) << where;
    EXPECT_EQ(a.intensity, b.intensity) << where;
    EXPECT_EQ(a.returnNumber, b.returnNumber) << where;
    EXPECT_EQ(a.numberOfReturns, b.numberOfReturns) << where;
    EXPECT_EQ(a.classification, b.classification) << where;
    EXPECT_EQ(a.flags, b.flags) << where;
    EXPECT_EQ(a.scannerChannel, b.scannerChannel) << where;
    EXPECT_EQ(a.userData, b.userData) << where;
    EXPECT_NEAR(a.scanAngleDeg, b.scanAngleDeg, 0.01) << where;
    EXPECT_EQ(a.pointSourceId, b.pointSourceId) << where;
    EXPECT_EQ(a.gpsTime, b.gpsTime) << where;
    EXPECT_EQ(a.red, b.red) << where;
    EXPECT_EQ(a.green, b.green) << where;
    EXPECT_EQ(a.blue, b.blue) << where;
}

// Every writer's LAZ of the 1065-point survey equals simple.las record for record: LASzip 3.4 and
// 2.0 and libLAS (compressor 2, items v2), LASzip 1.2 (compressor 1, items v1).
TEST(LazFile, EveryPointWiseWriterDecodesToItsLasTwin) {
    if (!fs::exists(lidar("simple.las"))) GTEST_SKIP() << "../shared/data is absent";
    const std::vector<LasPoint> twin = readAll(lidar("simple.las").string());
    ASSERT_EQ(twin.size(), 1065u);
    for (const char* name : {"simple.laz", "laszip-generated.laz", "liblas-generated.laz", "simple-laszip-compressor-version-1.2r0.laz"}) {
        SCOPED_TRACE(name);
        auto f = LasFile::open(lidar(name).string());
        ASSERT_TRUE(f.ok()) << f.message();
        EXPECT_TRUE((*f)->compressed());
        EXPECT_EQ((*f)->header().pointFormat, 3);   // the compressed bit is not part of the format
        EXPECT_EQ((*f)->header().compression.rfind("LAZ (LASzip ", 0), 0u) << (*f)->header().compression;
        std::vector<LasPoint> pts;
        ASSERT_TRUE((*f)->read(0, UINT64_MAX, pts).ok());
        ASSERT_EQ(pts.size(), twin.size());
        for (size_t i = 0; i < pts.size(); ++i) expectSamePoint(pts[i], twin[i], std::string(name).append(" point ").append(std::to_string(i)));
        // A range inside the chunk, and positions alone.
        ASSERT_TRUE((*f)->read(700, 100, pts).ok());
        ASSERT_EQ(pts.size(), 100u);
        EXPECT_EQ(pts[99].position, twin[799].position);
        std::vector<glm::dvec3> xyz;
        ASSERT_TRUE((*f)->readPositions(1000, 500, xyz).ok());
        ASSERT_EQ(xyz.size(), 65u);
        EXPECT_EQ(xyz[64], twin[1064].position);
    }
}

// The arithmetic coder and the integer codec read back what they wrote, through every class of
// corrector (k = 0..32) and contexts, with the raw bits of large classes.
TEST(LazCoder, EncoderAndDecoderMirrorEachOther) {
    std::vector<uint8_t> out;
    laz::ArithmeticEncoder enc(out);
    laz::IntegerCodec wide(32, 3), narrow(16, 2);
    laz::SymbolModel symbols(300);
    laz::BitModel bit;
    std::vector<std::tuple<int32_t, int32_t, uint32_t>> values;
    uint32_t seed = 12345;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (int i = 0; i < 20000; ++i) {
        const int shift = int(next() % 32);
        const int32_t pred = int32_t(next()) >> shift, real = int32_t(next()) >> int(next() % 32);
        values.emplace_back(pred, real, next() % 3);
    }
    values.emplace_back(0, INT32_MIN, 0);
    values.emplace_back(INT32_MIN, INT32_MAX, 1);
    for (const auto& [p, r, c] : values) {
        wide.compress(enc, p, r, c);
        narrow.compress(enc, p & 0xFFFF, r & 0xFFFF, c % 2);
        enc.encodeSymbol(symbols, uint32_t(r) % 300);
        enc.encodeBit(bit, uint32_t(p) & 1);
        enc.writeBits(13, uint32_t(r) & 0x1FFF);
    }
    enc.writeInt64(0x0123456789ABCDEFull);
    enc.done();
    // The decoder's models start afresh, as a reader's do.
    wide = laz::IntegerCodec(32, 3), narrow = laz::IntegerCodec(16, 2);
    symbols = laz::SymbolModel(300);
    bit = laz::BitModel();
    laz::ArithmeticDecoder dec;
    dec.init(out.data(), out.size());
    for (const auto& [p, r, c] : values) {
        ASSERT_EQ(wide.decompress(dec, p, c), r);
        ASSERT_EQ(narrow.decompress(dec, p & 0xFFFF, c % 2), r & 0xFFFF);
        ASSERT_EQ(dec.decodeSymbol(symbols), uint32_t(r) % 300);
        ASSERT_EQ(dec.decodeBit(bit), uint32_t(p) & 1);
        ASSERT_EQ(dec.readBits(13), uint32_t(r) & 0x1FFF);
    }
    EXPECT_EQ(dec.readInt64(), 0x0123456789ABCDEFull);
    EXPECT_EQ(dec.overrun(), 0u);
}

// simple.laz's layout: the int64 at the point data is the chunk table's offset; the table is a
// version, a count and the coded sizes.
struct Layout {
    uint32_t pointOffset = 0;
    int64_t tableAt = 0;
    size_t vlrPayload = 0;   // offset of the laszip VLR's payload
};
Layout layoutOf(const std::vector<char>& b) {
    Layout l;
    l.pointOffset = peek<uint32_t>(b, 96);
    l.tableAt = peek<int64_t>(b, l.pointOffset);
    size_t at = peek<uint16_t>(b, 94);
    for (uint32_t i = 0; i < peek<uint32_t>(b, 100); ++i) {
        if (std::string(b.data() + at + 2, 14) == "laszip encoded") l.vlrPayload = at + 54;
        at += 54 + peek<uint16_t>(b, at + 20);
    }
    return l;
}

/// simple.laz with its chunk table re-coded to say `bytes` and `points` for its one chunk.
std::vector<char> withChunkTable(std::vector<char> b, uint64_t bytes, uint64_t points, bool variable) {
    const Layout l = layoutOf(b);
    laz::LaszipVlr vlr;
    vlr.chunkSize = variable ? 0xFFFFFFFFu : 50000;
    if (variable) poke<uint32_t>(b, l.vlrPayload + 12, 0xFFFFFFFFu);
    std::vector<uint8_t> table;
    const laz::Chunk chunk{0, bytes, points, 0};
    laz::encodeChunkTable(vlr, {&chunk, 1}, table);
    b.resize(size_t(l.tableAt));
    b.insert(b.end(), table.begin(), table.end());
    return b;
}

TEST(LazFile, DamagedFilesGiveErrorsNamingTheFileAndTheChunk) {
    if (!fs::exists(lidar("simple.laz"))) GTEST_SKIP() << "../shared/data is absent";
    const std::vector<char> good = bytesOf(lidar("simple.laz"));
    const Layout l = layoutOf(good);
    ASSERT_GT(l.vlrPayload, 0u);
    ASSERT_GT(l.tableAt, int64_t(l.pointOffset));
    const uint64_t chunkBytes = uint64_t(l.tableAt) - l.pointOffset - 8;
    {   // The re-coded table of the same chunk reads as the original: the table codec is right.
        auto f = LasFile::open(writeBytes("same-table.laz", withChunkTable(good, chunkBytes, 1065, true)));
        ASSERT_TRUE(f.ok()) << f.message();
        std::vector<LasPoint> pts;
        ASSERT_TRUE((*f)->read(0, 2000, pts).ok());
        EXPECT_EQ(pts.size(), 1065u);
    }
    struct Case {
        const char* name;
        std::function<std::vector<char>()> make;
        const char* says;
        bool atOpen;
    };
    const auto patched = [&](std::function<void(std::vector<char>&)> patch) {
        return [&good, patch] {
            std::vector<char> b = good;
            patch(b);
            return b;
        };
    };
    const Case cases[] = {
        // The chunk's data ends early: its table says it is shorter than it is.
        {"truncated-chunk.laz", [&] { return withChunkTable(good, chunkBytes / 2, 1065, true); }, "LAZ chunk 0 of 1 (points 0 to 1064", false},
        {"table-outside.laz", patched([&](std::vector<char>& b) { poke<int64_t>(b, l.pointOffset, int64_t(1) << 40); }), "chunk table offset 1099511627776 lies outside", true},
        {"table-in-header.laz", patched([&](std::vector<char>& b) { poke<int64_t>(b, l.pointOffset, 12); }), "lies outside the point data", true},
        {"billion-points.laz", [&] { return withChunkTable(good, chunkBytes, 1000000000, true); }, "chunk 0 claims 1000000000 points", true},
        {"chunk-past-table.laz", [&] { return withChunkTable(good, chunkBytes + 100, 1065, true); }, "runs past the point data's end", true},
        {"unknown-compressor.laz", patched([&](std::vector<char>& b) { poke<uint16_t>(b, l.vlrPayload, 7); }), "unknown LAZ compressor 7", true},
        {"unknown-item-version.laz", patched([&](std::vector<char>& b) { poke<uint16_t>(b, l.vlrPayload + 34 + 4, 9); }), "LAZ item 0 (POINT10 version 9)", true},
        {"wrong-item.laz", patched([&](std::vector<char>& b) { poke<uint16_t>(b, l.vlrPayload + 34, 10); }), "does not belong to point format 3", true},
        {"no-vlr.laz", patched([&](std::vector<char>& b) { std::memcpy(b.data() + l.vlrPayload - 54 + 2, "laszip_encoded", 14); }), "has no \"laszip encoded\" VLR", true},
        {"cut-file.laz", [&] { return std::vector<char>(good.begin(), good.begin() + l.pointOffset + 4); }, "cut short before its chunk table offset", true},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = writeBytes(c.name, c.make());
        auto f = LasFile::open(path);
        if (c.atOpen) {
            ASSERT_FALSE(f.ok());
            EXPECT_NE(f.message().find(path), std::string::npos) << f.message();
            EXPECT_NE(f.message().find(c.says), std::string::npos) << f.message();
            continue;
        }
        ASSERT_TRUE(f.ok()) << f.message();
        std::vector<LasPoint> pts;
        auto r = (*f)->read(0, 2000, pts);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.message().find(path), std::string::npos) << r.message();
        EXPECT_NE(r.message().find(c.says), std::string::npos) << r.message();
        EXPECT_TRUE(pts.empty());
        // Skipping damaged chunks: the read succeeds without them and says what it left out.
        (*f)->setSkipDamagedChunks(true);
        ASSERT_TRUE((*f)->read(0, 2000, pts).ok());
        EXPECT_TRUE(pts.empty());
        EXPECT_EQ((*f)->skippedPoints(), 1065u);
        ASSERT_EQ((*f)->damagedChunks().size(), 1u);
        EXPECT_NE((*f)->damagedChunks()[0].find("left out"), std::string::npos);
    }
}

// Compressed and uncompressed data read the same under the decoder thread counts the layer uses.
TEST(LazFile, ThreadCountsDoNotChangeThePoints) {
    if (!fs::exists(lidar("simple.laz"))) GTEST_SKIP() << "../shared/data is absent";
    std::vector<LasPoint> one, two;
    for (unsigned threads : {1u, 2u, 8u}) {
        auto f = LasFile::open(lidar("simple.laz").string());
        ASSERT_TRUE(f.ok()) << f.message();
        (*f)->setDecodeThreads(threads);
        ASSERT_TRUE((*f)->read(0, UINT64_MAX, threads == 1 ? one : two).ok());
        if (threads > 1) {
            ASSERT_EQ(one.size(), two.size());
            for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i].position, two[i].position);
        }
    }
}

}  // namespace
}  // namespace orbis::points

namespace orbis::points {
namespace {

/// Points that exercise every field of formats 6-8: several scanner channels, returns, GPS time
/// jumps and repeats, classes above 31, colours with changing high and low bytes.
std::vector<LasPoint> variedPoints(size_t n) {
    std::vector<LasPoint> pts(n);
    uint32_t seed = 7;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    double time = 4e5;
    for (size_t i = 0; i < n; ++i) {
        LasPoint& p = pts[i];
        p.position = {500000.0 + 0.001 * double(next() % 100000), 5100000.0 + 0.001 * double(next() % 100000), 100.0 + 0.001 * double(next() % 5000)};
        p.numberOfReturns = uint8_t(1 + next() % 5);
        p.returnNumber = uint8_t(1 + next() % p.numberOfReturns);
        p.classification = uint8_t(next() % 8 == 0 ? 40 + next() % 100 : 2);
        p.flags = uint8_t(next() % 64);
        p.scannerChannel = uint8_t(next() % 4);
        p.userData = uint8_t(next() % 3);
        p.scanAngleDeg = float(int(next() % 200) - 100) * 0.006f * 50.0f;
        p.pointSourceId = uint16_t(next() % 50 == 0 ? next() : 7);
        if (next() % 3 != 0) time += next() % 1000 == 0 ? 1e6 : 1e-5 * double(next() % 7);
        p.gpsTime = time;
        p.intensity = uint16_t(next());
        p.red = uint16_t(next() % 4 == 0 ? next() : 256 * 40);
        p.green = uint16_t(p.red + next() % 300);
        p.blue = uint16_t(next());
        p.nir = uint16_t(next());
    }
    return pts;
}

// What Orbis writes as LAZ (layered chunks, formats 6, 7, 8, extra bytes, several chunks and a
// short last one) reads back exactly, whole and in ranges across chunks, on one or two threads.
TEST(LazFile, OrbisWrittenLazReadsBackExactly) {
    const std::vector<LasPoint> pts = variedPoints(12345);
    for (uint8_t format : {6, 7, 8}) {
        SCOPED_TRACE(int(format));
        LasWriteOptions o;
        o.versionMinor = 4;
        o.pointFormat = format;
        o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
        o.extraBytes = format == 8 ? 3 : 0;
        o.laz = true;
        o.lazChunkPoints = 5000;
        const std::string las = (tempDir() / ("plain-" + std::to_string(format) + ".las")).string();
        const std::string lazPath = (tempDir() / ("written-" + std::to_string(format) + ".laz")).string();
        for (const std::string& path : {las, lazPath}) {
            o.laz = path == lazPath;
            auto w = LasWriter::create(path, o);
            ASSERT_TRUE(w.ok()) << w.message();
            (*w)->write(std::span<const LasPoint>(pts).first(10000));
            (*w)->write(std::span<const LasPoint>(pts).subspan(10000));
            auto closed = (*w)->close();
            ASSERT_TRUE(closed.ok()) << closed.message();
        }
        const std::vector<LasPoint> twin = readAll(las);
        ASSERT_EQ(twin.size(), pts.size());
        auto f = LasFile::open(lazPath);
        ASSERT_TRUE(f.ok()) << f.message();
        EXPECT_EQ((*f)->header().compression, "LAZ (LASzip 3.4r3, layered chunked, 3 chunks)");
        EXPECT_LT(fs::file_size(lazPath), fs::file_size(las));
        for (unsigned threads : {1u, 2u}) {
            (*f)->setDecodeThreads(threads);
            std::vector<LasPoint> back;
            ASSERT_TRUE((*f)->read(0, UINT64_MAX, back).ok());
            ASSERT_EQ(back.size(), twin.size());
            for (size_t i = 0; i < back.size(); ++i) {
                expectSamePoint(back[i], twin[i], "point " + std::to_string(i));
                if (format == 8) {
                    ASSERT_EQ(back[i].nir, twin[i].nir);
                }
                if (HasFailure()) return;
            }
            ASSERT_TRUE((*f)->read(4990, 20, back).ok());   // across a chunk's edge
            ASSERT_EQ(back.size(), 20u);
            EXPECT_EQ(back[19].gpsTime, twin[5009].gpsTime);
            std::vector<glm::dvec3> xyz;   // positions alone skip the other layers
            ASSERT_TRUE((*f)->readPositions(9000, 5000, xyz).ok());
            ASSERT_EQ(xyz.size(), 3345u);
            for (size_t i = 0; i < xyz.size(); ++i) ASSERT_EQ(xyz[i], twin[9000 + i].position);
        }
    }
    // Formats without a version 3 coder in Orbis's writer are refused by name.
    LasWriteOptions o;
    o.versionMinor = 4;
    o.pointFormat = 3;
    o.laz = true;
    auto w = LasWriter::create((tempDir() / "format3.laz").string(), o);
    ASSERT_FALSE(w.ok());
    EXPECT_NE(w.message().find("formats 6, 7 and 8"), std::string::npos) << w.message();
}

}  // namespace
}  // namespace orbis::points

namespace orbis::points {
namespace {

// The COPC twin (LAZ 1.4, format 7, layered chunks written by a COPC writer, one chunk per
// octree node) holds the LAS file's points reordered: equal as a set, field by field.
TEST(LazFile, CopcTwinHoldsTheSamePointsAsASet) {
    if (!fs::exists(lidar("1.2-with-color.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    std::vector<LasPoint> twin = readAll(lidar("1.2-with-color.las").string());
    std::vector<LasPoint> copc = readAll(lidar("1.2-with-color.copc.laz").string());
    ASSERT_EQ(copc.size(), twin.size());
    const auto order = [](const LasPoint& a, const LasPoint& b) {   // by the centimetre grid both files hold
        const auto key = [](const LasPoint& p) { return std::make_tuple(std::llround(p.position.x * 100), std::llround(p.position.y * 100), std::llround(p.position.z * 100), p.gpsTime); };
        return key(a) < key(b);
    };
    std::sort(twin.begin(), twin.end(), order);
    std::sort(copc.begin(), copc.end(), order);
    for (size_t i = 0; i < copc.size(); ++i) {
        expectSamePoint(copc[i], twin[i], "point " + std::to_string(i), 1e-6);
        if (HasFailure()) return;
    }
}

// lone-star.copc.laz (format 6, 518 862 points in 15 chunks of different sizes): every chunk
// decodes, the points lie in the header's bounds, positions alone equal the full decode's.
TEST(LazFile, LoneStarDecodesEveryChunkInsideItsBounds) {
    if (!fs::exists(lidar("lone-star.copc.laz"))) GTEST_SKIP() << "../shared/data is absent";
    auto f = LasFile::open(lidar("lone-star.copc.laz").string());
    ASSERT_TRUE(f.ok()) << f.message();
    const LasHeader& h = (*f)->header();
    EXPECT_EQ(h.pointFormat, 6);
    EXPECT_EQ(h.pointCount, 518862u);
    EXPECT_EQ(h.compression, "LAZ (LASzip 3.4r3, layered chunked, 15 chunks)");
    std::vector<LasPoint> pts;
    ASSERT_TRUE((*f)->read(0, UINT64_MAX, pts).ok());
    ASSERT_EQ(pts.size(), 518862u);
    std::vector<glm::dvec3> xyz;
    ASSERT_TRUE((*f)->readPositions(0, UINT64_MAX, xyz).ok());
    ASSERT_EQ(xyz.size(), pts.size());
    size_t outside = 0, differ = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3 p = pts[i].position, slack = h.scale;
        outside += glm::any(glm::lessThan(p, h.min - slack)) || glm::any(glm::greaterThan(p, h.max + slack));
        differ += xyz[i] != p;
    }
    EXPECT_EQ(outside, 0u);
    EXPECT_EQ(differ, 0u);
}

}  // namespace
}  // namespace orbis::points
