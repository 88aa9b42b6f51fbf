// Heights for analysis at the DEM's own resolution (globe/ElevationSampler.h): a plane comes back
// exactly (bilinear is exact on it), a curved surface agrees with gdallocationinfo's pixel
// values at the pixels' centres within the surface's own change over a pixel, no data is none,
// a profile and a line of sight run over it.
#include "globe/ElevationSampler.h"
#include "globe/TerrainAnalysis.h"
#include "tests/support/ProcessTempDir.h"
#include "tests/support/Shell.h"

#include <gdal.h>
#include <ogr_srs_api.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace orbis::globe {
namespace {

namespace fs = std::filesystem;

constexpr double kNoData = -9999.0;

/// A lon/lat Float32 GeoTIFF of `n` x `n` pixels of `pixel` degrees from (west, north), heights
/// from `f` at the pixels' centres, no data where `f` gives NaN.
template <class F>
fs::path writeDem(const std::string& name, double west, double north, double pixel, int n, F f) {
    GDALAllRegister();
    const fs::path file = test::processTempDir("orbis-elevation-sampler") / name;
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), file.c_str(), n, n, 1, GDT_Float32, nullptr);
    double gt[6] = {west, pixel, 0.0, north, 0.0, -pixel};
    GDALSetGeoTransform(ds, gt);
    GDALSetProjection(ds, SRS_WKT_WGS84_LAT_LONG);
    std::vector<float> v(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double h = f(west + (i + 0.5) * pixel, north - (j + 0.5) * pixel);
            v[size_t(j) * size_t(n) + size_t(i)] = std::isnan(h) ? float(kNoData) : float(h);
        }
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    GDALSetRasterNoDataValue(b, kNoData);
    EXPECT_EQ(GDALRasterIO(b, GF_Write, 0, 0, n, n, v.data(), n, n, GDT_Float32, 0, 0), CE_None);
    GDALClose(ds);
    return file;
}

std::shared_ptr<const ElevationSampler> samplerOf(const fs::path& file) {
    auto source = RasterSource::open({.path = file.string(), .role = RasterRole::Elevation});
    EXPECT_TRUE(source.ok()) << source.message();
    if (!source) return nullptr;
    return std::make_shared<const ElevationSampler>(*source);
}

double plane(double lon, double lat) { return 100.0 + 2000.0 * (lon - 10.0) + 1000.0 * (lat - 45.0); }

TEST(ElevationSampler, APlaneComesBackExactlyAndOutsideIsNone) {
    const auto s = samplerOf(writeDem("plane.tif", 10.0, 45.1, 0.001, 100, plane));
    ASSERT_TRUE(s);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> lon(10.002, 10.098), lat(45.002, 45.098);
    for (int k = 0; k < 500; ++k) {
        const double x = lon(rng), y = lat(rng);
        const auto h = s->heightAt(x, y);
        ASSERT_TRUE(h) << x << " " << y;
        EXPECT_NEAR(*h, plane(x, y), 1e-3) << x << " " << y;
    }
    EXPECT_FALSE(s->heightAt(10.2, 45.05));
    EXPECT_FALSE(s->heightAt(9.0, 45.05));
    EXPECT_FALSE(s->heightAt(10.05, 95.0));
    EXPECT_FALSE(s->heightAt(NAN, 45.05));
    EXPECT_TRUE(s->error().empty()) << s->error();
    // Its cache read a few tiles, not one per sample.
    EXPECT_LT(s->tilesRead(), 20u);
}

TEST(ElevationSampler, AgreesWithGdallocationinfoAtThePixelsCentres) {
    if (test::runShell("command -v gdallocationinfo").exitCode != 0) GTEST_SKIP() << "gdallocationinfo (gdal-bin) is not installed";
    const auto hill = [](double lon, double lat) {
        const double dx = (lon - 10.05) / 0.02, dy = (lat - 45.05) / 0.02;
        return 300.0 + 250.0 * std::exp(-(dx * dx + dy * dy));
    };
    const fs::path file = writeDem("hill.tif", 10.0, 45.1, 0.001, 100, hill);
    const auto s = samplerOf(file);
    ASSERT_TRUE(s);
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> pixel(2, 97);
    for (int k = 0; k < 20; ++k) {
        const int i = pixel(rng), j = pixel(rng);
        const double lon = 10.0 + (i + 0.5) * 0.001, lat = 45.1 - (j + 0.5) * 0.001;
        const auto run = test::runShell("gdallocationinfo -valonly -wgs84 " + file.string() + " " + std::to_string(lon) + " " + std::to_string(lat));
        ASSERT_EQ(run.exitCode, 0) << run.output;
        const double gdal = std::stod(run.output);
        const auto ours = s->heightAt(lon, lat);
        ASSERT_TRUE(ours);
        // The surface's change over a pixel around there bounds the difference.
        double change = 0.0;
        for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
            change = std::max(change, std::abs(hill(lon + di * 0.001, lat + dj * 0.001) - hill(lon, lat)));
        EXPECT_NEAR(*ours, gdal, 0.5 * change + 1e-3) << "pixel " << i << ", " << j;
    }
}

TEST(ElevationSampler, AHoleIsNoneAndAProfileAndALineOfSightRunOverIt) {
    const auto ridge = [](double lon, double lat) {
        if (lat > 45.09) return double(NAN);   // no data along the north edge
        return std::abs(lon - 10.05) < 0.002 ? 400.0 : 100.0;
    };
    const auto s = samplerOf(writeDem("ridge.tif", 10.0, 45.1, 0.001, 100, ridge));
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->heightAt(10.02, 45.095));
    EXPECT_NEAR(*s->heightAt(10.02, 45.05), 100.0, 1e-3);
    EXPECT_NEAR(*s->heightAt(10.05, 45.05), 400.0, 1e-3);
    const HeightAt ground = ElevationSampler::function(s);
    const std::vector<LonLat> path{{10.01, 45.05}, {10.09, 45.05}};
    const TerrainProfile p = terrainProfile(path, ground, 20.0);
    EXPECT_EQ(p.unknown, 0u);
    EXPECT_NEAR(*p.maxHeight, 400.0, 1e-3);
    EXPECT_NEAR(*p.minHeight, 100.0, 1e-3);
    EXPECT_NEAR(p.ascentM, 300.0, 1e-3);
    EXPECT_FALSE(lineOfSight({10.01, 45.05, 102.0}, {10.09, 45.05, 102.0}, ground).visible);
    EXPECT_TRUE(lineOfSight({10.01, 45.05, 800.0}, {10.09, 45.05, 102.0}, ground).visible);   // 451 m over the ridge
}

}  // namespace
}  // namespace orbis::globe
