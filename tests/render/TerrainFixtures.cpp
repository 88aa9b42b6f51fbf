#include "tests/render/TerrainFixtures.h"

#include "tests/support/GoldenImage.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace orbis::test {
namespace {

std::string wgs84Wkt() {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, 4326);
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    std::string out = wkt;
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    return out;
}

GDALDatasetH create(const std::string& path, int w, int h, int bands, GDALDataType type, const char* const* options,
                    bool withCrs, double west, double north, double pixel) {
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, bands, type,
                                 const_cast<char**>(options));
    if (!ds) throw std::runtime_error("cannot create fixture " + path + ": " + CPLGetLastErrorMsg());
    const double gt[6] = {west, pixel, 0, north, 0, -pixel};
    GDALSetGeoTransform(ds, const_cast<double*>(gt));
    if (withCrs) GDALSetProjection(ds, wgs84Wkt().c_str());
    return ds;
}

TerrainFixtures paths(const std::filesystem::path& dir) {
    TerrainFixtures f;
    f.dir = dir;
    f.dem = (f.dir / "mountain.tif").string();
    f.image = (f.dir / "mountain-rgb.tif").string();
    f.noCrs = (f.dir / "no-crs.tif").string();
    f.corrupt = (f.dir / "corrupt.tif").string();
    f.huge = (f.dir / "huge.tif").string();
    f.holed = (f.dir / "holed.tif").string();
    f.coarse = (f.dir / "coarse.tif").string();
    return f;
}

/// Writes every fixture into f.dir.
void write(const TerrainFixtures& f) {
    {   // DEM: pixel centres on a 0.005 deg grid from lon 6 (so pixel edges at 6 -/+ 0.0025).
        const int n = 401;
        const double px = 2.0 / (n - 1);
        GDALDatasetH ds = create(f.dem, n, n, 1, GDT_Int16, nullptr, true, 6.0 - px / 2, 47.0 + px / 2, px);
        std::vector<int16_t> v(size_t(n) * n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                v[size_t(j) * n + i] = int16_t(std::lround(TerrainFixtures::height(6.0 + i * px, 47.0 - j * px)));
        GDALRasterBandH b = GDALGetRasterBand(ds, 1);
        GDALSetRasterNoDataValue(b, -32768);
        if (GDALRasterIO(b, GF_Write, 0, 0, n, n, v.data(), n, n, GDT_Int16, 0, 0) != CE_None)
            throw std::runtime_error("fixture write failed");
        GDALClose(ds);
    }
    {   // The same DEM with a nodata hole around the summit.
        const int n = 401;
        const double px = 2.0 / (n - 1);
        GDALDatasetH ds = create(f.holed, n, n, 1, GDT_Int16, nullptr, true, 6.0 - px / 2, 47.0 + px / 2, px);
        std::vector<int16_t> v(size_t(n) * n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double lon = 6.0 + i * px, lat = 47.0 - j * px;
                const bool hole = lon > 6.9 && lon < 7.1 && lat > 45.9 && lat < 46.1;
                v[size_t(j) * n + i] = hole ? int16_t(-32768) : int16_t(std::lround(TerrainFixtures::height(lon, lat)));
            }
        GDALRasterBandH b = GDALGetRasterBand(ds, 1);
        GDALSetRasterNoDataValue(b, -32768);
        if (GDALRasterIO(b, GF_Write, 0, 0, n, n, v.data(), n, n, GDT_Int16, 0, 0) != CE_None)
            throw std::runtime_error("fixture write failed");
        GDALClose(ds);
    }
    {   // A coarse constant DEM under it.
        GDALDatasetH ds = create(f.coarse, 80, 80, 1, GDT_Float32, nullptr, true, 5.0, 48.0, 0.05);
        std::vector<float> v(80 * 80, float(TerrainFixtures::kCoarseHeight));
        if (GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, 80, 80, v.data(), 80, 80, GDT_Float32, 0, 0) != CE_None)
            throw std::runtime_error("fixture write failed");
        GDALClose(ds);
    }
    {   // RGB image: a gradient (red east, green north) with dark grid lines every 0.25 deg.
        const int n = 512;
        const double px = 2.0 / n;
        const char* opts[] = {"PHOTOMETRIC=RGB", nullptr};
        GDALDatasetH ds = create(f.image, n, n, 3, GDT_Byte, opts, true, 6.0, 47.0, px);
        std::vector<uint8_t> v(size_t(n) * n * 3);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double lon = 6.0 + (i + 0.5) * px, lat = 47.0 - (j + 0.5) * px;
                const bool line = std::fmod(lon, 0.25) < px || std::fmod(lat, 0.25) < px;
                uint8_t* p = &v[(size_t(j) * n + i) * 3];
                p[0] = line ? 30 : uint8_t(60 + 180 * (lon - 6.0) / 2.0);
                p[1] = line ? 30 : uint8_t(60 + 180 * (lat - 45.0) / 2.0);
                p[2] = line ? 30 : 90;
            }
        if (GDALDatasetRasterIO(ds, GF_Write, 0, 0, n, n, v.data(), n, n, GDT_Byte, 3, nullptr, 3, 3 * n, 1) != CE_None)
            throw std::runtime_error("fixture write failed");
        GDALClose(ds);
    }
    {
        GDALDatasetH ds = create(f.noCrs, 16, 16, 1, GDT_Int16, nullptr, false, 1000.0, 2000.0, 30.0);
        GDALClose(ds);
    }
    {   // A valid TIFF cut to a third of its size.
        const std::string whole = (f.dir / "whole.tif").string();
        GDALDatasetH ds = create(whole, 256, 256, 1, GDT_Float32, nullptr, true, 6.0, 47.0, 0.01);
        std::vector<float> v(256 * 256, 100.0f);
        if (GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, 256, 256, v.data(), 256, 256, GDT_Float32, 0, 0) !=
            CE_None)
            throw std::runtime_error("fixture write failed");
        GDALClose(ds);
        std::ifstream in(whole, std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream out(f.corrupt, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size() / 3));
    }
    {
        // 1024-pixel blocks keep the block index (and so the file) near 15 MB.
        const char* opts[] = {"TILED=YES", "BLOCKXSIZE=1024", "BLOCKYSIZE=1024", "SPARSE_OK=TRUE", "BIGTIFF=YES",
                              nullptr};
        GDALDatasetH ds = create(f.huge, 1000000, 1000000, 1, GDT_Int16, opts, true, -180.0, 90.0, 180.0 / 1000000);
        GDALClose(ds);
    }
}

/// Test processes run in parallel (ctest -j), so the fixtures are written once per build of this
/// file into a folder named after its compile time, built under a private name and published with
/// an atomic rename: no process ever reads a file another one is still writing.
TerrainFixtures make() {
    namespace fs = std::filesystem;
    GDALAllRegister();
    std::string stamp = std::string(__DATE__ "-" __TIME__);
    for (char& c : stamp)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '-';
    const fs::path root = testOutputDir();
    const std::string name = "terrain-fixtures-" + stamp;
    const fs::path final = root / name;
    if (fs::exists(final / "complete")) return paths(final);

    const fs::path tmp = root / ("terrain-fixtures-tmp-" + std::to_string(::getpid()));
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    write(paths(tmp));
    std::ofstream(tmp / "complete") << "ok\n";
    std::error_code ec;
    fs::rename(tmp, final, ec);
    if (ec) fs::remove_all(tmp, ec);   // another process published first: use its copy
    if (!fs::exists(final / "complete")) throw std::runtime_error("cannot publish fixtures in " + final.string());

    // Earlier builds' fixtures, and leftovers of processes that died while writing.
    for (const auto& e : fs::directory_iterator(root, ec)) {
        const std::string n = e.path().filename().string();
        const bool old = n.starts_with("terrain-fixtures") && n != name && !n.starts_with("terrain-fixtures-tmp-");
        const bool deadTmp = n.starts_with("terrain-fixtures-tmp-") &&
                             fs::last_write_time(e.path(), ec) < fs::file_time_type::clock::now() - std::chrono::hours(1);
        if (old || deadTmp) fs::remove_all(e.path(), ec);
    }
    return paths(final);
}

}  // namespace

double TerrainFixtures::height(double lon, double lat) {
    const double dx = (lon - kPeakLon) * std::cos(kPeakLat * 3.14159265358979 / 180.0), dy = lat - kPeakLat;
    const double r2 = (dx * dx + dy * dy) / (0.25 * 0.25);
    return 300.0 + (kPeak - 300.0) * std::exp(-r2) + 80.0 * std::sin(lon * 9.0) * std::cos(lat * 7.0);
}

const TerrainFixtures& terrainFixtures() {
    static const TerrainFixtures f = make();
    return f;
}

std::filesystem::path sharedDataDir() {
    const std::filesystem::path p = std::filesystem::path(ORBIS_SOURCE_DIR) / ".." / "shared" / "data";
    return std::filesystem::exists(p / "dem") ? p : std::filesystem::path();
}

}  // namespace orbis::test
