#pragma once
// Internals of RasterSource shared by RasterSource.cpp (the public API: open, reads, describe)
// and RasterSourceGdal.cpp (GDAL configuration, the handle pool, warping, inspecting a file).
// Not part of the globe module's interface: include it from those two files only.

#include "globe/GdalSetup.h"
#include "globe/RasterSource.h"

#include "base/Log.h"
#include "base/Secrets.h"
#include "base/ThreadPool.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdalwarper.h>
#include <ogr_srs_api.h>

#include <array>
#include <condition_variable>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::globe {
namespace raster_detail {

constexpr int kMaxTileSize = 4096;
constexpr double kApproxErrorPx = 0.125;  // gdalwarp's default -et: invisible, several x faster
constexpr int kMaxWarpOpsPerLevel = 4;    // tile sizes cached per pooled handle and level
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();


// ---------------------------------------------------------------------------------------------
// GDAL's messages for this thread, captured instead of printed (GDAL's handler stack is per
// thread). Keeps the first few failures; warnings go to the debug log.

class GdalErrors {
public:
    GdalErrors() { CPLPushErrorHandlerEx(&GdalErrors::handler, this); }
    ~GdalErrors() { CPLPopErrorHandler(); }
    GdalErrors(const GdalErrors&) = delete;
    GdalErrors& operator=(const GdalErrors&) = delete;

    bool any() const { return !messages_.empty(); }
    /// "; "-joined failures (each said once, in GDAL's HTTP clients' words made plain: see
    /// plainGdalMessage), or `fallback` when GDAL said nothing.
    std::string text(const char* fallback = "unknown GDAL error") const;
    void clear() { messages_.clear(); }

private:
    static void CPL_STDCALL handler(CPLErr level, CPLErrorNum, const char* msg) {
        auto* self = static_cast<GdalErrors*>(CPLGetErrorHandlerUserData());
        if (!self || !msg) return;
        if (level >= CE_Failure) {
            log::debug("GDAL: ", redactSecrets(msg));
            if (self->messages_.size() < 8) self->messages_.emplace_back(std::string(msg).substr(0, 1000));
        } else if (level == CE_Warning) {
            log::debug("GDAL: ", redactSecrets(msg));
        }
    }
    std::vector<std::string> messages_;
};

/// One GDAL error in plain words: a WMS block that failed to download becomes "the server
/// answered HTTP 500: <its text>" or "no answer: <curl's reason>"; an image that does not
/// decode, "the server sent a damaged image (<decoder's words>)"; a block-read prefix ("IReadBlock
/// failed at ...") is dropped. Empty for the noise around them (the cache miss before a
/// download, "Unable to open downloaded block").
std::string plainGdalMessage(const std::string& message);

bool isRemotePath(const std::string& path);
/// A GDAL WMS (TMS minidriver) description of an XYZ server: EPSG:3857, 256-pixel tiles, y down,
/// four bands (alpha 0 where the server has no tile: 404/204 are empty blocks, not errors).
std::string xyzToWmsXml(const std::string& xyzUrl, int maxZoom, const std::string& cacheDir);
/// For a WMS dataset GDAL opened from a "WMS:URL" string (which has no disk cache and waits
/// 300 s for an answer): its service description as XML, with Orbis's HTTP timeout
/// (GDAL_HTTP_TIMEOUT), the tile cache in `cacheDir`, and 4 connections added where it names
/// none. For elevation (`heights`): one band of Float32 (GDAL guesses three of bytes), for a
/// server that sends heights (FORMAT=image/tiff of a DEM). Nothing when `ds` is not such a
/// dataset.
std::optional<std::string> wmsUrlToXml(GDALDatasetH ds, const std::string& cacheDir, bool heights);
/// GDAL's resampling algorithm by gdalwarp's name (-r); *ok = false for an unknown name.
GDALResampleAlg resampleAlg(const std::string& name, bool* ok);
std::string fmtExtent(const GeoExtent& e);

// One resolution of the source inside a pooled handle: the dataset (full resolution or opened
// with OVERVIEW_LEVEL), its transformer to the tile grid and warp operations per tile size.
struct WarpOp {
    int size = 0;
    std::unique_ptr<GDALWarpOperation> op;
    GDALDatasetH alphaDst = nullptr;  // imagery: MEM dataset whose last band receives alpha

    WarpOp() = default;
    WarpOp(WarpOp&& o) noexcept { *this = std::move(o); }
    WarpOp& operator=(WarpOp&& o) noexcept {
        std::swap(size, o.size);
        std::swap(op, o.op);
        std::swap(alphaDst, o.alphaDst);
        return *this;
    }
    ~WarpOp() {
        op.reset();  // before the dataset it writes to
        if (alphaDst) GDALClose(alphaDst);
    }
};

struct Level {
    GDALDatasetH ds = nullptr;
    void* genImg = nullptr;  // owned by `approx`
    void* approx = nullptr;
    std::vector<WarpOp> ops;  // they use `approx` and `ds`: destroyed first

    Level() = default;
    Level(Level&& o) noexcept { *this = std::move(o); }
    Level& operator=(Level&& o) noexcept {
        std::swap(ds, o.ds);
        std::swap(genImg, o.genImg);
        std::swap(approx, o.approx);
        std::swap(ops, o.ops);
        return *this;
    }
    ~Level() {
        ops.clear();
        if (approx) GDALDestroyApproxTransformer(approx);
        if (ds) GDALClose(ds);
    }
};

struct Handle {
    std::vector<Level> levels;  // index = overview level + 1 (0 = full resolution); opened lazily
    const jobs::CancelToken* cancel = nullptr;  // the current call's, for the progress callback
};

/// A box in a source's full-resolution pixels.
struct PixelBox {
    double x0, y0, x1, y1;
};

/// GDALWarpOperation's progress callback: stops the warp when the handle's call is cancelled.
int CPL_STDCALL warpProgress(double, const char*, void* arg);

inline bool isCancelled(const jobs::CancelToken* c) { return c && c->cancelled(); }

/// Closes a dataset at the end of a scope.
struct DatasetGuard {
    GDALDatasetH ds;
    ~DatasetGuard() {
        if (ds) GDALClose(ds);
    }
};

inline const char* typeName(GDALDataType t) { return GDALGetDataTypeName(t) ? GDALGetDataTypeName(t) : "?"; }

}  // namespace raster_detail

struct RasterSource::Impl {
    using Handle = raster_detail::Handle;
    using Level = raster_detail::Level;
    using WarpOp = raster_detail::WarpOp;
    using GdalErrors = raster_detail::GdalErrors;
    RasterSourceOptions options;
    std::string name;      // for messages: the path or URL
    std::string openPath;  // what GDALOpenEx gets (the WMS XML for an XYZ URL)
    std::string cachePath; // options.cacheDir through the tile cache's file system; empty: GDAL's default
    RasterRole role = RasterRole::Imagery;

    // What the file is (fixed at open).
    struct BandInfo {
        std::string type, interp;
        std::optional<double> noData;
        double scale = 1.0, offset = 0.0;
    };
    std::vector<BandInfo> bandInfo;  // every band of the file
    std::string driver;
    int width = 0, height = 0, bandCount = 0;
    std::optional<std::array<double, 6>> geoTransform;  // none for GCPs or a picture placed by bounds
    std::string crsName, crsEpsg;
    bool assumedLonLat = false;
    std::vector<std::pair<int, int>> overviews;  // of the first read band, GDAL's order
    GeoExtent coverage;
    double resolutionDeg = 0.0;
    uint32_t minLevel = 0;

    // How it is read (fixed at open).
    std::vector<int> bands;  // data bands: 1 (elevation, grey, palette) or 3 (RGB)
    int srcAlpha = 0;
    bool palette = false;
    std::array<std::array<uint8_t, 4>, 256> paletteRgba{};
    GDALDataType workType = GDT_Float32;
    std::vector<double> noData;                         // per data band (NaN: none); empty if none
    std::vector<std::pair<double, double>> valueRange;  // imagery, non-Byte: per data band
    double valueScale = 1.0, valueOffset = 0.0;         // elevation: band scale/offset
    GDALResampleAlg resample = GRA_Bilinear;

    // The handle pool.
    int maxHandles = 2;
    mutable std::mutex poolMutex;
    mutable std::condition_variable poolCv;
    mutable std::vector<std::unique_ptr<Handle>> idle;
    mutable int opened = 0;

    ~Impl() {
        GdalErrors quiet;  // closing handles
        idle.clear();
    }

    /// "<name>: <what>", any password in them (a URL's user info, GDAL quoting a request) as ***.
    Error error(const std::string& what) const { return makeError(redactSecrets(name + ": " + what)); }

    // Opening, in this order.
    Result<bool> inspect(GDALDatasetH ds);
    Result<bool> planBands(GDALDatasetH ds);
    // planBands' steps, in this order.
    Result<bool> chooseBands(GDALDatasetH ds);   // bands, srcAlpha
    Result<bool> chooseWorkType(GDALDatasetH ds);
    void readPalette(GDALDatasetH ds);
    Result<bool> chooseResampling();
    void readNoData(GDALDatasetH ds);
    Result<bool> readValueScaling(GDALDatasetH ds);   // valueScale/valueOffset, or valueRange
    Result<bool> computeCoverage(Level& full);
    void computeLevels();
    Result<bool> probe(GDALDatasetH ds) const;

    Result<bool> makeTransformer(Level& level) const;
    /// Empty when `ds` (the file opened again) matches the first open: size, bands, geotransform.
    std::string changedSinceOpened(GDALDatasetH ds) const;
    Result<std::unique_ptr<Handle>> openHandle(GDALDatasetH alreadyOpen = nullptr) const;
    Result<bool> ensureLevel(Handle& h, int level) const;
    Result<std::unique_ptr<Handle>> checkout(const jobs::CancelToken* cancel) const;
    void giveBack(std::unique_ptr<Handle> h) const;

    uint64_t sourcePixelsAt(uint32_t level, int tileSize) const;
    int overviewFor(double srcPixelsPerTilePixel) const;
    Result<WarpOp*> warpOp(Handle& h, Level& level, int size) const;
    Result<bool> warp(const GeoExtent& extent, int size, bool cornerAligned, const jobs::CancelToken* cancel,
                      void* bandsOut, uint8_t* alphaOut) const;
    // warp's steps.
    /// Where the tile (destination geotransform `gt`, size x size pixels) lies in full-resolution
    /// source pixels: a grid over it, exactly transformed. Nothing when no point of it maps.
    std::optional<raster_detail::PixelBox> tileInSource(Handle& h, const double gt[6], int size) const;
    /// True (and logged) when reading `clipped` at overview `level` is over the per-tile budget.
    bool overTileBudget(const raster_detail::PixelBox& clipped, int level, const GeoExtent& extent) const;
    /// Warps at overview `level` (0: full resolution) into the outputs; see warp().
    Result<bool> warpLevel(Handle& h, int level, const double gt[6], int size, const GeoExtent& extent,
                           const jobs::CancelToken* cancel, void* bandsOut, uint8_t* alphaOut) const;
};

}  // namespace orbis::globe
