// LAS reading, the parts LasFileTest.cpp leaves out: the CRS lookup (GeoTIFF unit and vertical
// keys, user-defined keys, sidecar order, WKT in an EVLR), feet and US survey feet against known
// coordinates, the writer's header fields, and more headers that lie (LASzip VLR, VLRs past the
// points, offsets inside the header, reads past the end).
#include "globe/Ellipsoid.h"
#include "layers/points/LasReader.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

namespace orbis::points {
namespace {

namespace fs = std::filesystem;

fs::path tempDir() { return test::processTempDir("orbis-lasreader"); }

std::vector<LasPoint> threePoints(glm::dvec3 origin) {
    std::vector<LasPoint> pts(3);
    for (size_t i = 0; i < pts.size(); ++i) {
        pts[i].position = origin + glm::dvec3(10.0 * double(i), 5.0 * double(i), 1.0 * double(i));
        pts[i].returnNumber = pts[i].numberOfReturns = 1;
        pts[i].classification = 2;
    }
    return pts;
}

std::string writeLas(const std::string& name, const LasWriteOptions& o, const std::vector<LasPoint>& pts) {
    const std::string path = (tempDir() / name).string();
    auto w = LasWriter::create(path, o);
    EXPECT_TRUE(w.ok()) << (w.ok() ? "" : w.message());
    if (!w) return path;
    (*w)->write(pts);
    const auto closed = (*w)->close();
    EXPECT_TRUE(closed.ok()) << (closed.ok() ? "" : closed.message());
    return path;
}

std::vector<char> bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

template <typename T>
void poke(std::vector<char>& b, size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof(T));
}

template <typename T>
T peek(const std::vector<char>& b, size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof(T));
    return v;
}

/// One point through the file's own CRS to longitude, latitude (degrees) and ellipsoidal height.
globe::Geodetic place(const LasFile& f, glm::dvec3 xyz) {
    auto g = LasGeoreference::create(f.crs().wkt, f.path());
    EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.message());
    if (!g) return {};
    std::vector<glm::dvec3> one{xyz};
    EXPECT_EQ(g->toEcef(one), 0u);
    return globe::Ellipsoid::wgs84().toGeodetic(one[0]);
}

constexpr double kUsFoot = 1200.0 / 3937.0;

// Reference values below come from GDAL's gdaltransform (PROJ) on this machine, and are checked
// against OGR directly where the test can: 1e-8 degrees is about a millimetre.
TEST(LasReader, UsSurveyFeetConvertAgainstAKnownPoint) {
    // EPSG:2227, NAD83 / California zone 3 (ftUS): (6 000 000, 2 000 000) ftUS is
    // lon -122.435572841825, lat 37.4716177057708 (gdaltransform -s_srs EPSG:2227 -t_srs EPSG:4326).
    auto g = LasGeoreference::create("EPSG:2227", "test");
    ASSERT_TRUE(g.ok()) << g.message();
    EXPECT_DOUBLE_EQ(g->linearUnitMetres(), kUsFoot);
    EXPECT_DOUBLE_EQ(g->verticalUnitMetres(), kUsFoot);   // horizontal only: heights in its unit
    std::vector<glm::dvec3> xyz{{6000000.0, 2000000.0, 100.0}};
    ASSERT_EQ(g->toEcef(xyz), 0u);
    const globe::Geodetic geo = globe::Ellipsoid::wgs84().toGeodetic(xyz[0]);
    EXPECT_NEAR(geo.lonDeg, -122.435572841825, 1e-8);
    EXPECT_NEAR(geo.latDeg, 37.4716177057708, 1e-8);
    EXPECT_NEAR(geo.height, 100.0 * kUsFoot, 1e-4);   // 100 ftUS = 30.48006 m

    // The same through OGR directly, to EPSG:4979 with the heights already in metres.
    OGRSpatialReference src, dst;
    ASSERT_EQ(src.importFromEPSG(2227), OGRERR_NONE);
    ASSERT_EQ(dst.importFromEPSG(4979), OGRERR_NONE);
    src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformation* ct = OGRCreateCoordinateTransformation(&src, &dst);
    ASSERT_NE(ct, nullptr);
    double x = 6000000.0, y = 2000000.0, z = 100.0 * kUsFoot;
    EXPECT_TRUE(ct->Transform(1, &x, &y, &z));
    OGRCoordinateTransformation::DestroyCT(ct);
    EXPECT_NEAR(geo.lonDeg, x, 1e-9);
    EXPECT_NEAR(geo.latDeg, y, 1e-9);
    EXPECT_NEAR(geo.height, z, 1e-4);
}

TEST(LasReader, RealOregonFileLandsWhereGdalPutsIt) {
    const fs::path file = fs::path(ORBIS_SHARED_DATA_DIR) / "lidar/1.2-with-color.las";
    if (!fs::exists(file)) GTEST_SKIP() << "../shared/data is absent";
    auto f = LasFile::open(file.string());
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "sidecar " + fs::weakly_canonical(file.string() + ".wkt").string());
    // The header and first record as a byte dump of the file shows them (struct.unpack).
    const LasHeader& h = (*f)->header();
    EXPECT_EQ(h.software, "TerraScan");
    EXPECT_EQ(h.pointOffset, 229u);   // a 227-byte header and 2 bytes of padding, no VLRs
    EXPECT_EQ(h.extraBytes, 0);
    const std::array<uint64_t, 5> byReturn{925, 114, 21, 5, 0};
    for (size_t i = 0; i < byReturn.size(); ++i) EXPECT_EQ(h.pointsByReturn[i], byReturn[i]) << "return " << i + 1;
    EXPECT_DOUBLE_EQ(h.scale.x, 0.01);
    EXPECT_DOUBLE_EQ(h.max.x, 638982.55);
    EXPECT_DOUBLE_EQ(h.min.y, 848899.70);
    EXPECT_DOUBLE_EQ(h.max.z, 586.38);
    std::vector<LasPoint> pts;
    EXPECT_TRUE((*f)->read(0, (*f)->points(), pts).ok());
    ASSERT_EQ(pts.size(), 1065u);
    const LasPoint& p = pts[0];
    EXPECT_EQ(p.returnNumber, 1);
    EXPECT_EQ(p.numberOfReturns, 1);
    EXPECT_EQ(p.scanAngleDeg, -9.0f);
    EXPECT_EQ(p.userData, 132);
    EXPECT_EQ(p.pointSourceId, 7326);
    EXPECT_DOUBLE_EQ(p.gpsTime, 245380.78254962614);
    std::array<uint64_t, 5> counted{};
    for (const LasPoint& q : pts) {   // inside the header's box, and the counts by return agree
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(q.position, h.min - 1e-9)) && glm::all(glm::lessThanEqual(q.position, h.max + 1e-9)));
        if (q.returnNumber >= 1 && q.returnNumber <= 5) ++counted[q.returnNumber - 1u];
    }
    EXPECT_EQ(counted, byReturn);
    // The first point (637012.24, 849028.31) international ft: gdaltransform with the sidecar
    // gives lon -123.069549792672, lat 44.0502429401301 (Eugene, Oregon).
    const globe::Geodetic geo = place(**f, {637012.24, 849028.31, 431.66});
    EXPECT_NEAR(geo.lonDeg, -123.069549792672, 1e-8);
    EXPECT_NEAR(geo.latDeg, 44.0502429401301, 1e-8);
    EXPECT_NEAR(geo.height, 431.66 * 0.3048, 1e-4);
    // Every point in the valley: heights 124 m to 180 m (406.59 ft to 586.38 ft in the header).
    std::vector<glm::dvec3> xyz;
    EXPECT_TRUE((*f)->readPositions(0, (*f)->points(), xyz).ok());
    auto g = LasGeoreference::create((*f)->crs().wkt, "sidecar");
    ASSERT_TRUE(g.ok());
    EXPECT_EQ(g->toEcef(xyz), 0u);
    for (const glm::dvec3& p : xyz) {
        const globe::Geodetic q = globe::Ellipsoid::wgs84().toGeodetic(p);
        EXPECT_NEAR(q.lonDeg, -123.07, 0.02);
        EXPECT_NEAR(q.latDeg, 44.05, 0.02);
        EXPECT_GT(q.height, 406.59 * 0.3048 - 1e-3);
        EXPECT_LT(q.height, 586.38 * 0.3048 + 1e-3);
    }
}

TEST(LasReader, GeoTiffGeographicKeysKeepHeightsInMetres) {
    LasWriteOptions o;
    o.epsg = 4326;
    o.scale = glm::dvec3(1e-7, 1e-7, 0.001);
    auto f = LasFile::open(writeLas("geographic.las", o, threePoints({9.0, 46.0, 100.0})));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:4326)");
    const globe::Geodetic geo = place(**f, {9.0, 46.0, 100.0});
    EXPECT_NEAR(geo.lonDeg, 9.0, 1e-9);
    EXPECT_NEAR(geo.latDeg, 46.0, 1e-9);
    EXPECT_NEAR(geo.height, 100.0, 1e-6);
}

TEST(LasReader, ProjLinearUnitsKeyOverridesTheCodesUnit) {
    // NAD83 / UTM 10N is in metres; the file says its coordinates are US survey feet (9003).
    // (500 000 m, 4 000 000 m) is lon -123, lat 36.1447181 (gdaltransform).
    LasWriteOptions o;
    o.epsg = 26910;
    o.linearUnits = 9003;
    o.offset = glm::dvec3(1640000.0, 13123000.0, 0.0);
    const glm::dvec3 feet{500000.0 / kUsFoot, 4000000.0 / kUsFoot, 100.0};
    auto f = LasFile::open(writeLas("utm-ftus.las", o, threePoints(feet)));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:26910 in US survey foot)");
    const globe::Geodetic geo = place(**f, feet);
    EXPECT_NEAR(geo.lonDeg, -123.0, 1e-8);
    EXPECT_NEAR(geo.latDeg, 36.1447181, 1e-7);
    EXPECT_NEAR(geo.height, 100.0 * kUsFoot, 1e-4);   // horizontal only: heights in its unit too
}

TEST(LasReader, VerticalKeysMakeACompoundCrs) {
    // 26910 + NAVD88 height (5703), metres: heights pass through (no geoid grid installed, so
    // PROJ's ballpark vertical transformation: the height stays 100 m).
    LasWriteOptions o;
    o.epsg = 26910;
    o.verticalEpsg = 5703;
    o.offset = glm::dvec3(500000.0, 4000000.0, 0.0);
    auto f = LasFile::open(writeLas("compound.las", o, threePoints({500000.0, 4000000.0, 100.0})));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:26910 + EPSG:5703)");
    EXPECT_NE((*f)->crs().wkt.find("NAVD88"), std::string::npos) << (*f)->crs().wkt;
    globe::Geodetic geo = place(**f, {500000.0, 4000000.0, 100.0});
    EXPECT_NEAR(geo.lonDeg, -123.0, 1e-8);
    EXPECT_NEAR(geo.height, 100.0, 1e-3);

    // The same in feet (VerticalUnitsGeoKey 9002).
    o.verticalUnits = 9002;
    f = LasFile::open(writeLas("compound-ft.las", o, threePoints({500000.0, 4000000.0, 100.0})));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:26910 + EPSG:5703 in foot)");
    auto g = LasGeoreference::create((*f)->crs().wkt, "compound");
    ASSERT_TRUE(g.ok()) << g.message();
    EXPECT_DOUBLE_EQ(g->verticalUnitMetres(), 0.3048);
    geo = place(**f, {500000.0, 4000000.0, 100.0});
    EXPECT_NEAR(geo.height, 30.48, 1e-3);

    // Feet horizontally, metres vertically, no vertical CRS: heights are not scaled.
    o = LasWriteOptions{};
    o.epsg = 2227;
    o.verticalUnits = 9001;
    o.offset = glm::dvec3(6000000.0, 2000000.0, 0.0);
    f = LasFile::open(writeLas("ftus-metre-heights.las", o, threePoints({6000000.0, 2000000.0, 100.0})));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:2227, heights in metre)");
    geo = place(**f, {6000000.0, 2000000.0, 100.0});
    EXPECT_NEAR(geo.lonDeg, -122.435572841825, 1e-8);
    EXPECT_NEAR(geo.height, 100.0, 1e-3);
}

TEST(LasReader, UserDefinedKeysLeaveTheCrsEmptyUntilASidecarGivesIt) {
    LasWriteOptions o;
    o.epsg = 32767;   // GeoTIFF "user-defined": the projection is in keys we do not interpret
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    const std::string path = writeLas("user.las", o, threePoints({500000.0, 5100000.0, 0.0}));
    auto f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_TRUE((*f)->crs().wkt.empty());
    EXPECT_NE((*f)->crs().source.find("user-defined projection"), std::string::npos) << (*f)->crs().source;
    EXPECT_NE((*f)->crs().source.find("sidecar"), std::string::npos) << (*f)->crs().source;

    const fs::path prj = tempDir() / "user.prj";
    std::ofstream(prj) << "EPSG:32632\n";
    f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().wkt, "EPSG:32632");
    EXPECT_EQ((*f)->crs().source, "sidecar " + fs::weakly_canonical(prj).string());
    fs::remove(prj);
}

TEST(LasReader, SidecarsAreTriedInOrder) {
    const std::string path = writeLas("side.las", {}, threePoints({0.0, 0.0, 0.0}));
    const fs::path dir = tempDir();
    std::ofstream(dir / "side.prj") << "EPSG:3";
    std::ofstream(dir / "side.wkt") << "EPSG:2\n\n";
    auto f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().wkt, "EPSG:2");   // stem.wkt before stem.prj, trailing blanks trimmed
    std::ofstream(dir / "side.las.wkt") << "EPSG:1";
    f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().wkt, "EPSG:1");   // path.wkt first
    EXPECT_EQ((*f)->crs().source, "sidecar " + fs::weakly_canonical(dir / "side.las.wkt").string());
}

TEST(LasReader, EvlrsAreListedAndTheirWktIsFound) {
    LasWriteOptions o;
    o.versionMinor = 4;
    o.pointFormat = 7;
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    const std::string path = writeLas("evlr.las", o, threePoints({500000.0, 5100000.0, 10.0}));
    std::vector<char> b = bytesOf(path);
    const std::string wkt = "EPSG:32632";
    std::array<char, 60> head{};   // LAS 1.4 R15 Table 17: the EVLR header
    std::memcpy(head.data() + 2, "LASF_Projection", 15);
    const uint16_t id = 2112;
    const uint64_t length = wkt.size() + 1;
    std::memcpy(head.data() + 18, &id, 2);
    std::memcpy(head.data() + 20, &length, 8);
    std::memcpy(head.data() + 28, "OGC WKT", 7);
    std::vector<char> evlr(head.begin(), head.end());
    evlr.insert(evlr.end(), wkt.c_str(), wkt.c_str() + wkt.size() + 1);
    poke<uint64_t>(b, 235, b.size());   // start of the first EVLR
    poke<uint32_t>(b, 243, 1);
    b.insert(b.end(), evlr.begin(), evlr.end());
    writeBytes(path, b);
    auto f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    ASSERT_EQ((*f)->header().vlrs.size(), 1u);
    const LasVlr& v = (*f)->header().vlrs[0];
    EXPECT_TRUE(v.extended);
    EXPECT_EQ(v.userId, "LASF_Projection");
    EXPECT_EQ(v.recordId, 2112);
    EXPECT_EQ(v.length, wkt.size() + 1);
    EXPECT_EQ(v.description, "OGC WKT");
    EXPECT_EQ((*f)->crs().source, "WKT VLR");
    EXPECT_EQ((*f)->crs().wkt, wkt);
    EXPECT_EQ((*f)->points(), 3u);

    // An EVLR that starts inside the points, or runs past the end, is an error naming the file.
    poke<uint64_t>(b, 235, 400);
    writeBytes(path, b);
    auto inside = LasFile::open(path);
    ASSERT_FALSE(inside.ok());
    EXPECT_NE(inside.message().find("evlr.las"), std::string::npos) << inside.message();
    EXPECT_NE(inside.message().find("extended variable-length record"), std::string::npos) << inside.message();
    poke<uint64_t>(b, 235, b.size() - evlr.size());
    poke<uint64_t>(b, b.size() - evlr.size() + 20, uint64_t(1) << 62);
    writeBytes(path, b);
    auto past = LasFile::open(path);
    ASSERT_FALSE(past.ok());
    EXPECT_NE(past.message().find("past the end"), std::string::npos) << past.message();
}

TEST(LasReader, WriterHeadersFollowTheVersion) {
    LasWriteOptions o;
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    const auto pts = threePoints({500000.0, 5100000.0, 0.0});
    // LAS 1.4 format 6: legacy counts 0, the 64-bit ones filled, WKT bit set with a WKT VLR.
    o.versionMinor = 4;
    o.pointFormat = 6;
    o.wkt = "EPSG:32632";
    std::vector<char> b = bytesOf(writeLas("h14.las", o, pts));
    ASSERT_GE(b.size(), 375u);
    EXPECT_EQ(peek<uint16_t>(b, 94), 375);
    EXPECT_EQ(peek<uint16_t>(b, 6) & 16, 16);   // global encoding bit 4: the CRS is WKT
    EXPECT_EQ(peek<uint32_t>(b, 107), 0u);
    EXPECT_EQ(peek<uint32_t>(b, 111), 0u);
    EXPECT_EQ(peek<uint64_t>(b, 247), 3u);
    EXPECT_EQ(peek<uint64_t>(b, 255), 3u);   // all first returns
    EXPECT_EQ(peek<uint16_t>(b, 105), 30);
    // LAS 1.3 format 4: 235-byte header, legacy counts, wave packet fields in a 57-byte record.
    o.versionMinor = 3;
    o.pointFormat = 4;
    o.wkt.clear();
    b = bytesOf(writeLas("h13.las", o, pts));
    EXPECT_EQ(peek<uint16_t>(b, 94), 235);
    EXPECT_EQ(peek<uint32_t>(b, 107), 3u);
    EXPECT_EQ(peek<uint16_t>(b, 105), 57);
    EXPECT_EQ(b.size(), 235u + 3u * 57u);
    // LAS 1.0 with GeoTIFF keys: the VLR carries the 1.0 record signature 0xAABB, and reads back.
    o.versionMinor = 0;
    o.pointFormat = 1;
    o.epsg = 32632;
    const std::string path = writeLas("h10.las", o, pts);
    b = bytesOf(path);
    EXPECT_EQ(peek<uint16_t>(b, 94), 227);
    EXPECT_EQ(peek<uint16_t>(b, 227), 0xAABB);
    auto f = LasFile::open(path);
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->crs().source, "GeoTIFF keys (EPSG:32632)");
    EXPECT_NEAR((*f)->header().max.x, 500020.0, 1e-9);
    EXPECT_NEAR((*f)->header().max.z, 2.0, 1e-9);
}

TEST(LasReader, WideExtraBytesAreSkipped) {
    LasWriteOptions o;
    o.pointFormat = 0;
    o.extraBytes = 1000;
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    auto pts = threePoints({500000.0, 5100000.0, 0.0});
    pts[2].intensity = 4242;
    auto f = LasFile::open(writeLas("extra.las", o, pts));
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_EQ((*f)->header().recordLength, 1020);
    EXPECT_EQ((*f)->header().extraBytes, 1000);
    std::vector<LasPoint> back;
    EXPECT_TRUE((*f)->read(1, 5, back).ok());
    ASSERT_EQ(back.size(), 2u);
    EXPECT_NEAR(back[1].position.x, 500020.0, 0.0005);   // within scale / 2
    EXPECT_EQ(back[1].intensity, 4242);
}

TEST(LasReader, ReadsPastTheEndAllocateNothing) {
    auto f = LasFile::open(writeLas("ends.las", {}, threePoints({0.0, 0.0, 0.0})));
    ASSERT_TRUE(f.ok()) << f.message();
    std::vector<LasPoint> pts(7);
    EXPECT_TRUE((*f)->read(3, UINT64_MAX, pts).ok());   // replaced, not appended
    EXPECT_TRUE(pts.empty());
    EXPECT_TRUE((*f)->read(UINT64_MAX, UINT64_MAX, pts).ok());
    EXPECT_TRUE(pts.empty());
    std::vector<glm::dvec3> xyz;
    EXPECT_TRUE((*f)->readPositions(1, UINT64_MAX, xyz).ok());
    EXPECT_EQ(xyz.size(), 2u);
    EXPECT_LE(xyz.capacity(), 3u);
}

/// A valid file (one GeoTIFF VLR, 3 points) with `patch` applied, for the error cases below.
std::string broken(const std::string& name, const std::function<void(std::vector<char>&)>& patch) {
    LasWriteOptions o;
    o.epsg = 32632;
    o.offset = glm::dvec3(500000.0, 5100000.0, 0.0);
    const std::string path = writeLas(name, o, threePoints({500000.0, 5100000.0, 0.0}));
    std::vector<char> b = bytesOf(path);
    patch(b);
    writeBytes(path, b);
    return path;
}

TEST(LasReader, MoreLyingHeadersGiveClearErrors) {
    struct Case {
        const char* name;
        std::function<void(std::vector<char>&)> patch;
        const char* says;
    };
    const Case cases[] = {
        {"laszip-vlr.las",
         [](std::vector<char>& b) {
             std::memset(b.data() + 227 + 2, 0, 16);
             std::memcpy(b.data() + 227 + 2, "laszip encoded", 14);
             poke<uint16_t>(b, 227 + 18, 22204);
         },
         "the laszip VLR is 24 bytes, shorter than its 34-byte header"},   // another VLR renamed: a clear refusal
        {"compressed-bit.las", [](std::vector<char>& b) { b[104] = char(0x83); }, "marks the file compressed (LAZ) but it has no"},
        {"vlr-too-long.las", [](std::vector<char>& b) { poke<uint16_t>(b, 227 + 20, 60000); }, "runs past the start of the point data"},
        {"too-many-vlrs.las", [](std::vector<char>& b) { poke<uint32_t>(b, 100, 1000000); }, "runs past the start of the point data"},
        {"offset-in-header.las", [](std::vector<char>& b) { poke<uint32_t>(b, 96, 100); }, "inside the 227-byte header"},
        {"offset-past-eof.las", [](std::vector<char>& b) { poke<uint32_t>(b, 96, 0xFFFFFFF0u); }, "past the end of the file"},
        {"header-size.las", [](std::vector<char>& b) { b[25] = 4; }, "header size 227 is wrong for LAS 1.4"},
        {"version-2.las", [](std::vector<char>& b) { b[24] = 2; }, "LAS version 2.2 is not supported"},
        {"nan-offset.las", [](std::vector<char>& b) { poke<double>(b, 163, std::nan("")); }, "offset of axis y"},
        {"count-plus-one.las", [](std::vector<char>& b) { poke<uint32_t>(b, 107, 4); }, "declares 4 points"},
    };
    for (const Case& c : cases) {
        auto f = LasFile::open(broken(c.name, c.patch));
        ASSERT_FALSE(f.ok()) << c.name;
        EXPECT_NE(f.message().find(c.name), std::string::npos) << f.message();
        EXPECT_NE(f.message().find(c.says), std::string::npos) << c.name << ": " << f.message();
    }
    // The bytes decide, not the name: a LAS file called .laz reads as LAS; a missing file says so.
    const fs::path laz = tempDir() / "renamed.laz";
    fs::copy_file(broken("plain.las", [](std::vector<char>&) {}), laz, fs::copy_options::overwrite_existing);
    auto f = LasFile::open(laz.string());
    ASSERT_TRUE(f.ok()) << f.message();
    EXPECT_FALSE((*f)->compressed());
    f = LasFile::open((tempDir() / "absent.las").string());
    ASSERT_FALSE(f.ok());
    EXPECT_NE(f.message().find("absent.las: cannot open"), std::string::npos) << f.message();
}

TEST(LasReader, GeoreferenceErrorsNameTheirInput) {
    auto bad = LasGeoreference::create("PROJCS[\"broken", "cloud.las (CRS from WKT VLR)");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.message().find("cloud.las (CRS from WKT VLR)"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("PROJCS[\"broken"), std::string::npos) << bad.message();
    // Points the transformation cannot place become NaN and are counted; the others still convert.
    auto g = LasGeoreference::create("EPSG:4326", "test");
    ASSERT_TRUE(g.ok()) << g.message();
    std::vector<glm::dvec3> xyz{{9.0, 46.0, 0.0}, {9.0, 1000.0, 0.0}, {std::nan(""), 0.0, 0.0}};
    EXPECT_EQ(g->toEcef(xyz), 2u);
    EXPECT_TRUE(std::isfinite(xyz[0].x));
    EXPECT_TRUE(std::isnan(xyz[1].x));
    EXPECT_TRUE(std::isnan(xyz[2].y));
}

TEST(LasReader, OneGeoreferenceServesManyThreads) {
    auto g = LasGeoreference::create("EPSG:32632", "test");
    ASSERT_TRUE(g.ok()) << g.message();
    std::vector<glm::dvec3> expected(10000);
    for (size_t i = 0; i < expected.size(); ++i) expected[i] = {490000.0 + double(i), 5100000.0 + double(i % 97), 300.0};
    std::vector<std::vector<glm::dvec3>> results(4, expected);
    g->toEcef(expected);
    std::vector<std::thread> threads;
    for (auto& r : results) threads.emplace_back([&g, &r] { g->toEcef(r); });
    for (auto& t : threads) t.join();
    for (const auto& r : results) EXPECT_EQ(r, expected);   // bit-identical: the same transformation
}

}  // namespace
}  // namespace orbis::points
