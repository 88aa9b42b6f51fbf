// LAS reading: every version and point format round-trips through the writer, the real file
// in ../shared/data/lidar (CRS only in a sidecar, Oregon Lambert in international feet), and
// headers that lie about the file give errors without allocating.
#include "globe/Ellipsoid.h"
#include "layers/points/LasReader.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace orbis::points {
namespace {

std::filesystem::path tempDir() { return test::processTempDir("orbis-las"); }

std::string write(const std::string& name, const std::vector<LasPoint>& pts, const LasWriteOptions& o) {
    const std::string path = (tempDir() / name).string();
    auto w = LasWriter::create(path, o);
    EXPECT_TRUE(w.ok()) << (w.ok() ? "" : w.message());
    if (!w) return path;
    (*w)->write(pts);
    auto closed = (*w)->close();
    EXPECT_TRUE(closed.ok()) << (closed.ok() ? "" : closed.message());
    return path;
}

/// Options whose scale and offset hold samplePoints().
LasWriteOptions utm() {
    LasWriteOptions o;
    o.offset = glm::dvec3(500000.0, 5000000.0, 0.0);
    return o;
}

std::vector<LasPoint> samplePoints(uint8_t format) {
    std::vector<LasPoint> pts;
    for (int i = 0; i < 5; ++i) {
        LasPoint p;
        p.position = {500000.0 + 1.25 * i, 5100000.0 - 0.5 * i, 200.0 + 0.125 * i};
        p.intensity = uint16_t(100 * i + 7);
        p.returnNumber = uint8_t(1 + i % 3);
        p.numberOfReturns = 3;
        p.classification = uint8_t(format >= 6 ? 40 + i : 2 + i);   // > 31 only in formats 6..10
        p.flags = uint8_t(i % 2);
        p.userData = uint8_t(i);
        p.scanAngleDeg = format >= 6 ? -12.0f + 0.006f * 100 * i : float(-12 + i);
        p.pointSourceId = uint16_t(1000 + i);
        p.gpsTime = 1e5 + 0.25 * i;
        p.red = uint16_t(1000 * i), p.green = uint16_t(2000 * i), p.blue = uint16_t(3000 * i), p.nir = uint16_t(400 * i);
        pts.push_back(p);
    }
    return pts;
}

TEST(LasFile, EveryVersionAndFormatRoundTrips) {
    for (uint8_t minor = 0; minor <= 4; ++minor)
        for (uint8_t format = 0; format <= 10; ++format) {
            // The formats each version defines.
            if ((format >= 2 && minor < 2) || (format >= 4 && minor < 3) || (format >= 6 && minor < 4)) continue;
            LasWriteOptions o;
            o.versionMinor = minor;
            o.pointFormat = format;
            o.extraBytes = 5;
            o.scale = glm::dvec3(0.01, 0.01, 0.001);
            o.offset = glm::dvec3(500000.0, 5000000.0, 0.0);
            const auto pts = samplePoints(format);
            const std::string path = write("v1" + std::to_string(minor) + "f" + std::to_string(format) + ".las", pts, o);
            auto f = LasFile::open(path);
            ASSERT_TRUE(f.ok()) << f.message();
            const LasHeader& h = (*f)->header();
            SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
            EXPECT_EQ(h.versionMinor, minor);
            EXPECT_EQ(h.pointFormat, format);
            EXPECT_EQ(h.extraBytes, 5);
            EXPECT_EQ(h.pointCount, pts.size());
            EXPECT_EQ(h.pointsByReturn[0], 2u);
            EXPECT_NEAR(h.min.x, 500000.0, 1e-9);
            EXPECT_NEAR(h.max.x, 500005.0, 1e-9);
            std::vector<LasPoint> back;
            EXPECT_TRUE((*f)->read(0, 100, back).ok());
            ASSERT_EQ(back.size(), pts.size());
            for (size_t i = 0; i < pts.size(); ++i) {
                const LasPoint &a = pts[i], &b = back[i];
                EXPECT_LE(glm::length(a.position - b.position), 0.006);
                EXPECT_EQ(a.intensity, b.intensity);
                EXPECT_EQ(a.returnNumber, b.returnNumber);
                EXPECT_EQ(a.numberOfReturns, b.numberOfReturns);
                EXPECT_EQ(a.classification, b.classification);
                EXPECT_EQ(a.flags, b.flags);
                EXPECT_EQ(a.userData, b.userData);
                EXPECT_NEAR(a.scanAngleDeg, b.scanAngleDeg, 0.01);
                EXPECT_EQ(a.pointSourceId, b.pointSourceId);
                EXPECT_EQ(b.gpsTime, h.hasGpsTime() ? a.gpsTime : 0.0);
                EXPECT_EQ(b.red, h.hasRgb() ? a.red : 0);
                EXPECT_EQ(b.blue, h.hasRgb() ? a.blue : 0);
                EXPECT_EQ(b.nir, h.hasNir() ? a.nir : 0);
            }
            std::vector<glm::dvec3> xyz;
            EXPECT_TRUE((*f)->readPositions(3, 10, xyz).ok());   // clamped to the file
            ASSERT_EQ(xyz.size(), 2u);
            EXPECT_EQ(xyz[0], back[3].position);
        }
}

TEST(LasFile, RealFileWithItsCrsInASidecar) {
    const std::filesystem::path file = std::filesystem::path(ORBIS_SHARED_DATA_DIR) / "lidar/1.2-with-color.las";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    auto f = LasFile::open(file.string());
    ASSERT_TRUE(f.ok()) << f.message();
    const LasHeader& h = (*f)->header();
    EXPECT_EQ(h.versionMinor, 2);
    EXPECT_EQ(h.pointFormat, 3);
    EXPECT_EQ(h.recordLength, 34);
    EXPECT_EQ(h.pointCount, 1065u);
    EXPECT_TRUE(h.vlrs.empty());
    EXPECT_NEAR(h.min.x, 635619.85, 1e-6);
    EXPECT_NEAR(h.max.y, 853535.43, 1e-6);
    EXPECT_NEAR(h.min.z, 406.59, 1e-6);
    EXPECT_NE((*f)->crs().source.find("sidecar"), std::string::npos) << (*f)->crs().source;
    EXPECT_NE((*f)->crs().wkt.find("Oregon"), std::string::npos);
    std::vector<LasPoint> pts;
    EXPECT_TRUE((*f)->read(0, 2000, pts).ok());
    ASSERT_EQ(pts.size(), 1065u);
    EXPECT_NEAR(pts[0].position.x, 637012.24, 1e-6);
    EXPECT_NEAR(pts[0].position.y, 849028.31, 1e-6);
    EXPECT_NEAR(pts[0].position.z, 431.66, 1e-6);
    EXPECT_EQ(pts[0].intensity, 143);
    EXPECT_EQ(pts[0].classification, 1);
    EXPECT_EQ(pts[0].red, 68);
    EXPECT_EQ(pts[0].green, 77);
    EXPECT_EQ(pts[0].blue, 88);
    EXPECT_NEAR(pts[0].gpsTime, 245380.78255, 1e-5);
    for (const LasPoint& p : pts) {   // every point inside the header's bounds
        EXPECT_GE(p.position.x, h.min.x - 1e-6);
        EXPECT_LE(p.position.z, h.max.z + 1e-6);
    }
    // International feet: heights too (the CRS is horizontal only), so 431.66 ft = 131.57 m.
    auto g = LasGeoreference::create((*f)->crs().wkt, "sidecar");
    ASSERT_TRUE(g.ok()) << g.message();
    EXPECT_DOUBLE_EQ(g->linearUnitMetres(), 0.3048);
    std::vector<glm::dvec3> xyz{pts[0].position};
    EXPECT_EQ(g->toEcef(xyz), 0u);
    const globe::Geodetic geo = globe::Ellipsoid::wgs84().toGeodetic(xyz[0]);
    EXPECT_NEAR(geo.lonDeg, -123.06955, 1e-4);   // Eugene, Oregon
    EXPECT_NEAR(geo.latDeg, 44.05024, 1e-4);
    EXPECT_NEAR(geo.height, 431.66 * 0.3048, 0.05);
}

// A file changed under a loaded cloud: cut short in place, reads of the points it lost fail
// with the file named and its size now (no SIGBUS, as a mapping would give); replaced by a
// rename (how tools write), the open file keeps reading what it opened.
TEST(LasFile, FileChangedWhileLoadedGivesAClearErrorNotACrash) {
    std::vector<LasPoint> many;
    for (int k = 0; k < 200; ++k)
        for (const LasPoint& p : samplePoints(3)) many.push_back(p);
    LasWriteOptions o = utm();
    o.pointFormat = 3;
    const std::string path = write("changing.las", many, o);
    auto f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    std::vector<LasPoint> pts;
    ASSERT_TRUE((*f)->read(0, 1000, pts).ok());
    std::filesystem::resize_file(path, 4096);   // another program rewrites it in place
    auto cut = (*f)->read(0, 1000, pts);
    ASSERT_FALSE(cut.ok());
    EXPECT_NE(cut.message().find(path), std::string::npos) << cut.message();
    EXPECT_NE(cut.message().find("4096 bytes"), std::string::npos) << cut.message();
    EXPECT_TRUE(pts.empty());
    std::vector<glm::dvec3> xyz;
    EXPECT_FALSE((*f)->readPositions(900, 100, xyz).ok());

    const std::string other = write("changing-2.las", many, o);
    auto g = LasFile::open(other);
    ASSERT_TRUE(g.ok()) << g.message();
    const std::string replacement = write("replacement.las", samplePoints(3), o);
    std::filesystem::rename(replacement, other);
    ASSERT_TRUE((*g)->read(0, 1000, pts).ok());
    EXPECT_EQ(pts.size(), 1000u);
    EXPECT_DOUBLE_EQ(pts[999].position.x, many[999].position.x);
}


/// A valid 3-point file with `patch` applied to its bytes.
std::string patched(const std::string& name, const std::function<void(std::vector<char>&)>& patch) {
    const std::string good = write("good-" + name, samplePoints(3), utm());
    std::ifstream in(good, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    patch(bytes);
    const std::string path = (tempDir() / name).string();
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

TEST(LasFile, LyingHeadersGiveClearErrors) {
    struct Case {
        const char* name;
        std::function<void(std::vector<char>&)> patch;
        const char* says;
    };
    const Case cases[] = {
        {"truncated.las", [](std::vector<char>& b) { b.resize(b.size() - 40); }, "truncated"},
        {"huge.las",
         [](std::vector<char>& b) {   // 10^12 points: a LAS 1.2 count is 32 bits, so use 1.4's field
             b[25] = 4;
             b.resize(std::max<size_t>(b.size(), 375));
             const uint16_t header = 375;
             std::memcpy(b.data() + 94, &header, 2);
             const uint32_t offset = 375;
             std::memcpy(b.data() + 96, &offset, 4);
             const uint64_t count = 1000000000000ull;
             std::memcpy(b.data() + 247, &count, 8);
             const uint32_t zero = 0;
             std::memcpy(b.data() + 107, &zero, 4);
         },
         "1000000000000"},
        {"format42.las", [](std::vector<char>& b) { b[104] = 42; }, "point data format 42"},
        {"short-record.las",
         [](std::vector<char>& b) {
             const uint16_t len = 20;   // format 3 needs 34
             std::memcpy(b.data() + 105, &len, 2);
         },
         "shorter"},
        {"not-las.las", [](std::vector<char>& b) { b[0] = 'X'; }, "not a LAS file"},
        {"offset.las",
         [](std::vector<char>& b) {
             const uint32_t offset = 1u << 30;
             std::memcpy(b.data() + 96, &offset, 4);
         },
         "past the end"},
        {"zero-scale.las", [](std::vector<char>& b) { std::memset(b.data() + 131, 0, 8); }, "scale"},
        {"tiny.las", [](std::vector<char>& b) { b.resize(100); }, "not a LAS file"},
    };
    for (const Case& c : cases) {
        auto f = LasFile::open(patched(c.name, c.patch));
        ASSERT_FALSE(f.ok()) << c.name;
        EXPECT_NE(f.message().find(c.name), std::string::npos) << f.message();
        EXPECT_NE(f.message().find(c.says), std::string::npos) << c.name << ": " << f.message();
    }
    EXPECT_FALSE(LasFile::open((tempDir() / "missing.las").string()).ok());
    // Zero points is a valid, empty cloud.
    auto empty = LasFile::open(write("empty.las", {}, {}));
    ASSERT_TRUE(empty.ok()) << empty.message();
    EXPECT_EQ((*empty)->points(), 0u);
    std::vector<LasPoint> none;
    EXPECT_TRUE((*empty)->read(0, 1000, none).ok());
    EXPECT_TRUE(none.empty());
}

TEST(LasFile, CrsFromWktVlrAndGeoTiffKeys) {
    LasWriteOptions o;
    o.epsg = 32632;
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    auto keys = LasFile::open(write("geokeys.las", samplePoints(3), o));
    ASSERT_TRUE(keys.ok()) << keys.message();
    EXPECT_EQ((*keys)->crs().source, "GeoTIFF keys (EPSG:32632)");
    auto g = LasGeoreference::create((*keys)->crs().wkt, "keys");
    ASSERT_TRUE(g.ok()) << g.message();
    std::vector<glm::dvec3> xyz{glm::dvec3(500000.0, 5100000.0, 100.0)};   // on zone 32's central meridian
    g->toEcef(xyz);
    const globe::Geodetic geo = globe::Ellipsoid::wgs84().toGeodetic(xyz[0]);
    EXPECT_NEAR(geo.lonDeg, 9.0, 1e-9);
    EXPECT_NEAR(geo.latDeg, 46.05, 0.01);
    EXPECT_NEAR(geo.height, 100.0, 1e-6);

    o.epsg = 0;
    o.wkt = g->name().empty() ? "" : "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
                                    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]]";
    o.versionMinor = 4;
    o.pointFormat = 6;
    auto wkt = LasFile::open(write("wkt.las", samplePoints(6), o));
    ASSERT_TRUE(wkt.ok()) << wkt.message();
    EXPECT_EQ((*wkt)->crs().source, "WKT VLR");
    EXPECT_NE((*wkt)->crs().wkt.find("WGS 84"), std::string::npos);
    ASSERT_EQ((*wkt)->header().vlrs.size(), 1u);
    EXPECT_EQ((*wkt)->header().vlrs[0].recordId, 2112);

    // No CRS at all; an unreadable CRS names its input.
    auto bare = LasFile::open(write("bare.las", samplePoints(3), utm()));
    ASSERT_TRUE(bare.ok());
    EXPECT_TRUE((*bare)->crs().wkt.empty());
    EXPECT_EQ((*bare)->crs().source, "none");
    auto bad = LasGeoreference::create("EPSG:999999", "the scene's crs");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.message().find("EPSG:999999"), std::string::npos) << bad.message();
}

TEST(LasFile, WriterRefusesCoordinatesItCannotHold) {
    std::vector<LasPoint> pts(1);
    pts[0].position = {46.0, 7.0, 0.0};
    LasWriteOptions o;
    o.scale = glm::dvec3(1e-8);   // 46 / 1e-8 does not fit in 32 bits
    auto w = LasWriter::create((tempDir() / "overflow.las").string(), o);
    ASSERT_TRUE(w.ok());
    (*w)->write(pts);
    auto closed = (*w)->close();
    ASSERT_FALSE(closed.ok());
    EXPECT_NE(closed.message().find("32 bits"), std::string::npos);
}

}  // namespace
}  // namespace orbis::points
