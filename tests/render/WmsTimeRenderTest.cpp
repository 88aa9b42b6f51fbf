// A time-enabled WMS layer follows the scene's virtual time, against a real MapServer on loopback
// (tests/support/MapServer.h): a raster tile index whose three tiles (red, green, blue) are
// January, February and March 2026; the terrain shows the month the scene's time is in, asking
// the server for TIME=<that month>. Skipped, with the reason, when the packages are missing.
#include "tests/render/SceneGpuTest.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/MapServer.h"
#include "tests/support/ProcessTempDir.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;

/// A whole-world GeoTIFF of one colour.
void writeFlat(const fs::path& file, uint8_t r, uint8_t g, uint8_t b) {
    std::unique_ptr<GDALDataset> ds(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(file.c_str(), 16, 8, 3, GDT_Byte, nullptr));
    double gt[6] = {-180.0, 22.5, 0.0, 90.0, 0.0, -22.5};
    ds->SetGeoTransform(gt);
    ds->SetProjection(SRS_WKT_WGS84_LAT_LONG);
    for (int band = 1; band <= 3; ++band) {
        std::vector<uint8_t> v(16 * 8, band == 1 ? r : band == 2 ? g : b);
        if (ds->GetRasterBand(band)->RasterIO(GF_Write, 0, 0, 16, 8, v.data(), 16, 8, GDT_Byte, 0, 0) != CE_None)
            ADD_FAILURE() << "cannot write " << file;
    }
}

/// MapServer's raster tile index: one world polygon per month, naming its file.
void writeIndex(const fs::path& dir) {
    std::unique_ptr<GDALDataset> ds(GetGDALDriverManager()->GetDriverByName("ESRI Shapefile")->Create((dir / "seasons.shp").c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRLayer* layer = ds->CreateLayer("seasons", &wgs84, wkbPolygon, nullptr);
    OGRFieldDefn location("location", OFTString), time("time", OFTString);
    location.SetWidth(254);
    layer->CreateField(&location);
    layer->CreateField(&time);
    const struct { const char* month; const char* file; uint8_t r, g, b; } months[] = {
        {"2026-01-01", "jan.tif", 220, 30, 30}, {"2026-02-01", "feb.tif", 30, 200, 40}, {"2026-03-01", "mar.tif", 30, 60, 220}};
    for (const auto& m : months) {
        writeFlat(dir / m.file, m.r, m.g, m.b);
        OGRFeature f(layer->GetLayerDefn());
        f.SetField("location", (dir / m.file).c_str());
        f.SetField("time", m.month);
        OGRGeometry* g = nullptr;
        OGRGeometryFactory::createFromWkt("POLYGON((-180 -90,180 -90,180 90,-180 90,-180 -90))", &wgs84, &g);
        f.SetGeometryDirectly(g);
        if (layer->CreateFeature(&f) != OGRERR_NONE) ADD_FAILURE() << "index feature not written";
    }
}

class WmsTimeRender : public SceneGpuTest {
protected:
    void SetUp() override {
        SceneGpuTest::SetUp();
        if (IsSkipped()) return;
        GDALAllRegister();
        dir = orbis::test::processTempDir("orbis-wms-time");
        writeIndex(dir);
        ms = std::make_unique<MapServer>(std::vector<std::string>{
            R"(LAYER NAME "seasons" TYPE RASTER STATUS ON TILEINDEX ")" + (dir / "seasons.shp").string() + R"(" TILEITEM "location"
                 PROJECTION "init=epsg:4326" END
                 METADATA "wms_title" "Seasons" "wms_timeextent" "2026-01-01/2026-03-01/P1M" "wms_timeitem" "time"
                          "wms_timedefault" "2026-01-01" END END)"});
        if (!ms->available()) GTEST_SKIP() << ms->error();
        ASSERT_TRUE(ms->running()) << ms->error();
    }
    void TearDown() override {
        ms.reset();
        std::error_code ec;
        if (!dir.empty()) fs::remove_all(dir, ec);
        SceneGpuTest::TearDown();
    }
    fs::path dir;
    std::unique_ptr<MapServer> ms;
};

TEST_F(WmsTimeRender, TheLayerShowsTheMonthOfTheScenesTime) {
    const std::string wms = "WMS:" + ms->url() + "SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=seasons&SRS=EPSG:4326&BBOX=-180,-90,180,90&FORMAT=image/png";
    const std::string json =
        R"({"viewpoint": {"lon": 10, "lat": 20, "range": 12000000}, "time": {"start": "2026-01-01T00:00:00Z", "end": "2026-04-01T00:00:00Z"},
            "background": [0, 0, 0], "layers": [{"type": "terrain", "name": "Seasons", "sky": false, "lighting": "headlight",
            "imagery": [{"path": )" + jsonString(wms) + R"(, "cacheDir": )" + jsonString((dir / "cache").string()) +
        R"(, "time": "2026-01-01/2026-03-01/P1M"}]}]})";
    auto scene = load(json);
    ASSERT_TRUE(scene);
    const struct { const char* at; int channel; const char* asked; } steps[] = {
        {"2026-01-15T00:00:00Z", 0, "time=2026-01-01"}, {"2026-02-10T00:00:00Z", 1, "time=2026-02-01"},
        {"2026-03-31T00:00:00Z", 2, "time=2026-03-01"}, {"2026-01-20T00:00:00Z", 0, "time=2026-01-01"}};
    for (const auto& s : steps) {
        SCOPED_TRACE(s.at);
        scene->time().seek(*parseIso8601(s.at));
        const ImageRgba8 image = renderScene(*scene, 128, 128);
        const uint8_t* centre = &image.pixels[(size_t(64) * 128 + 64) * 4];
        // The month's colour dominates the globe's centre (lit by the headlight: darker, same hue).
        for (int c = 0; c < 3; ++c) {
            if (c == s.channel) continue;
            EXPECT_GT(int(centre[s.channel]), 2 * int(centre[c]) + 20) << int(centre[0]) << "," << int(centre[1]) << "," << int(centre[2]);
        }
        std::string log = ms->accessLog();
        for (char& ch : log) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        EXPECT_NE(log.find(s.asked), std::string::npos) << log;
    }
}

}  // namespace
}  // namespace orbis::test
