#include "globe/ViewshedGdal.h"

#include "globe/GdalSetup.h"

#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_srs_api.h>
#include <cpl_conv.h>
#include <cpl_error.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace orbis::globe {
namespace {

struct DatasetCloser {
    void operator()(void* ds) const {
        if (ds) GDALClose(ds);
    }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

void georeference(GDALDatasetH ds, const ViewshedGrid& grid) {
    const double half = (grid.radiusCells + 0.5) * grid.cellM;
    double gt[6] = {-half, grid.cellM, 0.0, half, 0.0, -grid.cellM};
    GDALSetGeoTransform(ds, gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    if (OSRImportFromProj4(srs, viewshedGridProj(grid).c_str()) == OGRERR_NONE) GDALSetSpatialRef(ds, srs);
    OSRDestroySpatialReference(srs);
}

std::string lastGdalError(const char* fallback) {
    const char* m = CPLGetLastErrorMsg();
    return m && *m ? std::string(m) : std::string(fallback);
}

}  // namespace

std::string viewshedGridProj(const ViewshedGrid& grid) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "+proj=aeqd +lat_0=%.12f +lon_0=%.12f +x_0=0 +y_0=0 +datum=WGS84 +units=m +no_defs", grid.centre.y,
                  grid.centre.x);
    return buf;
}

Result<Viewshed> viewshedGdal(const ViewshedGrid& grid, const ViewshedOptions& options, double* seconds) {
    auto eye = viewshedEyeHeight(grid, options);
    if (!eye) return eye.error();
    for (float h : grid.heights)
        if (!std::isfinite(h)) return makeError("GDAL's viewshed cannot take a grid with no-data cells");
    configureGdal();
    const int side = grid.side();
    GDALDriverH mem = GDALGetDriverByName("MEM");
    if (!mem) return makeError("GDAL has no MEM driver");
    Dataset src(GDALCreate(mem, "", side, side, 1, GDT_Float32, nullptr));
    if (!src) return makeError("could not make an in-memory raster of " + std::to_string(side) + " cells a side");
    georeference(src.get(), grid);
    GDALRasterBandH band = GDALGetRasterBand(src.get(), 1);
    if (GDALRasterIO(band, GF_Write, 0, 0, side, side, const_cast<float*>(grid.heights.data()), side, side, GDT_Float32, 0, 0) != CE_None)
        return makeError("could not fill the in-memory raster: " + lastGdalError("RasterIO failed"));
    const double x = grid.east(options.observerCol), y = grid.north(options.observerRow);
    CPLErrorReset();
    const auto t0 = std::chrono::steady_clock::now();
    Dataset out(GDALViewshedGenerate(band, "MEM", "", nullptr, x, y, options.observerHeight, options.targetHeight, 1.0, 0.0, 2.0, -1.0,
                                     options.curvature, GVM_Edge, options.radiusM, nullptr, nullptr, GVOT_NORMAL, nullptr));
    if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!out) return makeError("GDAL's viewshed failed: " + lastGdalError("no reason given"));
    double gt[6];
    GDALGetGeoTransform(out.get(), gt);
    const int xOff = int(std::lround((gt[0] + (grid.radiusCells + 0.5) * grid.cellM) / grid.cellM));
    const int yOff = int(std::lround(((grid.radiusCells + 0.5) * grid.cellM - gt[3]) / grid.cellM));
    const int w = GDALGetRasterXSize(out.get()), h = GDALGetRasterYSize(out.get());
    std::vector<uint8_t> bytes(size_t(w) * size_t(h));
    if (GDALRasterIO(GDALGetRasterBand(out.get(), 1), GF_Read, 0, 0, w, h, bytes.data(), w, h, GDT_Byte, 0, 0) != CE_None)
        return makeError("could not read GDAL's viewshed: " + lastGdalError("RasterIO failed"));
    Viewshed v;
    v.side = side;
    v.cells.assign(size_t(side) * size_t(side), Sight::OutOfRange);
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            const int c = col + xOff, r = row + yOff;
            if (c < 0 || r < 0 || c >= side || r >= side) continue;
            const uint8_t b = bytes[size_t(row) * size_t(w) + size_t(col)];
            v.cells[size_t(r) * size_t(side) + size_t(c)] = b == 1 ? Sight::Visible : b == 0 ? Sight::Hidden : Sight::OutOfRange;
        }
    return v;
}

namespace {

Result<void> writeTiff(const ViewshedGrid& grid, const std::string& path, GDALDataType type, const void* data, double nodata) {
    configureGdal();
    GDALDriverH gtiff = GDALGetDriverByName("GTiff");
    if (!gtiff) return makeError("GDAL has no GTiff driver");
    const int side = grid.side();
    const char* options[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
    CPLErrorReset();
    Dataset ds(GDALCreate(gtiff, path.c_str(), side, side, 1, type, const_cast<char**>(options)));
    if (!ds) return makeError(path + ": cannot be written: " + lastGdalError("GDALCreate failed"));
    georeference(ds.get(), grid);
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    GDALSetRasterNoDataValue(band, nodata);
    if (GDALRasterIO(band, GF_Write, 0, 0, side, side, const_cast<void*>(data), side, side, type, 0, 0) != CE_None)
        return makeError(path + ": cannot be written: " + lastGdalError("RasterIO failed"));
    ds.reset();
    if (CPLGetLastErrorType() >= CE_Failure) return makeError(path + ": " + lastGdalError("the file could not be closed"));
    return {};
}

}  // namespace

Result<void> writeViewshedGridTiff(const ViewshedGrid& grid, const std::string& path) {
    if (grid.heights.size() != size_t(grid.side()) * size_t(grid.side())) return makeError("the viewshed grid is inconsistent");
    return writeTiff(grid, path, GDT_Float32, grid.heights.data(), std::nan(""));
}

Result<void> writeViewshedTiff(const ViewshedGrid& grid, const Viewshed& viewshed, const std::string& path) {
    if (viewshed.side != grid.side() || viewshed.cells.size() != size_t(grid.side()) * size_t(grid.side()))
        return makeError("the viewshed does not match its grid");
    std::vector<uint8_t> bytes(viewshed.cells.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        const Sight s = viewshed.cells[i];
        bytes[i] = s == Sight::Visible ? 255 : s == Sight::Hidden ? 0 : s == Sight::OutOfRange ? 1 : 2;
    }
    return writeTiff(grid, path, GDT_Byte, bytes.data(), 2.0);
}

}  // namespace orbis::globe
