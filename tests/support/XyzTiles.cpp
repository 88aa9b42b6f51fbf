#include "tests/support/XyzTiles.h"

#include <cpl_conv.h>
#include <gdal.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace orbis::test {

uint8_t xyzRedAt(double lon) { return uint8_t(std::lround((lon + 180.0) / 360.0 * 255.0)); }
uint8_t xyzGreenAt(double lat) { return uint8_t(std::lround((lat + 90.0) / 180.0 * 255.0)); }

std::string writeXyzTiles(const std::filesystem::path& root, int maxZoom) {
    GDALAllRegister();
    constexpr double kR = 6378137.0, kHalf = std::numbers::pi * kR, kDeg = 180.0 / std::numbers::pi;
    for (int z = 0; z <= maxZoom; ++z)
        for (int x = 0; x < (1 << z); ++x)
            for (int y = 0; y < (1 << z); ++y) {
                const double span = 2 * kHalf / (1 << z), px = span / 256;
                std::vector<uint8_t> r(256 * 256), g(256 * 256), b(256 * 256, 128);
                for (int j = 0; j < 256; ++j)
                    for (int i = 0; i < 256; ++i) {
                        const double mx = -kHalf + x * span + (i + 0.5) * px, my = kHalf - y * span - (j + 0.5) * px;
                        r[size_t(j * 256 + i)] = xyzRedAt(mx / kR * kDeg);
                        g[size_t(j * 256 + i)] = xyzGreenAt(std::atan(std::sinh(my / kR)) * kDeg);
                    }
                GDALDatasetH mem = GDALCreate(GDALGetDriverByName("MEM"), "", 256, 256, 3, GDT_Byte, nullptr);
                if (!mem) return "cannot create an in-memory raster";
                uint8_t* planes[3] = {r.data(), g.data(), b.data()};
                for (int k = 0; k < 3; ++k)
                    if (GDALRasterIO(GDALGetRasterBand(mem, k + 1), GF_Write, 0, 0, 256, 256, planes[k], 256, 256,
                                     GDT_Byte, 0, 0) != CE_None) {
                        GDALClose(mem);
                        return std::string("cannot fill a tile: ") + CPLGetLastErrorMsg();
                    }
                const auto file = root / std::to_string(z) / std::to_string(x) / (std::to_string(y) + ".png");
                std::filesystem::create_directories(file.parent_path());
                GDALDatasetH png =
                    GDALCreateCopy(GDALGetDriverByName("PNG"), file.c_str(), mem, FALSE, nullptr, nullptr, nullptr);
                GDALClose(mem);
                if (!png) return "cannot write " + file.string() + ": " + CPLGetLastErrorMsg();
                GDALClose(png);
            }
    return {};
}

}  // namespace orbis::test
