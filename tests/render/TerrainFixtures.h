#pragma once
// Small rasters written with GDAL at test time (the repository carries no binary fixtures):
// a DEM with a known mountain, an RGB image over the same area, and broken files.

#include <filesystem>
#include <string>

namespace orbis::test {

struct TerrainFixtures {
    std::filesystem::path dir;
    std::string dem;        ///< EPSG:4326, lon 6..8, lat 45..47, 401x401 Int16; mountain of kPeak m at (7, 46)
    std::string image;      ///< EPSG:4326, same area, 512x512 RGB: a colour gradient with a grid
    std::string noCrs;      ///< a GeoTIFF without a coordinate reference system
    std::string corrupt;    ///< a TIFF cut short
    std::string huge;       ///< declares 1 000 000 x 1 000 000 pixels (sparse: ~15 MB of block index on disk)
    std::string holed;      ///< the mountain DEM with a nodata square over lon 6.9..7.1, lat 45.9..46.1
    std::string coarse;     ///< kCoarseHeight m everywhere over lon 5..9, lat 44..48, 0.05 deg pixels
    static constexpr double kCoarseHeight = 1234.0;
    static constexpr double kPeak = 4000.0;
    static constexpr double kPeakLon = 7.0, kPeakLat = 46.0;
    /// The DEM's height function (metres): what the fixture encodes, before Int16 rounding.
    static double height(double lonDeg, double latDeg);
};

/// The fixtures, written once per build into the test output folder (safe under ctest -j).
const TerrainFixtures& terrainFixtures();

/// ../shared/data from the source tree, or empty when absent.
std::filesystem::path sharedDataDir();

}  // namespace orbis::test
