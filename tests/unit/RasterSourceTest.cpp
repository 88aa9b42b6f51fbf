// RasterSource: GDAL reads warped to geodetic tiles. Fixtures are generated at test time with
// GDAL itself into a temporary folder; real data from ../shared/data is used when present.
#include "globe/RasterSource.h"

#include "base/ThreadPool.h"
#include "tests/support/ProcessTempDir.h"

#include <cpl_conv.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

namespace fs = std::filesystem;
using namespace orbis;
using namespace orbis::globe;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNoData = -9999.0;

// Heights of the synthetic DEMs: a plane plus a gentle wave. Bilinear interpolation of 0.01 deg
// samples is off by at most 10 * 4 * 0.01^2 / 8 = 0.5 mm, so tolerances below are about the
// warper's approximate transformer (1/8 pixel), not the interpolation.
double heightAt(double lon, double lat) { return 100.0 * lon + 50.0 * lat + 10.0 * std::sin(lon * 2.0); }

// The hole of nodata in the synthetic DEMs.
bool inHole(double lon, double lat) { return lon > 11.2 && lon < 11.4 && lat > 46.2 && lat < 46.4; }

/// One temporary folder per test process, removed at exit.
class TempDir : public ::testing::Environment {
public:
    static const fs::path& path() {
        static const fs::path p = [] {
            fs::path d = orbis::test::processTempDir("orbis-raster-test");
            return d;
        }();
        return p;
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(path(), ec);
    }
};
[[maybe_unused]] auto* const gTempDirEnv = ::testing::AddGlobalTestEnvironment(new TempDir);

std::string wktOf(int epsg) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, epsg);
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    std::string s = wkt ? wkt : "";
    CPLFree(wkt);
    OSRRelease(srs);
    return s;
}

struct NewRaster {
    int width, height, bands = 1;
    GDALDataType type = GDT_Float32;
    double gt[6];
    int epsg = 4326;  // 0: no CRS
    std::vector<const char*> options;
};

/// Creates a GeoTIFF and hands back the open dataset (caller fills and closes it).
GDALDatasetH createTiff(const fs::path& file, const NewRaster& r) {
    GDALAllRegister();
    std::vector<const char*> opts = r.options;
    opts.push_back(nullptr);
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), file.c_str(), r.width, r.height, r.bands, r.type,
                                 const_cast<char**>(opts.data()));
    if (!ds) return nullptr;
    double gt[6];
    std::copy(r.gt, r.gt + 6, gt);
    GDALSetGeoTransform(ds, gt);
    if (r.epsg) GDALSetProjection(ds, wktOf(r.epsg).c_str());
    return ds;
}

/// Lon/lat DEM: 201 x 201 pixels of 0.01 deg over lon 10..12, lat 45..47, Float32, nodata hole.
const fs::path& demLonLat() {
    static const fs::path file = [] {
        fs::path f = TempDir::path() / "dem_lonlat.tif";
        GDALDatasetH ds = createTiff(f, {201, 201, 1, GDT_Float32, {9.995, 0.01, 0, 47.005, 0, -0.01}});
        std::vector<float> v(201 * 201);
        for (int j = 0; j < 201; ++j)
            for (int i = 0; i < 201; ++i) {
                const double lon = 10.0 + 0.01 * i, lat = 47.0 - 0.01 * j;
                v[size_t(j * 201 + i)] = inHole(lon, lat) ? float(kNoData) : float(heightAt(lon, lat));
            }
        GDALRasterBandH b = GDALGetRasterBand(ds, 1);
        GDALSetRasterNoDataValue(b, kNoData);
        EXPECT_EQ(GDALRasterIO(b, GF_Write, 0, 0, 201, 201, v.data(), 201, 201, GDT_Float32, 0, 0), CE_None);
        GDALClose(ds);
        return f;
    }();
    return file;
}

/// The same heights in UTM zone 32N (EPSG:32632), 100 m pixels, with the same hole.
const fs::path& demUtm() {
    static const fs::path file = [] {
        fs::path f = TempDir::path() / "dem_utm32n.tif";
        constexpr int kW = 500, kH = 500;
        constexpr double kX0 = 630000.0, kY0 = 5120000.0, kPx = 100.0;
        GDALDatasetH ds = createTiff(f, {kW, kH, 1, GDT_Float32, {kX0, kPx, 0, kY0, 0, -kPx}, 32632});
        OGRSpatialReferenceH utm = OSRNewSpatialReference(nullptr), wgs = OSRNewSpatialReference(nullptr);
        OSRImportFromEPSG(utm, 32632);
        OSRImportFromEPSG(wgs, 4326);
        OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
        OSRSetAxisMappingStrategy(wgs, OAMS_TRADITIONAL_GIS_ORDER);
        OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(utm, wgs);
        std::vector<float> v(size_t(kW) * kH);
        for (int j = 0; j < kH; ++j) {
            std::vector<double> x(kW), y(kW);
            for (int i = 0; i < kW; ++i) x[size_t(i)] = kX0 + (i + 0.5) * kPx, y[size_t(i)] = kY0 - (j + 0.5) * kPx;
            OCTTransform(ct, kW, x.data(), y.data(), nullptr);
            for (int i = 0; i < kW; ++i)
                v[size_t(j * kW + i)] =
                    inHole(x[size_t(i)], y[size_t(i)]) ? float(kNoData) : float(heightAt(x[size_t(i)], y[size_t(i)]));
        }
        OCTDestroyCoordinateTransformation(ct);
        OSRRelease(utm);
        OSRRelease(wgs);
        GDALRasterBandH b = GDALGetRasterBand(ds, 1);
        GDALSetRasterNoDataValue(b, kNoData);
        EXPECT_EQ(GDALRasterIO(b, GF_Write, 0, 0, kW, kH, v.data(), kW, kH, GDT_Float32, 0, 0), CE_None);
        GDALClose(ds);
        return f;
    }();
    return file;
}

/// 3-band Byte image over lon 0..10, lat 0..10, constant colour (200, 100, 50).
const fs::path& imageRgb() {
    static const fs::path file = [] {
        fs::path f = TempDir::path() / "rgb.tif";
        GDALDatasetH ds = createTiff(f, {100, 100, 3, GDT_Byte, {0, 0.1, 0, 10, 0, -0.1}});
        const uint8_t colour[3] = {200, 100, 50};
        std::vector<uint8_t> v(100 * 100);
        for (int b = 0; b < 3; ++b) {
            std::fill(v.begin(), v.end(), colour[b]);
            EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, b + 1), GF_Write, 0, 0, 100, 100, v.data(), 100, 100, GDT_Byte, 0, 0),
                      CE_None);
        }
        GDALClose(ds);
        return f;
    }();
    return file;
}

/// 10^6 x 10^6 pixels over lon 0..10, lat 40..50, no overviews, no data written (sparse).
const fs::path& hugeSparse() {
    static const fs::path file = [] {
        fs::path f = TempDir::path() / "huge_sparse.tif";
        GDALDatasetH ds = createTiff(f, {1000000, 1000000, 1, GDT_Byte, {0, 1e-5, 0, 50, 0, -1e-5}, 4326,
                                         {"TILED=YES", "BLOCKXSIZE=4096", "BLOCKYSIZE=4096", "SPARSE_OK=TRUE",
                                          "BIGTIFF=YES"}});
        EXPECT_NE(ds, nullptr);
        if (ds) GDALClose(ds);
        return f;
    }();
    return file;
}

Result<std::shared_ptr<RasterSource>> openDem(const fs::path& file) {
    RasterSourceOptions o;
    o.path = file.string();
    o.role = RasterRole::Elevation;
    return RasterSource::open(o);
}

/// A 65-sample tile whose centre sample (32, 32) lies exactly on (lon, lat).
GeoExtent tileCentredOn(double lon, double lat, double halfDeg) {
    return GeoExtent{lon - halfDeg, lat - halfDeg, lon + halfDeg, lat + halfDeg};
}

float heightAtPoint(const RasterSource& src, double lon, double lat, double halfDeg = 0.032) {
    auto t = src.readElevation(tileCentredOn(lon, lat, halfDeg), 65);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.message());
    return t.ok() ? t->heights[32 * 65 + 32] : std::numeric_limits<float>::quiet_NaN();
}

long maxRssKb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Errors at open

TEST(RasterSource, OpenMissingFileNamesTheFile) {
    const std::string path = (TempDir::path() / "does_not_exist.tif").string();
    auto src = openDem(path);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.message().find(path), std::string::npos) << src.message();
    EXPECT_NE(src.message().find("no such file"), std::string::npos) << src.message();
}

TEST(RasterSource, OpenNonRasterIsAClearError) {
    const fs::path f = TempDir::path() / "notes.txt";
    std::ofstream(f) << "this is not an image\n";
    auto src = openDem(f);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.message().find(f.string()), std::string::npos) << src.message();
    EXPECT_NE(src.message().find("not a raster"), std::string::npos) << src.message();
    auto json = describeRasterJson(f.string());
    ASSERT_FALSE(json.ok());
    EXPECT_NE(json.message().find(f.string()), std::string::npos) << json.message();

    const fs::path v = TempDir::path() / "points.geojson";
    std::ofstream(v) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},)"
                     << R"( "geometry": {"type": "Point", "coordinates": [1, 2]}}]})";
    auto vec = openDem(v);
    ASSERT_FALSE(vec.ok());
    EXPECT_NE(vec.message().find(v.string() + ": is vector data"), std::string::npos) << vec.message();
}

TEST(RasterSource, OpenTruncatedTiffIsAClearError) {
    const fs::path f = TempDir::path() / "truncated.tif";
    GDALDatasetH ds = createTiff(f, {512, 512, 1, GDT_Float32, {0, 0.01, 0, 10, 0, -0.01}});
    std::vector<float> v(512 * 512, 5.0f);
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, 512, 512, v.data(), 512, 512, GDT_Float32, 0, 0),
              CE_None);
    GDALClose(ds);
    fs::resize_file(f, fs::file_size(f) / 3);  // the pixel data is cut short
    auto src = openDem(f);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.message().find(f.string()), std::string::npos) << src.message();

    const fs::path g = TempDir::path() / "header_only.tif";
    fs::copy_file(f, g);
    fs::resize_file(g, 16);  // not even a directory
    auto src2 = openDem(g);
    ASSERT_FALSE(src2.ok());
    EXPECT_NE(src2.message().find(g.string()), std::string::npos) << src2.message();
}

TEST(RasterSource, OpenWithoutCrsIsAClearError) {
    const fs::path f = TempDir::path() / "no_crs.tif";
    GDALClose(createTiff(f, {64, 64, 1, GDT_Float32, {500000, 30, 0, 4000000, 0, -30}, 0}));
    auto src = openDem(f);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.message().find(f.string() + ": has no coordinate reference system"), std::string::npos)
        << src.message();
}

TEST(RasterSource, OpenLonLatGridWithoutCrsAssumesWgs84) {
    const fs::path f = TempDir::path() / "no_crs_lonlat.tif";
    GDALClose(createTiff(f, {64, 64, 1, GDT_Float32, {10, 0.1, 0, 50, 0, -0.1}, 0}));
    auto src = openDem(f);
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_NEAR((*src)->coverage().west, 10.0, 1e-9);
    EXPECT_NEAR((*src)->coverage().north, 50.0, 1e-9);
    EXPECT_NE((*src)->describe().find("assumed"), std::string::npos);
}

TEST(RasterSource, BandOutOfRangeIsAClearError) {
    RasterSourceOptions o;
    o.path = imageRgb().string();
    o.bands = {1, 2, 7};
    auto src = RasterSource::open(o);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.message().find(o.path), std::string::npos) << src.message();
    EXPECT_NE(src.message().find("band 7 out of range"), std::string::npos) << src.message();
}

TEST(RasterSource, ReadWithTheWrongRoleOrSizeIsAnError) {
    auto dem = openDem(demLonLat());
    ASSERT_TRUE(dem.ok()) << dem.message();
    EXPECT_FALSE((*dem)->readImagery({10, 45, 11, 46}, 64).ok());
    EXPECT_FALSE((*dem)->readElevation({10, 45, 11, 46}, 1).ok());
    EXPECT_FALSE((*dem)->readElevation({11, 45, 10, 46}, 65).ok());
}

// ---------------------------------------------------------------------------------------------
// Elevation

TEST(RasterSource, CoverageAndLevelsOfLonLatDem) {
    auto src = openDem(demLonLat());
    ASSERT_TRUE(src.ok()) << src.message();
    const GeoExtent c = (*src)->coverage();
    // The raster's outer pixel edges, to floating-point noise.
    EXPECT_NEAR(c.west, 9.995, 1e-9);
    EXPECT_NEAR(c.east, 12.005, 1e-9);
    EXPECT_NEAR(c.south, 44.995, 1e-9);
    EXPECT_NEAR(c.north, 47.005, 1e-9);
    EXPECT_NEAR((*src)->resolutionDeg(), 0.01, 1e-9);
    EXPECT_EQ((*src)->minLevel(), 0u);
    // 65-sample tiles reach 0.01 deg pixels at level 9 (180 / 512 / 65 = 0.0054 <= 0.01 < 0.0108).
    EXPECT_EQ((*src)->maxLevel(65), 9u);
    EXPECT_TRUE((*src)->covers({11, 46, 11.5, 46.5}));
    EXPECT_FALSE((*src)->covers({-20, 46, -19, 47}));
    const std::string d = (*src)->describe();
    EXPECT_NE(d.find("GTiff"), std::string::npos) << d;
    EXPECT_NE(d.find("EPSG:4326"), std::string::npos) << d;
    EXPECT_NE(d.find("nodata -9999"), std::string::npos) << d;
}

TEST(RasterSource, ElevationMatchesAnalyticHeights) {
    auto src = openDem(demLonLat());
    ASSERT_TRUE(src.ok()) << src.message();
    // Samples every 0.005 deg: magnified 2x, so GDAL's bilinear is plain bilinear interpolation.
    const GeoExtent e{10.2, 45.2, 10.52, 45.52};
    auto t = (*src)->readElevation(e, 65);
    ASSERT_TRUE(t.ok()) << t.message();
    ASSERT_EQ(t->heights.size(), 65u * 65u);
    ASSERT_TRUE(t->anyValid);
    for (int j = 0; j < 65; j += 4)
        for (int i = 0; i < 65; i += 4) {
            // Corner-aligned samples. 0.01 m: bilinear error of the wave (0.5 mm) plus Float32.
            const double lon = e.west + i * e.width() / 64, lat = e.north - j * e.height() / 64;
            EXPECT_NEAR(t->heights[size_t(j * 65 + i)], heightAt(lon, lat), 0.01) << "at " << lon << ", " << lat;
        }
    EXPECT_NEAR(t->minHeight, heightAt(10.2, 45.2), 0.01);

    // Minified (0.0109 deg samples over 0.01 deg pixels), GDAL widens bilinear into a triangle
    // filter over each sample's footprint: an antialiasing average whose normalised weights can
    // shift a 1.2 m-per-pixel slope by up to about a tenth of a pixel, hence 0.25 m.
    const GeoExtent coarse{10.2, 45.2, 10.9, 45.9};
    auto c = (*src)->readElevation(coarse, 65);
    ASSERT_TRUE(c.ok()) << c.message();
    for (int j = 0; j < 65; j += 4)
        for (int i = 0; i < 65; i += 4) {
            const double lon = coarse.west + i * coarse.width() / 64, lat = coarse.north - j * coarse.height() / 64;
            EXPECT_NEAR(c->heights[size_t(j * 65 + i)], heightAt(lon, lat), 0.25) << "at " << lon << ", " << lat;
        }
}

TEST(RasterSource, DtedVrtJpeg2000AndNetcdfDemsReadLikeGeoTiff) {
    // The same heights through four more GDAL drivers. DTED needs its own 1-degree cell
    // geometry (level 0: 121 x 121 posts, pixel-is-point); JPEG 2000 stores integers, written
    // reversibly (lossless), so the heights are rounded to the metre.
    GDALAllRegister();
    const fs::path dir = TempDir::path() / "formats";
    fs::create_directories(dir);
    std::vector<std::pair<std::string, double>> files;   // file, tolerance (m)

    {   // VRT over the GeoTIFF.
        GDALDatasetH tif = GDALOpen(demLonLat().c_str(), GA_ReadOnly);
        ASSERT_NE(tif, nullptr);
        const std::string vrt = (dir / "dem.vrt").string();
        GDALDatasetH out = GDALCreateCopy(GDALGetDriverByName("VRT"), vrt.c_str(), tif, FALSE, nullptr, nullptr, nullptr);
        ASSERT_NE(out, nullptr) << CPLGetLastErrorMsg();
        GDALClose(out);
        // netCDF (CF lat/lon variables, _FillValue from the nodata value).
        const std::string nc = (dir / "dem.nc").string();
        out = GDALCreateCopy(GDALGetDriverByName("netCDF"), nc.c_str(), tif, FALSE, nullptr, nullptr, nullptr);
        ASSERT_NE(out, nullptr) << CPLGetLastErrorMsg();
        GDALClose(out);
        // JPEG 2000, Int16, lossless.
        const std::string jp2 = (dir / "dem.jp2").string();
        const char* translateArgs[] = {"-ot", "Int16", "-of", "JP2OpenJPEG", "-co", "REVERSIBLE=YES", "-co",
                                       "QUALITY=100", nullptr};
        GDALTranslateOptions* t = GDALTranslateOptionsNew(const_cast<char**>(translateArgs), nullptr);
        int usageError = 0;
        out = GDALTranslate(jp2.c_str(), tif, t, &usageError);
        GDALTranslateOptionsFree(t);
        ASSERT_NE(out, nullptr) << CPLGetLastErrorMsg();
        GDALClose(out);
        GDALClose(tif);
        files = {{vrt, 0.01}, {nc, 0.01}, {jp2, 0.51}};
    }
    {   // DTED level 0 of the cell lon 10..11, lat 45..46.
        constexpr int kPosts = 121;
        constexpr double kStep = 1.0 / (kPosts - 1);
        GDALDatasetH mem = GDALCreate(GDALGetDriverByName("MEM"), "", kPosts, kPosts, 1, GDT_Int16, nullptr);
        double gt[6] = {10.0 - 0.5 * kStep, kStep, 0, 46.0 + 0.5 * kStep, 0, -kStep};
        GDALSetGeoTransform(mem, gt);
        GDALSetProjection(mem, wktOf(4326).c_str());
        std::vector<int16_t> v(kPosts * kPosts);
        for (int j = 0; j < kPosts; ++j)
            for (int i = 0; i < kPosts; ++i)
                v[size_t(j * kPosts + i)] = int16_t(std::lround(heightAt(10.0 + i * kStep, 46.0 - j * kStep)));
        ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(mem, 1), GF_Write, 0, 0, kPosts, kPosts, v.data(), kPosts, kPosts,
                               GDT_Int16, 0, 0),
                  CE_None);
        const std::string dt0 = (dir / "n45e010.dt0").string();
        GDALDatasetH out = GDALCreateCopy(GDALGetDriverByName("DTED"), dt0.c_str(), mem, FALSE, nullptr, nullptr, nullptr);
        GDALClose(mem);
        ASSERT_NE(out, nullptr) << CPLGetLastErrorMsg();
        GDALClose(out);
        files.emplace_back(dt0, 0.51);
    }

    const GeoExtent e{10.2, 45.2, 10.52, 45.52};   // inside the DTED cell, away from the hole
    for (const auto& [file, tolerance] : files) {
        auto src = openDem(file);
        ASSERT_TRUE(src.ok()) << file << ": " << src.message();
        auto t = (*src)->readElevation(e, 65);
        ASSERT_TRUE(t.ok()) << file << ": " << t.message();
        ASSERT_TRUE(t->anyValid) << file;
        double worst = 0.0;
        for (int j = 0; j < 65; j += 4)
            for (int i = 0; i < 65; i += 4) {
                const double lon = e.west + i * e.width() / 64, lat = e.north - j * e.height() / 64;
                worst = std::max(worst, std::abs(double(t->heights[size_t(j * 65 + i)]) - heightAt(lon, lat)));
            }
        EXPECT_LE(worst, tolerance) << file;
        std::printf("%s: worst height error %.4f m\n", fs::path(file).filename().c_str(), worst);
    }
}

TEST(RasterSource, NodataBecomesNaNWithoutSpikes) {
    auto src = openDem(demLonLat());
    ASSERT_TRUE(src.ok()) << src.message();
    const GeoExtent e{11.1, 46.1, 11.5, 46.5};  // the hole 11.2..11.4 x 46.2..46.4 in the middle
    auto t = (*src)->readElevation(e, 65);
    ASSERT_TRUE(t.ok()) << t.message();
    int holes = 0;
    for (int j = 0; j < 65; ++j)
        for (int i = 0; i < 65; ++i) {
            const double lon = e.west + i * e.width() / 64, lat = e.north - j * e.height() / 64;
            const float h = t->heights[size_t(j * 65 + i)];
            if (lon > 11.22 && lon < 11.38 && lat > 46.22 && lat < 46.38) {
                EXPECT_TRUE(std::isnan(h)) << "inside the hole at " << lon << ", " << lat << ": " << h;
            }
            if (std::isnan(h)) {
                ++holes;
                EXPECT_TRUE(lon > 11.18 && lon < 11.42 && lat > 46.18 && lat < 46.42) << "NaN outside the hole";
                continue;
            }
            // Never a spike towards -9999: valid samples near the hole interpolate valid pixels
            // only, so they stay within one pixel's slope (1.2 m) of the true height.
            EXPECT_NEAR(h, heightAt(lon, lat), 1.5) << "at " << lon << ", " << lat;
        }
    EXPECT_GT(holes, 100);
    EXPECT_GT(t->minHeight, 1000.0f);
}

TEST(RasterSource, OutsideCoverageIsNaN) {
    auto src = openDem(demLonLat());
    ASSERT_TRUE(src.ok()) << src.message();
    auto away = (*src)->readElevation({-50, -10, -40, 0}, 65);
    ASSERT_TRUE(away.ok()) << away.message();
    EXPECT_FALSE(away->anyValid);
    EXPECT_TRUE(std::all_of(away->heights.begin(), away->heights.end(), [](float h) { return std::isnan(h); }));

    // A tile half over the data: the western half (lon < 9.995) is NaN, the eastern half valid.
    auto half = (*src)->readElevation({9.0, 45.5, 11.0, 46.5}, 65);
    ASSERT_TRUE(half.ok()) << half.message();
    EXPECT_TRUE(half->anyValid);
    for (int j = 0; j < 65; ++j) {
        EXPECT_TRUE(std::isnan(half->heights[size_t(j * 65 + 10)]));   // lon 9.3125
        EXPECT_FALSE(std::isnan(half->heights[size_t(j * 65 + 40)]));  // lon 10.25
    }
}

TEST(RasterSource, CoarseTilesReadTheMatchingOverview) {
    // 1024^2 pixels of 0.01 deg with overviews 2x, 4x, 8x; each level holds its own constant
    // (100 at full resolution, 1000 * factor in the overviews) so the value read names the level.
    const fs::path f = TempDir::path() / "with_overviews.tif";
    GDALDatasetH ds = createTiff(f, {1024, 1024, 1, GDT_Float32, {0, 0.01, 0, 50.24, 0, -0.01}});
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    ASSERT_EQ(GDALFillRaster(band, 100.0, 0.0), CE_None);
    int factors[] = {2, 4, 8};
    ASSERT_EQ(GDALBuildOverviews(ds, "NEAREST", 3, factors, 0, nullptr, nullptr, nullptr), CE_None);
    ASSERT_EQ(GDALGetOverviewCount(band), 3);
    for (int i = 0; i < 3; ++i) ASSERT_EQ(GDALFillRaster(GDALGetOverview(band, i), 1000.0 * factors[i], 0.0), CE_None);
    GDALClose(ds);

    auto src = openDem(f);
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_NE((*src)->describe().find("512x512 256x256 128x128"), std::string::npos) << (*src)->describe();
    auto valueAt = [&](const GeoExtent& e) {
        auto t = (*src)->readElevation(e, 65);
        EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.message());
        return t.ok() && t->anyValid ? t->heights[32 * 65 + 32] : -1.0f;
    };
    // Tile samples of 0.64 / 64 = 0.01 deg: full resolution.
    EXPECT_EQ(valueAt({4.0, 44.0, 4.64, 44.64}), 100.0f);
    // 0.025 deg: 2.5 source pixels per sample -> the 2x overview.
    EXPECT_EQ(valueAt({4.0, 44.0, 5.6, 45.6}), 2000.0f);
    // 0.1 deg: 10 per sample -> the coarsest (8x) overview.
    EXPECT_EQ(valueAt({2.0, 42.0, 8.4, 48.4}), 8000.0f);
}

// A file replaced while it is read (a tool writes a new one and renames it over the old): the
// open dataset keeps reading what it opened, and what is opened again (an overview, another
// thread's handle) must match it, else the read says the file changed instead of mixing two.
TEST(RasterSource, FileReplacedWhileReadSaysSoInsteadOfMixingTwoFiles) {
    const auto write = [](const fs::path& f, int side, double originLon) {
        GDALDatasetH ds = createTiff(f, {side, side, 1, GDT_Float32, {originLon, 0.01, 0, 50.24, 0, -0.01}});
        ASSERT_NE(ds, nullptr);
        ASSERT_EQ(GDALFillRaster(GDALGetRasterBand(ds, 1), 100.0, 0.0), CE_None);
        int factors[] = {2, 4};
        ASSERT_EQ(GDALBuildOverviews(ds, "NEAREST", 2, factors, 0, nullptr, nullptr, nullptr), CE_None);
        GDALClose(ds);
    };
    const fs::path f = TempDir::path() / "replaced.tif", next = TempDir::path() / "replacement.tif";
    write(f, 1024, 0.0);
    auto src = openDem(f);
    ASSERT_TRUE(src.ok()) << src.message();
    const GeoExtent fine{4.0, 44.0, 4.64, 44.64}, coarse{4.0, 44.0, 5.6, 45.6};
    auto before = (*src)->readElevation(fine, 65);
    ASSERT_TRUE(before.ok()) << before.message();
    EXPECT_EQ(before->heights[32 * 65 + 32], 100.0f);

    write(next, 512, 3.0);
    fs::rename(next, f);
    auto overview = (*src)->readElevation(coarse, 65);   // opens the 2x overview: the new file's
    ASSERT_FALSE(overview.ok());
    EXPECT_NE(overview.message().find(f.string()), std::string::npos) << overview.message();
    EXPECT_NE(overview.message().find("changed on disk since it was opened"), std::string::npos) << overview.message();
    auto again = (*src)->readElevation(fine, 65);   // the open dataset: the file it opened
    ASSERT_TRUE(again.ok()) << again.message();
    EXPECT_EQ(again->heights[32 * 65 + 32], 100.0f);
}

TEST(RasterSource, UtmDemLandsAtTheRightLonLat) {
    auto src = openDem(demUtm());
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_NE((*src)->describe().find("EPSG:32632"), std::string::npos);
    const GeoExtent c = (*src)->coverage();
    EXPECT_TRUE(c.contains(11.0, 46.0)) << c.west << " " << c.south << " " << c.east << " " << c.north;
    // About 0.001 deg of pixel = 100 m.
    EXPECT_NEAR((*src)->resolutionDeg(), 0.0009, 0.0003);
    for (const auto& [lon, lat] : {std::pair{10.9, 45.9}, {11.0, 46.0}, {11.1, 46.1}, {10.95, 46.15}}) {
        // 0.1 m: 1/8 of a 100 m pixel times a slope of 0.0013 m/m, plus bilinear over 100 m.
        EXPECT_NEAR(heightAtPoint(**src, lon, lat), heightAt(lon, lat), 0.1) << lon << ", " << lat;
    }
    EXPECT_TRUE(std::isnan(heightAtPoint(**src, 11.3, 46.3)));  // the hole
}

// ---------------------------------------------------------------------------------------------
// Imagery

TEST(RasterSource, ImageryBandSelectionSwapsChannels) {
    RasterSourceOptions o;
    o.path = imageRgb().string();
    auto rgb = RasterSource::open(o);
    ASSERT_TRUE(rgb.ok()) << rgb.message();
    o.bands = {3, 2, 1};
    auto bgr = RasterSource::open(o);
    ASSERT_TRUE(bgr.ok()) << bgr.message();

    const GeoExtent e{-5, 0, 5, 10};  // the western half lies outside the image
    auto a = (*rgb)->readImagery(e, 32);
    auto b = (*bgr)->readImagery(e, 32);
    ASSERT_TRUE(a.ok()) << a.message();
    ASSERT_TRUE(b.ok()) << b.message();
    ASSERT_EQ(a->rgba.size(), 32u * 32u * 4u);
    const uint8_t* in = &a->rgba[(16 * 32 + 24) * 4];  // lon 2.5, lat 4.8
    EXPECT_EQ(in[0], 200);
    EXPECT_EQ(in[1], 100);
    EXPECT_EQ(in[2], 50);
    EXPECT_EQ(in[3], 255);
    const uint8_t* swapped = &b->rgba[(16 * 32 + 24) * 4];
    EXPECT_EQ(swapped[0], 50);
    EXPECT_EQ(swapped[1], 100);
    EXPECT_EQ(swapped[2], 200);
    const uint8_t* out = &a->rgba[(16 * 32 + 4) * 4];  // lon -3.6: no data
    EXPECT_EQ(out[3], 0);
}

// ---------------------------------------------------------------------------------------------
// Huge files, threads, cancellation

TEST(RasterSource, HugeSparseFileIsShownFromMinLevelWithOneWarning) {
    const fs::path f = hugeSparse();
    testing::internal::CaptureStderr();
    auto src = openDem(f);
    const std::string log = testing::internal::GetCapturedStderr();
    ASSERT_TRUE(src.ok()) << src.message();
    // 10 deg over 10^6 pixels: a tile may span 16 Mi pixels = 4096^2 = 0.041 deg, first reached at
    // level 13 (180 / 2^13 = 0.022 deg).
    EXPECT_EQ((*src)->minLevel(), 13u);
    EXPECT_NE(log.find(f.string()), std::string::npos) << log;
    EXPECT_NE(log.find("1000000 x 1000000"), std::string::npos) << log;
    EXPECT_NE(log.find("level 13"), std::string::npos) << log;
    EXPECT_NE(log.find("gdaladdo"), std::string::npos) << log;
    EXPECT_EQ(log.find("warn"), log.rfind("warn")) << "one warning: " << log;

    const long rssBefore = maxRssKb();
    const auto t0 = std::chrono::steady_clock::now();
    auto coarse = (*src)->readElevation(TileKey{0, 1, 0}.extent(), 65);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(coarse.ok()) << coarse.message();
    EXPECT_FALSE(coarse->anyValid);
    EXPECT_LT(ms, 1000.0);  // returns at once: nothing is read
    EXPECT_LT(maxRssKb() - rssBefore, 64 * 1024);

    // At minLevel the (sparse, zero) data is read: one 4096^2 block at most.
    const TileKey fine = TileKey::containing(5.0, 45.0, 13);
    auto t = (*src)->readElevation(fine.extent(), 65);
    ASSERT_TRUE(t.ok()) << t.message();
    EXPECT_TRUE(t->anyValid);
    EXPECT_EQ(t->maxHeight, 0.0f);
    EXPECT_LT(maxRssKb() - rssBefore, 256 * 1024);
}

TEST(RasterSource, ConcurrentReadsMatchSingleThreaded) {
    auto src = openDem(demUtm());
    ASSERT_TRUE(src.ok()) << src.message();
    std::vector<GeoExtent> extents;
    for (int k = 0; k < 16; ++k) {
        const double lon = 10.8 + 0.03 * k, lat = 45.9 + 0.02 * k;
        extents.push_back({lon, lat, lon + 0.1, lat + 0.1});
    }
    std::vector<std::vector<float>> serial;
    for (const auto& e : extents) {
        auto t = (*src)->readElevation(e, 65);
        ASSERT_TRUE(t.ok()) << t.message();
        serial.push_back(t->heights);
    }
    std::vector<std::vector<float>> parallel(extents.size());
    std::atomic<int> failures{0};
    auto worker = [&](size_t first) {
        for (int round = 0; round < 3; ++round)
            for (size_t k = first; k < extents.size(); k += 2) {
                auto t = (*src)->readElevation(extents[k], 65);
                if (!t.ok()) {
                    ++failures;
                    continue;
                }
                parallel[k] = t->heights;
            }
    };
    std::thread a(worker, 0), b(worker, 1);
    a.join();
    b.join();
    EXPECT_EQ(failures.load(), 0);
    for (size_t k = 0; k < extents.size(); ++k) {
        ASSERT_EQ(parallel[k].size(), serial[k].size());
        // Same code, same data: bit-identical (memcmp, so NaN compares equal to NaN).
        EXPECT_EQ(std::memcmp(parallel[k].data(), serial[k].data(), serial[k].size() * sizeof(float)), 0) << k;
    }
    EXPECT_LE((*src)->openHandles(), (*src)->maxHandles());
    EXPECT_GE((*src)->openHandles(), 1);
}

TEST(RasterSource, CancelledReadReturnsCancelled) {
    auto src = openDem(demLonLat());
    ASSERT_TRUE(src.ok()) << src.message();
    jobs::CancelToken token = jobs::CancelToken::create();
    token.cancel();
    auto t = (*src)->readElevation({10, 45, 11, 46}, 65, &token);
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.message().find("cancelled"), std::string::npos) << t.message();
    jobs::CancelToken live = jobs::CancelToken::create();
    EXPECT_TRUE((*src)->readElevation({10, 45, 11, 46}, 65, &live).ok());
}

TEST(RasterSource, DescribeJsonListsDriverCrsAndLevels) {
    auto json = describeRasterJson(demUtm().string());
    ASSERT_TRUE(json.ok()) << json.message();
    EXPECT_NE(json->find("\"driver\": \"GTiff\""), std::string::npos) << *json;
    EXPECT_NE(json->find("\"epsg\": 32632"), std::string::npos) << *json;
    EXPECT_NE(json->find("\"minLevel\": 0"), std::string::npos) << *json;
    EXPECT_NE(json->find("\"noData\": -9999"), std::string::npos) << *json;
    EXPECT_FALSE(describeRasterJson((TempDir::path() / "missing.tif").string()).ok());
}

// ---------------------------------------------------------------------------------------------
// Real data (../shared/data); skipped when absent

namespace {

fs::path sharedData(const char* relative) { return fs::path(ORBIS_SHARED_DATA_DIR) / relative; }

#define REQUIRE_SHARED(file)                                                                     \
    if (!fs::exists(file)) GTEST_SKIP() << "no shared test data at " << (file) << " (../shared/data is optional)"

}  // namespace

TEST(RasterSourceRealData, OlindaUtmHeightsMatchGdallocationinfo) {
    const fs::path f = sharedData("dem/olinda_dem_utm25s.tif");
    REQUIRE_SHARED(f);
    auto src = openDem(f);
    ASSERT_TRUE(src.ok()) << src.message();
    // Pixel centres (11,13), (44,52), (34,34) of the file, where the 3x3 neighbourhood varies by
    // at most 3 m; values from `gdallocationinfo -wgs84 -valonly FILE LON LAT`.
    const struct { double lon, lat, height; } kPoints[] = {
        {-34.90683, -7.96085, 71.0}, {-34.88004, -7.99270, 56.0}, {-34.88814, -7.97802, 63.0}};
    // The points are pixel centres, so bilinear returns the pixel's own value up to the warper's
    // 1/8-pixel approximation times the local slope (<= 3 m per pixel): 1 m.
    for (const auto& p : kPoints)
        EXPECT_NEAR(heightAtPoint(**src, p.lon, p.lat, 0.01), p.height, 1.0) << p.lon << ", " << p.lat;
}

TEST(RasterSourceRealData, LandsatBands321ReadAsImagery) {
    const fs::path f = sharedData("imagery/L7_ETMs.tif");
    REQUIRE_SHARED(f);
    RasterSourceOptions o;
    o.path = f.string();
    o.bands = {3, 2, 1};
    auto src = RasterSource::open(o);
    ASSERT_TRUE(src.ok()) << src.message();
    const GeoExtent c = (*src)->coverage();
    auto t = (*src)->readImagery(c, 256);
    ASSERT_TRUE(t.ok()) << t.message();
    ASSERT_TRUE(t->anyValid);
    size_t opaque = 0, coloured = 0;
    for (size_t p = 0; p < 256 * 256; ++p) {
        opaque += t->rgba[p * 4 + 3] == 255;
        coloured += t->rgba[p * 4] != t->rgba[p * 4 + 2];
    }
    EXPECT_GT(opaque, 256u * 256u * 9 / 10);  // the image fills its own coverage (UTM corners aside)
    EXPECT_GT(coloured, 256u * 256u / 2);     // not grey: three different bands
}

TEST(RasterSourceRealData, LuxembourgNodataHolesBecomeNaN) {
    const fs::path f = sharedData("dem/lux_elev.tif");
    REQUIRE_SHARED(f);
    auto src = openDem(f);
    ASSERT_TRUE(src.ok()) << src.message();
    auto t = (*src)->readElevation((*src)->coverage(), 65);
    ASSERT_TRUE(t.ok()) << t.message();
    size_t nan = 0, valid = 0;
    for (float h : t->heights) {
        if (std::isnan(h)) {
            ++nan;
            continue;
        }
        ++valid;
        EXPECT_GE(h, 141.0f);  // the file's own minimum and maximum: no spike from -32768
        EXPECT_LE(h, 547.0f);
    }
    EXPECT_GT(nan, 200u);
    EXPECT_GT(valid, 1000u);
    EXPECT_TRUE(std::isnan(heightAtPoint(**src, 5.75, 50.18, 0.01)));    // outside the border
    EXPECT_FALSE(std::isnan(heightAtPoint(**src, 6.1375, 49.8167, 0.01)));  // in the middle
}

TEST(RasterSourceRealData, WorldCoversPolesAndAntimeridian) {
    const fs::path f = sharedData("imagery/world.tif");
    REQUIRE_SHARED(f);
    RasterSourceOptions o;
    o.path = f.string();
    auto src = RasterSource::open(o);
    ASSERT_TRUE(src.ok()) << src.message();
    EXPECT_EQ((*src)->coverage(), (GeoExtent{-180, -90, 180, 90}));
    auto fullyOpaque = [](const ImageryTile& t) {
        for (size_t p = 0; p < t.rgba.size(); p += 4)
            if (t.rgba[p + 3] != 255) return false;
        return true;
    };
    // A polar tile, and tiles either side of the antimeridian.
    for (const TileKey key : {TileKey{2, 3, 0}, TileKey{2, 4, 3}, TileKey{1, 0, 0}, TileKey{1, 3, 1}}) {
        auto t = (*src)->readImagery(key.extent(), 256);
        ASSERT_TRUE(t.ok()) << t.message();
        EXPECT_TRUE(t->anyValid) << key.toString();
        EXPECT_TRUE(fullyOpaque(*t)) << key.toString();
    }
}
