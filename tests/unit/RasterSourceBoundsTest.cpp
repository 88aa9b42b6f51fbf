// "bounds": a picture without georeferencing (a plate carree JPEG, as xplanet's earth.jpg)
// placed on a lon/lat box, read right at every level, the coarse ones through its overviews.
#include "globe/RasterSource.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace orbis::globe;

namespace {
TEST(RasterSource, BoundsPlaceAPictureWithoutGeoreferencingAtEveryLevel) {
    // A plate carrée JPEG without georeferencing (as xplanet's earth.jpg): west half red, east
    // half blue. JPEG has overviews (reduced decoding), which coarse tiles read.
    const fs::path dir = fs::temp_directory_path() / ("orbis-raster-bounds-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path jpg = dir / "plate-carree.jpg";
    GDALAllRegister();
    {
        const int w = 1024, h = 512;
        GDALDatasetH mem = GDALCreate(GDALGetDriverByName("MEM"), "", w, h, 3, GDT_Byte, nullptr);
        std::vector<uint8_t> band(size_t(w) * h);
        for (int b = 1; b <= 3; ++b) {
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) band[size_t(y) * w + x] = (b == 1) == (x < w / 2) ? 220 : 20;
            ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(mem, b), GF_Write, 0, 0, w, h, band.data(), w, h, GDT_Byte, 0, 0), CE_None);
        }
        GDALDatasetH out = GDALCreateCopy(GDALGetDriverByName("JPEG"), jpg.c_str(), mem, FALSE, nullptr, nullptr, nullptr);
        ASSERT_NE(out, nullptr);
        GDALClose(out);
        GDALClose(mem);
    }
    RasterSourceOptions o;
    o.path = jpg.string();
    auto plain = RasterSource::open(o);
    ASSERT_FALSE(plain.ok());   // no CRS and a pixel geotransform: refused, as any such file
    o.bounds = GeoExtent{-180, -90, 180, 90};
    auto placed = RasterSource::open(o);
    ASSERT_TRUE(placed.ok()) << placed.message();
    EXPECT_EQ((*placed)->coverage(), (GeoExtent{-180, -90, 180, 90}));
    // A level-0 tile (an overview) and a fine one: red in the west, blue in the east.
    for (const GeoExtent e : {GeoExtent{-180, -90, 180, 90}, GeoExtent{-10, -5, 10, 5}}) {
        auto t = (*placed)->readImagery(e, 64);
        ASSERT_TRUE(t.ok()) << t.message();
        const uint8_t* west = &t->rgba[(32 * 64 + 8) * 4];
        const uint8_t* east = &t->rgba[(32 * 64 + 56) * 4];
        EXPECT_GT(west[0], 180) << "west red at " << e.west;
        EXPECT_LT(west[2], 60);
        EXPECT_GT(east[2], 180) << "east blue at " << e.west;
        EXPECT_LT(east[0], 60);
        EXPECT_EQ(west[3], 255);
    }
    o.bounds = GeoExtent{10, 0, -10, 5};
    auto bad = RasterSource::open(o);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.message().find("bounds"), std::string::npos) << bad.message();
    std::error_code ec;
    fs::remove_all(dir, ec);
}

}  // namespace
