// The vector reader: fixtures written at test time (GeoJSON, CSV with WKT and a .prj, a
// GeoPackage in NC State Plane feet written with OGR) and the Natural Earth, Olinda and North
// Carolina files of ../shared/data/vector when present.
#include "layers/vector/FeatureClip.h"
#include "layers/vector/VectorReader.h"
#include "tests/support/HttpServer.h"
#include "tests/support/ScopedGdalConfig.h"
#include "tests/support/ProcessTempDir.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;

fs::path tempDir() {
    static const fs::path p = [] {
        fs::path d = orbis::test::processTempDir("orbis-vector-test");
        return d;
    }();
    return p;
}

struct TempCleanup : ::testing::Environment {
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(tempDir(), ec);
    }
};
[[maybe_unused]] auto* const gCleanup = ::testing::AddGlobalTestEnvironment(new TempCleanup);

fs::path writeFile(const std::string& name, const std::string& text) {
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

/// A GeoJSON FeatureCollection of the given features (each a JSON object text).
fs::path writeGeoJson(const std::string& name, const std::vector<std::string>& features) {
    std::string text = R"({"type": "FeatureCollection", "features": [)";
    for (size_t i = 0; i < features.size(); ++i) text += (i ? ",\n" : "\n") + features[i];
    return writeFile(name + ".geojson", text + "]}\n");
}

std::string feature(const std::string& geometry, const std::string& properties = "{}") {
    return R"({"type": "Feature", "properties": )" + properties + R"(, "geometry": )" + geometry + "}";
}

Result<VectorData> read(const fs::path& file, const std::string& where = "", const std::string& sql = "") {
    VectorReadOptions o;
    o.source = file.string();
    o.where = where;
    o.sql = sql;
    return readVector(o);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---------------------------------------------------------------------------------------------
// Generated fixtures

TEST(VectorReader, LineAcrossTheAntimeridianIsUnwrapped) {
    const auto file = writeGeoJson("dateline", {feature(R"({"type": "LineString", "coordinates": [[179, 0], [-179, 1]]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    ASSERT_EQ(data->layers.size(), 1u);
    const VectorLayer& layer = data->layers[0];
    EXPECT_EQ(layer.name, "dateline");
    ASSERT_EQ(layer.features.size(), 1u);
    const Feature& f = layer.features[0];
    EXPECT_EQ(f.kind, GeometryKind::Lines);
    ASSERT_EQ(f.coords.size(), 2u);
    EXPECT_DOUBLE_EQ(f.coords[0].x, 179.0);
    EXPECT_DOUBLE_EQ(f.coords[1].x, 181.0);
    EXPECT_DOUBLE_EQ(f.coords[1].y, 1.0);
    EXPECT_DOUBLE_EQ(f.bounds.west, 179.0);
    EXPECT_DOUBLE_EQ(f.bounds.east, 181.0);
    EXPECT_DOUBLE_EQ(layer.bounds.widthDeg(), 2.0);
    EXPECT_EQ(layer.crs, "EPSG:4326");
}

TEST(VectorReader, AShapeChangesOrDropsEachFeatureAsItIsReadAndTheLimitsCountWhatIsKept) {
    const auto file = writeGeoJson("shaped", {feature(R"({"type": "LineString", "coordinates": [[0, 0], [1, 0], [2, 0]]})", R"({"n": 1})"),
                                              feature(R"({"type": "LineString", "coordinates": [[0, 1], [1, 1], [2, 1]]})", R"({"n": 2})"),
                                              feature(R"({"type": "LineString", "coordinates": [[0, 2], [1, 2], [2, 2]]})", R"({"n": 3})")});
    VectorReadOptions o;
    o.source = file.string();
    int seen = 0;
    o.shape = [&seen](Feature& f) {
        ++seen;
        if (f.coords[0].y == 1.0) return false;    // dropped
        f.coords.pop_back();                       // changed: the last vertex goes
        return true;
    };
    o.limits.maxTotalVertices = 4;   // two shaped lines fit, three whole ones would not
    auto data = readVector(o);
    ASSERT_TRUE(data) << data.message();
    EXPECT_EQ(seen, 3);
    const VectorLayer& layer = data->layers[0];
    ASSERT_EQ(layer.features.size(), 2u);
    EXPECT_EQ(layer.features[0].coords.size(), 2u);
    EXPECT_EQ(layer.features[1].coords[0].y, 2.0);
    EXPECT_EQ(layer.vertexCount, 4u);
    EXPECT_TRUE(layer.warnings.empty());
}

TEST(VectorReader, PolygonWithAHoleKeepsItsRings) {
    const auto file = writeGeoJson(
        "holed", {feature(R"({"type": "Polygon", "coordinates": [[[0,0],[10,0],[10,10],[0,10],[0,0]], [[2,2],[2,4],[4,4],[4,2],[2,2]]]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const Feature& f = data->layers[0].features.at(0);
    EXPECT_EQ(f.kind, GeometryKind::Polygons);
    EXPECT_EQ(f.coords.size(), 10u);
    EXPECT_EQ(f.parts, (std::vector<uint32_t>{0, 5}));
    EXPECT_EQ(f.polygons, (std::vector<uint32_t>{0}));
    EXPECT_EQ(f.containsPole, (std::vector<int8_t>{0, 0}));
    EXPECT_EQ(f.polygonEnd(0), 2u);
    EXPECT_DOUBLE_EQ(f.coords[6].x, 2.0);
    EXPECT_DOUBLE_EQ(f.coords[6].y, 4.0);
    EXPECT_DOUBLE_EQ(f.bounds.west, 0.0);
    EXPECT_DOUBLE_EQ(f.bounds.north, 10.0);
}

TEST(VectorReader, HoleAcrossTheAntimeridianStaysInsideItsOuterRing) {
    // The outer ring starts at 179 and crosses 180; the hole lies wholly at -179.8 .. -179.2.
    const auto file = writeGeoJson(
        "dateline-hole", {feature(R"({"type": "Polygon", "coordinates": [[[179,-1],[-179,-1],[-179,1],[179,1],[179,-1]],
                                     [[-179.8,-0.5],[-179.2,-0.5],[-179.2,0.5],[-179.8,0.5],[-179.8,-0.5]]]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const Feature& f = data->layers[0].features.at(0);
    ASSERT_EQ(f.parts, (std::vector<uint32_t>{0, 5}));
    EXPECT_DOUBLE_EQ(f.coords[1].x, 181.0);
    EXPECT_NEAR(f.coords[5].x, 180.2, 1e-12);
    EXPECT_NEAR(f.coords[6].x, 180.8, 1e-12);
    EXPECT_DOUBLE_EQ(f.bounds.west, 179.0);
    EXPECT_DOUBLE_EQ(f.bounds.east, 181.0);
}

TEST(VectorReader, MultiGeometriesAndCollectionsAreFlattened) {
    const auto file = writeGeoJson(
        "multi", {feature(R"({"type": "MultiPoint", "coordinates": [[1,2],[3,4],[5,6]]})"),
                  feature(R"({"type": "MultiLineString", "coordinates": [[[0,0],[1,1]], [[2,2],[3,3],[4,4]]]})"),
                  feature(R"({"type": "MultiPolygon", "coordinates": [[[[0,0],[1,0],[1,1],[0,0]]], [[[5,5],[6,5],[6,6],[5,5]]]]})"),
                  feature(R"({"type": "GeometryCollection", "geometries": [{"type": "Point", "coordinates": [7,8]},
                             {"type": "Polygon", "coordinates": [[[0,0],[2,0],[2,2],[0,0]]]}]})",
                          R"({"name": "mixed"})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    EXPECT_EQ(layer.featuresRead, 4u);
    ASSERT_EQ(layer.features.size(), 5u);   // the mixed collection gives a point and a polygon feature
    const Feature& points = layer.features[0];
    EXPECT_EQ(points.kind, GeometryKind::Points);
    EXPECT_EQ(points.parts, (std::vector<uint32_t>{0, 1, 2}));
    const Feature& lines = layer.features[1];
    EXPECT_EQ(lines.kind, GeometryKind::Lines);
    EXPECT_EQ(lines.parts, (std::vector<uint32_t>{0, 2}));
    EXPECT_EQ(lines.coords.size(), 5u);
    const Feature& polygons = layer.features[2];
    EXPECT_EQ(polygons.polygons, (std::vector<uint32_t>{0, 1}));
    EXPECT_DOUBLE_EQ(polygons.coords[polygons.parts[1]].x, 5.0);
    const Feature& a = layer.features[3];
    const Feature& b = layer.features[4];
    EXPECT_EQ(a.fid, b.fid);
    EXPECT_EQ(a.kind, GeometryKind::Points);
    EXPECT_EQ(b.kind, GeometryKind::Polygons);
    EXPECT_EQ(std::get<std::string>(b.attributes.at(0)), "mixed");
    EXPECT_EQ(layer.vertexCount, 3u + 5u + 8u + 1u + 4u);
}

TEST(VectorReader, HeightsAreKeptAndZeroWithoutZ) {
    const auto file = writeGeoJson("heights", {feature(R"({"type": "LineString", "coordinates": [[10,20,100.5],[11,21,-3]]})"),
                                               feature(R"({"type": "Point", "coordinates": [10,20]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const auto& features = data->layers[0].features;
    ASSERT_EQ(features.size(), 2u);
    EXPECT_TRUE(features[0].hasZ);
    EXPECT_DOUBLE_EQ(features[0].coords[0].z, 100.5);
    EXPECT_DOUBLE_EQ(features[0].coords[1].z, -3.0);
    EXPECT_FALSE(features[1].hasZ);
    EXPECT_DOUBLE_EQ(features[1].coords[0].z, 0.0);
}

fs::path writeTowns() {
    return writeGeoJson("towns", {feature(R"({"type": "Point", "coordinates": [1,1]})", R"({"name": "a", "pop": 10})"),
                                  feature(R"({"type": "Point", "coordinates": [2,2]})", R"({"name": "b", "pop": 250})"),
                                  feature(R"({"type": "Point", "coordinates": [3,3]})", R"({"name": "c", "pop": 900})")});
}

TEST(VectorReader, WhereAndSqlSelectTheRightFeatures) {
    const auto file = writeTowns();
    auto where = read(file, "pop > 100");
    ASSERT_TRUE(where) << where.message();
    ASSERT_EQ(where->layers[0].features.size(), 2u);
    EXPECT_DOUBLE_EQ(where->layers[0].features[0].coords[0].x, 2.0);
    EXPECT_DOUBLE_EQ(where->layers[0].features[1].coords[0].x, 3.0);
    auto sql = read(file, "", "SELECT name FROM towns WHERE name = 'a' OR pop = 900 ORDER BY pop DESC");
    ASSERT_TRUE(sql) << sql.message();
    const VectorLayer& layer = sql->layers.at(0);
    ASSERT_EQ(layer.fields.size(), 1u);
    EXPECT_EQ(layer.fields[0].name, "name");
    EXPECT_EQ(layer.fields[0].type, "String");
    ASSERT_EQ(layer.features.size(), 2u);
    EXPECT_EQ(std::get<std::string>(layer.features[0].attributes[0]), "c");
    EXPECT_EQ(std::get<std::string>(layer.features[1].attributes[0]), "a");
}

TEST(VectorReader, BadWhereOrSqlIsAnErrorNamingIt) {
    const auto file = writeTowns();
    auto where = read(file, "pop >>> 2");
    ASSERT_FALSE(where);
    EXPECT_TRUE(contains(where.message(), file.string())) << where.message();
    EXPECT_TRUE(contains(where.message(), "\"pop >>> 2\"")) << where.message();
    EXPECT_TRUE(contains(where.message(), "towns")) << where.message();
    auto sql = read(file, "", "SELECT nothing FROM nowhere");
    ASSERT_FALSE(sql);
    EXPECT_TRUE(contains(sql.message(), "\"SELECT nothing FROM nowhere\"")) << sql.message();
    EXPECT_TRUE(contains(sql.message(), "nowhere")) << sql.message();   // OGR's message names the table
}

TEST(VectorReader, AttributesAreTyped) {
    const auto file = writeGeoJson("typed", {feature(R"({"type": "Point", "coordinates": [1,2]})",
                                                     R"({"i": 3, "r": 1.5, "s": "x", "d": "2020-01-02", "t": "2020-01-02T03:04:05Z", "n": null})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    std::vector<std::string> types;
    for (const FieldInfo& f : layer.fields) types.push_back(f.name + ":" + f.type);
    EXPECT_EQ(types, (std::vector<std::string>{"i:Integer", "r:Real", "s:String", "d:Date", "t:DateTime", "n:String"}));
    const auto& a = layer.features.at(0).attributes;
    EXPECT_EQ(std::get<int64_t>(a[0]), 3);
    EXPECT_DOUBLE_EQ(std::get<double>(a[1]), 1.5);
    EXPECT_EQ(std::get<std::string>(a[2]), "x");
    EXPECT_EQ(std::get<std::string>(a[3]), "2020-01-02");
    EXPECT_EQ(std::get<std::string>(a[4]), "2020-01-02T03:04:05Z");
    EXPECT_TRUE(std::holds_alternative<std::monostate>(a[5]));
}

TEST(VectorReader, NanCoordinatesAreSkippedWithAWarning) {
    // GDAL's GeoJSON reader takes NaN and Infinity literals.
    const auto file = writeGeoJson("nan", {feature(R"({"type": "LineString", "coordinates": [[0,0],[NaN,1]]})"),
                                           feature(R"({"type": "Point", "coordinates": [3,4]})"),
                                           feature(R"({"type": "Point", "coordinates": [Infinity,4]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    EXPECT_EQ(layer.featuresRead, 3u);
    EXPECT_EQ(layer.featuresSkipped, 2u);
    ASSERT_EQ(layer.features.size(), 1u);
    EXPECT_DOUBLE_EQ(layer.features[0].coords[0].x, 3.0);
    EXPECT_EQ(layer.warnings, (std::vector<std::string>{"skipped feature 0: a coordinate is NaN or infinite",
                                                        "skipped feature 2: a coordinate is NaN or infinite"}));
    // Past the cap, warnings are counted, not listed.
    VectorReadOptions o;
    o.source = file.string();
    o.limits.maxWarnings = 1;
    auto capped = readVector(o);
    ASSERT_TRUE(capped) << capped.message();
    EXPECT_EQ(capped->layers[0].warnings, (std::vector<std::string>{"skipped feature 0: a coordinate is NaN or infinite",
                                                                     "1 more warnings not listed"}));
}

TEST(VectorReader, CoordinatesOutsideLonLatAreSkippedAndPoleRoundingIsKept) {
    // Found by fuzzing: a FlatGeobuf in EPSG:4326 with an x of -2.7e283.
    const auto file = writeGeoJson("range", {feature(R"({"type": "Point", "coordinates": [-2.7e283, 10]})"),
                                             feature(R"({"type": "LineString", "coordinates": [[0,0],[1,91]]})"),
                                             feature(R"({"type": "Point", "coordinates": [10, 90.0000000001]})"),
                                             feature(R"({"type": "Point", "coordinates": [350, -45]})")});
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    EXPECT_EQ(layer.featuresSkipped, 2u);
    EXPECT_EQ(layer.warnings,
              (std::vector<std::string>{
                  "skipped feature 0: the coordinate (-2.7e+283, 10) is not a WGS84 longitude, latitude (is the layer's CRS right?)",
                  "skipped feature 1: the coordinate (1, 91) is not a WGS84 longitude, latitude (is the layer's CRS right?)"}));
    ASSERT_EQ(layer.features.size(), 2u);
    EXPECT_EQ(layer.features[0].coords[0].y, 90.0);
    EXPECT_DOUBLE_EQ(layer.features[1].coords[0].x, -10.0);
    EXPECT_FALSE(tilesCovering(layer.features[0], 3).empty());
}

TEST(VectorReader, FeatureOverTheVertexLimitIsSkippedAndTheReadLimitsStopTheRead) {
    const auto file = writeGeoJson("long", {feature(R"({"type": "LineString", "coordinates": [[0,0],[1,1],[2,2],[3,3],[4,4]]})"),
                                            feature(R"({"type": "LineString", "coordinates": [[0,0],[1,1]]})")});
    VectorReadOptions o;
    o.source = file.string();
    o.limits.maxVerticesPerFeature = 3;
    auto data = readVector(o);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    ASSERT_EQ(layer.features.size(), 1u);
    EXPECT_EQ(layer.features[0].fid, 1);
    ASSERT_EQ(layer.warnings.size(), 1u);
    EXPECT_EQ(layer.warnings[0], "skipped feature 0: more than 3 vertices (the limit per feature)");
    // The total limit stops the read.
    o.limits.maxVerticesPerFeature = 100;
    o.limits.maxTotalVertices = 6;
    auto total = readVector(o);
    ASSERT_TRUE(total) << total.message();
    EXPECT_EQ(total->layers[0].features.size(), 1u);
    EXPECT_TRUE(contains(total->layers[0].warnings.at(0), "limit of 6 vertices")) << total->layers[0].warnings.at(0);
    // So does the feature limit.
    o.limits.maxTotalVertices = 100;
    o.limits.maxFeatures = 1;
    auto one = readVector(o);
    ASSERT_TRUE(one) << one.message();
    EXPECT_EQ(one->layers[0].features.size(), 1u);
    EXPECT_EQ(one->layers[0].warnings, (std::vector<std::string>{"reading stopped at feature 1: the limit of 1 features was reached"}));
}

TEST(VectorReader, MissingFileUnknownLayerAndUnreadableFileAreErrorsNamingThem) {
    auto missing = read(tempDir() / "nothing-here.shp");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.message(), (tempDir() / "nothing-here.shp").string() + ": no such file");
    const auto towns = writeTowns();
    VectorReadOptions o;
    o.source = towns.string();
    o.layers = {"cities"};
    auto unknown = readVector(o);
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.message(), towns.string() + ": no layer 'cities' (layers: towns)");
    const auto garbage = writeFile("garbage.gpkg", "this is not a GeoPackage");
    auto bad = read(garbage);
    ASSERT_FALSE(bad);
    EXPECT_TRUE(contains(bad.message(), garbage.string() + ": OGR cannot open it as vector data")) << bad.message();
    // A connection string goes to OGR (not "no such file"); nothing listens on port 1.
    auto wfs = read("WFS:http://127.0.0.1:1/wfs");
    ASSERT_FALSE(wfs);
    EXPECT_TRUE(contains(wfs.message(), "WFS:http://127.0.0.1:1/wfs: OGR cannot open it as vector data")) << wfs.message();
}

TEST(VectorReader, EmptyLayerIsNotAnError) {
    auto data = read(writeGeoJson("empty", {}));
    ASSERT_TRUE(data) << data.message();
    ASSERT_EQ(data->layers.size(), 1u);
    EXPECT_TRUE(data->layers[0].features.empty());
    EXPECT_TRUE(data->layers[0].bounds.empty);
}

TEST(VectorReader, SelfIntersectingPolygonIsKept) {
    auto data = read(writeGeoJson("bowtie", {feature(R"({"type": "Polygon", "coordinates": [[[0,0],[2,2],[2,0],[0,2],[0,0]]]})")}));
    ASSERT_TRUE(data) << data.message();
    ASSERT_EQ(data->layers[0].features.size(), 1u);
    EXPECT_EQ(data->layers[0].features[0].coords.size(), 5u);
}

TEST(VectorReader, CurvesAreLinearised) {
    const auto file = writeFile("arc.csv", "id,WKT\n1,\"CIRCULARSTRING (0 0,1 1,2 0)\"\n");
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const Feature& f = data->layers[0].features.at(0);
    EXPECT_EQ(f.kind, GeometryKind::Lines);
    ASSERT_GT(f.coords.size(), 10u);
    for (const glm::dvec3& v : f.coords) EXPECT_NEAR(std::hypot(v.x - 1.0, v.y), 1.0, 1e-9);   // on the arc's circle
}

TEST(VectorReader, LayerWithoutCrsIsLonLatWithAWarningOrAnError) {
    // A CSV has no CRS: coordinates that fit lon/lat are taken as such (0..360 included).
    auto lonLat = read(writeFile("lonlat.csv", "id,WKT\n1,\"POINT (350 -45)\"\n"));
    ASSERT_TRUE(lonLat) << lonLat.message();
    const VectorLayer& layer = lonLat->layers.at(0);
    EXPECT_EQ(layer.warnings, (std::vector<std::string>{
                                  "no coordinate reference system: coordinates taken as WGS84 longitude/latitude"}));
    ASSERT_EQ(layer.features.size(), 1u);
    EXPECT_DOUBLE_EQ(layer.features[0].coords[0].x, -10.0);
    EXPECT_DOUBLE_EQ(layer.features[0].coords[0].y, -45.0);
    // Projected metres without a CRS cannot be placed.
    const auto file = writeFile("metres.csv", "id,WKT\n1,\"POINT (500000 4000000)\"\n");
    auto data = read(file);
    ASSERT_FALSE(data);
    EXPECT_TRUE(contains(data.message(), file.string() + ": layer 'metres': no coordinate reference system")) << data.message();
}

TEST(VectorReader, CrsWithoutTransformationToWgs84IsAnError) {
    const auto file = writeFile("local.csv", "id,WKT\n1,\"POINT (1 2)\"\n");
    writeFile("local.prj", R"(LOCAL_CS["shop floor",UNIT["metre",1]])");
    auto data = read(file);
    ASSERT_FALSE(data);
    EXPECT_TRUE(contains(data.message(), file.string() + ": layer 'local': no transformation from its CRS")) << data.message();
    EXPECT_TRUE(contains(data.message(), "shop floor")) << data.message();
}

/// NC State Plane (EPSG:2264, NAD83, US survey feet): its false origin, 2 000 000 ftUS east of
/// nothing at 33°45'N 79°W, must come back as exactly that place.
TEST(VectorReader, StatePlaneFeetAreTransformedToLonLat) {
    GDALAllRegister();
    const fs::path file = tempDir() / "stateplane.gpkg";
    {
        GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
        ASSERT_NE(driver, nullptr);
        std::unique_ptr<GDALDataset> ds(driver->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
        ASSERT_NE(ds, nullptr);
        OGRSpatialReference srs;
        ASSERT_EQ(srs.importFromEPSG(2264), OGRERR_NONE);
        OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPoint, nullptr);
        ASSERT_NE(layer, nullptr);
        for (double northingFt : {0.0, 656168.0}) {   // 656 168 ftUS: about 200 km north
            OGRFeature f(layer->GetLayerDefn());
            OGRPoint p(2000000.0, northingFt);
            f.SetGeometry(&p);
            ASSERT_EQ(layer->CreateFeature(&f), OGRERR_NONE);
        }
    }
    auto data = read(file);
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers.at(0);
    EXPECT_EQ(layer.crs, "EPSG:2264");
    ASSERT_EQ(layer.features.size(), 2u);
    // NAD83 to WGS84 is within a metre (PROJ's default for the US is the null transformation):
    // 1e-5 degrees is about a metre; reading feet as metres would be off by 120 km.
    const glm::dvec3 origin = layer.features[0].coords[0];
    EXPECT_NEAR(origin.x, -79.0, 1e-5);
    EXPECT_NEAR(origin.y, 33.75, 1e-5);
    // On the central meridian, 200 km north: 656 168 ftUS = 200 000.4 m of grid. The meridian arc
    // of GRS 1980 near 34.65 N is 110 934 m per degree, and the projection's scale there is within
    // 1e-4 of 1 (20 m): 50 m of tolerance; feet read as metres would be 139 km short.
    const glm::dvec3 north = layer.features[1].coords[0];
    EXPECT_NEAR(north.x, -79.0, 1e-5);
    EXPECT_NEAR((north.y - 33.75) * 110934.0, 200000.4, 50.0);
}

}  // namespace
}  // namespace orbis::vector

namespace orbis::vector {
namespace {

// Vector reads set Orbis's GDAL defaults as raster reads do: without a timeout a WFS server that
// stops answering held a worker for ever (curl waits without end). Each ctest runs this test in
// a process of its own, where nothing else has set up GDAL first.
TEST(VectorReader, AVectorReadSetsTheHttpTimeouts) {
    if (std::getenv("GDAL_HTTP_TIMEOUT")) GTEST_SKIP() << "GDAL_HTTP_TIMEOUT is set in the environment";
    VectorReadOptions o;
    o.source = writeGeoJson("timeouts", {feature(R"({"type": "Point", "coordinates": [1, 2]})")}).string();
    ASSERT_TRUE(readVector(o));
    EXPECT_STREQ(CPLGetConfigOption("GDAL_HTTP_TIMEOUT", ""), "30");
    EXPECT_STREQ(CPLGetConfigOption("GDAL_HTTP_CONNECTTIMEOUT", ""), "10");
}

// A WFS server that takes the connection and never answers: the read ends with the HTTP timeout
// (2 s here, 30 s by default) with an error that names the source; nothing hangs.
TEST(VectorReader, AStalledWfsServerEndsTheReadWithinItsTimeout) {
    test::HttpServer server(tempDir());
    ASSERT_TRUE(server.running()) << server.error();
    server.setFault(test::HttpServer::Fault::Stall);
    const test::ScopedGdalConfig timeout("GDAL_HTTP_TIMEOUT", "2");
    const test::ScopedGdalConfig retries("GDAL_HTTP_MAX_RETRY", "0");
    VectorReadOptions o;
    o.source = "WFS:" + server.url() + "/wfs";
    const auto t0 = std::chrono::steady_clock::now();
    auto r = readVector(o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_FALSE(r);
    EXPECT_NE(r.message().find(o.source), std::string::npos) << r.message();
    EXPECT_LT(s, 15.0) << "the read waited past its timeout";
    EXPECT_GT(server.requestCount(), 0);
}

}  // namespace
}  // namespace orbis::vector
