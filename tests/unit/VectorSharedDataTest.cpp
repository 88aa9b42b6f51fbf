// The vector reader on real files of ../shared/data/vector (skipped when absent): Natural Earth
// 110 m countries (cut at the antimeridian, Antarctica around the South Pole) and cities, the
// Olinda census polygons (a GRS 1980 CRS), and North Carolina's counties in NAD27.
#include "layers/vector/Triangulate.h"
#include "layers/vector/VectorReader.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(ORBIS_SHARED_DATA_DIR) / "vector";

#define REQUIRE_SHARED(file) \
    if (!fs::exists(kDir / (file))) GTEST_SKIP() << "../shared/data is absent: no " << (kDir / (file))

Result<VectorData> readAll(const std::string& file, const std::string& where = "", const std::string& sql = "") {
    VectorReadOptions o;
    o.source = (kDir / file).string();
    o.where = where;
    o.sql = sql;
    return readVector(o);
}

size_t fieldIndex(const VectorLayer& layer, const std::string& name) {
    for (size_t i = 0; i < layer.fields.size(); ++i)
        if (layer.fields[i].name == name) return i;
    ADD_FAILURE() << "no field " << name;
    return 0;
}

const Feature* findByName(const VectorLayer& layer, const std::string& field, const std::string& value) {
    const size_t i = fieldIndex(layer, field);
    for (const Feature& f : layer.features)
        if (const auto* s = std::get_if<std::string>(&f.attributes.at(i)); s && *s == value) return &f;
    return nullptr;
}

// Bounds are checked to 1e-9 degrees: the lon/lat files pass through PROJ's identity.
constexpr double kEps = 1e-9;

TEST(VectorSharedData, NaturalEarthCountriesAreReadWithTypedFields) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto data = readAll("naturalearth_lowres.shp");
    ASSERT_TRUE(data) << data.message();
    ASSERT_EQ(data->layers.size(), 1u);
    const VectorLayer& layer = data->layers[0];
    EXPECT_EQ(layer.features.size(), 177u);
    EXPECT_EQ(layer.featuresSkipped, 0u);
    EXPECT_TRUE(layer.warnings.empty());
    EXPECT_EQ(layer.crs, "EPSG:4326");
    EXPECT_EQ(layer.geometryType, "Polygon");
    EXPECT_EQ(layer.fields[fieldIndex(layer, "pop_est")].type, "Real");
    EXPECT_EQ(layer.fields[fieldIndex(layer, "gdp_md_est")].type, "Integer64");
    EXPECT_TRUE(layer.bounds.spansAllLongitudes());
    EXPECT_DOUBLE_EQ(layer.bounds.south, -90.0);
}

TEST(VectorSharedData, FijiAndRussiaCutAtTheAntimeridianHaveTightBounds) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto data = readAll("naturalearth_lowres.shp");
    ASSERT_TRUE(data) << data.message();
    const Feature* fiji = findByName(data->layers[0], "name", "Fiji");
    ASSERT_NE(fiji, nullptr);
    // Three islands: one ending at 180, one west of it, one starting at -180 (the file's rings:
    // 8, 9 and 5 vertices).
    EXPECT_EQ(fiji->parts, (std::vector<uint32_t>{0, 8, 17}));
    EXPECT_EQ(fiji->polygons, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(fiji->coords.size(), 22u);
    EXPECT_DOUBLE_EQ(fiji->coords[0].x, 180.0);
    EXPECT_NEAR(fiji->coords[17].x, -179.793320109049, kEps);
    EXPECT_NEAR(fiji->bounds.west, 177.28504, kEps);
    EXPECT_NEAR(fiji->bounds.east, 360.0 - 179.793320109049, kEps);
    EXPECT_NEAR(fiji->bounds.south, -18.28799, kEps);
    EXPECT_NEAR(fiji->bounds.north, -16.0208822567412, kEps);
    EXPECT_TRUE(fiji->bounds.contains(-179.9, -16.3));
    EXPECT_FALSE(fiji->bounds.contains(0.0, -17.0));

    const Feature* russia = findByName(data->layers[0], "name", "Russia");
    ASSERT_NE(russia, nullptr);
    EXPECT_EQ(russia->polygons.size(), 13u);
    // From Kaliningrad (19.66 E) east across 180 to Chukotka (169.9 W): 170.4 degrees, not 360.
    EXPECT_NEAR(russia->bounds.west, 19.6606400896064, kEps);
    EXPECT_NEAR(russia->bounds.east, 360.0 - 169.89958, kEps);
    EXPECT_NEAR(russia->bounds.north, 81.2504, kEps);
    for (const Feature* f : {fiji, russia})
        for (int8_t pole : f->containsPole) EXPECT_EQ(pole, 0);
}

TEST(VectorSharedData, AntarcticaAloneEnclosesThePole) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto data = readAll("naturalearth_lowres.shp");
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers[0];
    const Feature* antarctica = findByName(layer, "name", "Antarctica");
    ASSERT_NE(antarctica, nullptr);
    ASSERT_FALSE(antarctica->containsPole.empty());
    // Its mainland is the ring around the South Pole; the islands are not.
    size_t around = 0;
    for (size_t p = 0; p < antarctica->parts.size(); ++p) {
        if (antarctica->containsPole[p] == 0) continue;
        EXPECT_EQ(antarctica->containsPole[p], -1);
        ++around;
    }
    EXPECT_EQ(around, 1u);
    EXPECT_TRUE(antarctica->bounds.spansAllLongitudes());
    EXPECT_DOUBLE_EQ(antarctica->bounds.south, -90.0);
    size_t flagged = 0;
    for (const Feature& f : layer.features)
        for (int8_t pole : f.containsPole) flagged += pole != 0;
    EXPECT_EQ(flagged, 1u);
}

TEST(VectorSharedData, SqlOnAShapefileSelectsAContinent) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto data = readAll("naturalearth_lowres.shp", "", "SELECT name FROM naturalearth_lowres WHERE continent = 'Oceania'");
    ASSERT_TRUE(data) << data.message();
    EXPECT_EQ(data->layers.at(0).features.size(), 7u);
    EXPECT_NE(findByName(data->layers[0], "name", "Fiji"), nullptr);
}

TEST(VectorSharedData, NaturalEarthCitiesArePoints) {
    REQUIRE_SHARED("naturalearth_cities.shp");
    auto data = readAll("naturalearth_cities.shp");
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers.at(0);
    ASSERT_EQ(layer.features.size(), 243u);
    for (const Feature& f : layer.features) {
        EXPECT_EQ(f.kind, GeometryKind::Points);
        EXPECT_EQ(f.coords.size(), 1u);
    }
    const Feature* suva = findByName(layer, "name", "Suva");
    ASSERT_NE(suva, nullptr);
    EXPECT_NEAR(suva->coords[0].x, 178.4417073, kEps);
    EXPECT_NEAR(suva->coords[0].y, -18.1330159, kEps);
}

TEST(VectorSharedData, OlindaPolygonsInGrs80) {
    REQUIRE_SHARED("olinda1.shp");
    auto data = readAll("olinda1.shp");
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers.at(0);
    EXPECT_EQ(layer.features.size(), 470u);
    for (const Feature& f : layer.features) EXPECT_EQ(f.kind, GeometryKind::Polygons);
    // A GRS 1980 datum without a shift to WGS84: the file's extent, to 1e-6 degrees (0.1 m).
    EXPECT_NEAR(layer.bounds.west, -34.916923, 1e-6);
    EXPECT_NEAR(layer.bounds.east, -34.827789, 1e-6);
    EXPECT_NEAR(layer.bounds.south, -8.044467, 1e-6);
    EXPECT_NEAR(layer.bounds.north, -7.954672, 1e-6);
}

/// The first vertex of a feature as stored (NAD27 lon/lat), read with OGR directly.
glm::dvec2 storedVertex(const fs::path& file, int64_t fid) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds) return glm::dvec2(NAN);
    std::unique_ptr<OGRFeature> f(ds->GetLayer(0)->GetFeature(fid));
    if (!f || !f->GetGeometryRef()) return glm::dvec2(NAN);
    const OGRPolygon* polygon = f->GetGeometryRef()->toMultiPolygon()->getGeometryRef(0);
    const OGRLinearRing* ring = polygon->getExteriorRing();
    return {ring->getX(0), ring->getY(0)};
}

TEST(VectorSharedData, NorthCarolinaCountiesAreShiftedFromNad27ToWgs84) {
    REQUIRE_SHARED("nc.gpkg");
    auto data = readAll("nc.gpkg");
    ASSERT_TRUE(data) << data.message();
    const VectorLayer& layer = data->layers.at(0);
    EXPECT_EQ(layer.features.size(), 100u);
    EXPECT_EQ(layer.geometryType, "Multi Polygon");
    EXPECT_EQ(layer.crs, "EPSG:4267");
    EXPECT_EQ(layer.crsName, "NAD27");
    const Feature* ashe = findByName(layer, "NAME", "Ashe");
    ASSERT_NE(ashe, nullptr);
    const glm::dvec2 nad27 = storedVertex(kDir / "nc.gpkg", ashe->fid);
    ASSERT_TRUE(std::isfinite(nad27.x));
    // The same vertex through OGR's own transformation, lon first.
    OGRSpatialReference from, to;
    from.importFromEPSG(4267);
    to.importFromEPSG(4326);
    from.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&from, &to));
    ASSERT_NE(ct, nullptr);
    double x = nad27.x, y = nad27.y;
    ASSERT_TRUE(ct->Transform(1, &x, &y));
    const glm::dvec3 read = ashe->coords[0];
    EXPECT_NEAR(read.x, x, 1e-9);
    EXPECT_NEAR(read.y, y, 1e-9);
    // The datum shift happened: NAD27 to WGS84 moves North Carolina by 10-50 m (here about 18 m,
    // mostly east). Metres per degree from the sphere of 6371 km: 1 % is plenty for this bound.
    const double metresPerDeg = 6371000.0 * std::numbers::pi / 180.0;
    const double eastM = (read.x - nad27.x) * metresPerDeg * std::cos(read.y * std::numbers::pi / 180.0);
    const double northM = (read.y - nad27.y) * metresPerDeg;
    EXPECT_GT(std::hypot(eastM, northM), 10.0);
    EXPECT_LT(std::hypot(eastM, northM), 50.0);
    EXPECT_GT(eastM, 5.0);
    // A where filter on real data.
    auto one = readAll("nc.gpkg", "NAME = 'Ashe'");
    ASSERT_TRUE(one) << one.message();
    ASSERT_EQ(one->layers.at(0).features.size(), 1u);
    EXPECT_EQ(one->layers[0].features[0].fid, ashe->fid);
    // SQLite checks a GeoPackage's filter only at the first feature: still an error naming it.
    auto bad = readAll("nc.gpkg", "NOSUCH = 1");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("nc.gpkg: layer 'nc.gpkg'"), std::string::npos) << bad.message();
    EXPECT_NE(bad.message().find("\"NOSUCH = 1\""), std::string::npos) << bad.message();
}

}  // namespace
}  // namespace orbis::vector

namespace orbis::vector {
namespace {

TEST(VectorSharedData, AReadWithinABoxGetsTheFeaturesNearItAndNoOthers) {
    // Central Europe from Natural Earth (lon/lat), and one corner of North Carolina from a NAD27
    // GeoPackage (the box is put into NAD27 for OGR's spatial filter).
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto all = readAll("naturalearth_lowres.shp");
    ASSERT_TRUE(all) << all.message();
    VectorReadOptions o;
    o.source = (kDir / "naturalearth_lowres.shp").string();
    o.within = LonLatBounds{.west = 8.0, .south = 47.0, .east = 14.0, .north = 52.0, .empty = false};
    auto europe = readVector(o);
    ASSERT_TRUE(europe) << europe.message();
    const VectorLayer& layer = europe->layers[0];
    EXPECT_TRUE(findByName(layer, "name", "Germany"));
    EXPECT_TRUE(findByName(layer, "name", "Czechia"));
    EXPECT_FALSE(findByName(layer, "name", "Brazil"));
    EXPECT_FALSE(findByName(layer, "name", "Spain"));
    EXPECT_LT(layer.features.size(), 12u);
    // Each one's box meets the asked box (west of 14, east of 8, ...).
    for (const Feature& f : layer.features) {
        EXPECT_LE(f.bounds.south, 52.0);
        EXPECT_GE(f.bounds.north, 47.0);
    }

    REQUIRE_SHARED("nc.gpkg");
    o.source = (kDir / "nc.gpkg").string();
    o.within = LonLatBounds{.west = -81.6, .south = 36.3, .east = -81.4, .north = 36.5, .empty = false};   // in Ashe
    auto nc = readVector(o);
    ASSERT_TRUE(nc) << nc.message();
    EXPECT_TRUE(findByName(nc->layers[0], "NAME", "Ashe"));
    EXPECT_LT(nc->layers[0].features.size(), 5u);
    EXPECT_FALSE(findByName(nc->layers[0], "NAME", "Brunswick"));   // the far south-east corner

    o.within = LonLatBounds{.west = 10.0, .south = 0.0, .east = 5.0, .north = 1.0, .empty = false};
    auto bad = readVector(o);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("west < east"), std::string::npos) << bad.message();
}

TEST(VectorSharedData, EveryNaturalEarthCountryIsTriangulatedExactlyInTheLonLatPlane) {
    // Each polygon that does not go around a pole, cut in the plane of its (unwrapped) lon/lat:
    // the triangles cover the outer ring less its holes, and no ear needed forcing (the data
    // is valid). Antarctica's ring around the pole needs a polar plane and is left out here.
    REQUIRE_SHARED("naturalearth_lowres.shp");
    auto data = readAll("naturalearth_lowres.shp");
    ASSERT_TRUE(data) << data.message();
    size_t polygons = 0, triangles = 0;
    for (const Feature& f : data->layers[0].features) {
        for (size_t k = 0; k < f.polygons.size(); ++k) {
            if (f.containsPole[f.polygons[k]] != 0) continue;
            std::vector<glm::dvec2> points;
            std::vector<uint32_t> starts;
            double expected = 0.0;
            for (size_t p = f.polygons[k]; p < f.polygonEnd(k); ++p) {
                starts.push_back(uint32_t(points.size()));
                const size_t first = points.size();
                for (uint32_t i = f.parts[p]; i < f.partEnd(p); ++i) points.emplace_back(f.coords[i].x, f.coords[i].y);
                const double a = std::abs(ringArea2(std::span(points).subspan(first)));
                expected += p == f.polygons[k] ? a : -a;
            }
            TriangulateStats stats;
            auto tris = triangulate(points, starts, 1'000'000, &stats);
            ASSERT_TRUE(tris) << tris.message();
            double area = 0.0;
            for (size_t t = 0; t < tris->size(); t += 3) {
                const glm::dvec2 a = points[(*tris)[t]], b = points[(*tris)[t + 1]], c = points[(*tris)[t + 2]];
                area += (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            }
            EXPECT_NEAR(area, expected, 1e-9 * expected + 1e-12) << "feature " << f.fid << " polygon " << k;
            EXPECT_EQ(stats.forced, 0u) << "feature " << f.fid << " polygon " << k;
            ++polygons;
            triangles += tris->size() / 3;
        }
    }
    EXPECT_GT(polygons, 280u);   // 177 countries, many of them several islands
    EXPECT_GT(triangles, 9000u);
}

TEST(VectorSharedData, ASummaryCountsFieldsAndBoundsWithoutReadingFeatures) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    VectorReadOptions o;
    o.source = (kDir / "naturalearth_lowres.shp").string();
    auto all = summarizeVector(o);
    ASSERT_TRUE(all) << all.message();
    ASSERT_EQ(all->size(), 1u);
    const LayerSummary& layer = (*all)[0];
    EXPECT_EQ(layer.name, "naturalearth_lowres");
    EXPECT_EQ(layer.featureCount, 177);
    EXPECT_TRUE(findField(layer.fields, "pop_est").has_value());
    ASSERT_TRUE(layer.bounds.has_value());
    EXPECT_NEAR(layer.bounds->west, -180.0, 1e-6);
    EXPECT_NEAR(layer.bounds->east, 180.0, 1e-6);
    EXPECT_NEAR(layer.bounds->south, -90.0, 1e-6);
    // A where filter counts what it keeps; an SQL statement is summarised as its result.
    o.where = "continent = 'Oceania'";
    auto oceania = summarizeVector(o);
    ASSERT_TRUE(oceania) << oceania.message();
    EXPECT_GT((*oceania)[0].featureCount, 3);
    EXPECT_LT((*oceania)[0].featureCount, 15);
    o.where.clear();
    o.sql = "SELECT name FROM naturalearth_lowres";
    auto sql = summarizeVector(o);
    ASSERT_TRUE(sql) << sql.message();
    EXPECT_EQ((*sql)[0].fields.size(), 1u);
    o.sql = "SELECT nothing FROM nowhere";
    auto bad = summarizeVector(o);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.message().find("bad SQL statement"), std::string::npos) << bad.message();
    o.sql.clear();
    o.layers = {"roads"};
    auto missing = summarizeVector(o);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.message().find("no layer 'roads'"), std::string::npos) << missing.message();
}

TEST(VectorSharedData, ASourceKeptOpenBetweenReadsTakesEachReadsOwnFilters) {
    REQUIRE_SHARED("naturalearth_lowres.shp");
    VectorReadOptions o;
    o.source = (kDir / "naturalearth_lowres.shp").string();
    o.reuseDataset = true;
    const auto count = [&] {
        auto data = readVector(o);
        EXPECT_TRUE(data) << data.message();
        return data ? data->layers[0].features.size() : size_t(0);
    };
    o.where = "continent = 'Africa'";
    const size_t africa = count();
    o.where.clear();
    o.within = LonLatBounds{-10.0, 35.0, 30.0, 60.0, false};
    const size_t europe = count();
    o.within.reset();
    EXPECT_EQ(count(), 177u) << "neither the where filter nor the box stayed on the kept source";
    EXPECT_GT(africa, 40u);
    EXPECT_LT(africa, 60u);
    EXPECT_GT(europe, 20u);
    EXPECT_LT(europe, 60u);
}

}  // namespace
}  // namespace orbis::vector
